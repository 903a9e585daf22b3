"""The interpolator: tool path segments to the sampled position command.

Steps: segment and corner speed limits, look-ahead (backward and forward pass),
accelerate-cruise-decelerate profile per segment, sampling at the interpolation
period with points evaluated exactly on the programmed geometry, and the per-axis
post-interpolation acc/dec filter.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _compiled as ck  # the look-ahead, profiles and sampling, compiled
from ..errors import InputError
from .blend import blended_path
from .blocktrack import BlockTrack
from .command import Command
from .filters import FilterShape, apply_filter, filter_shape
from .geometry import ARC, DWELL, PathArrays, evaluate, to_arrays
from .segments import AXES, Dwell
from .settings import InterpolatorSettings
from .speedlimits import path_limits

#: longest command the interpolator makes (about 2.8 h at 1 ms) [-]
MAX_SAMPLES = 10_000_000


@dataclass
class Interpolation:
    """Everything the interpolator computed, for callers that need more than the command.

    Parameters
    ----------
    command : Command
        The position command (filtered if a filter is set) [-].
    path : PathArrays
        The path as arrays [-].
    junction_speed_m_per_s : ndarray
        Speed at the start of each segment and at the end of the path [m/s].
    segment_vmax_m_per_s : ndarray
        Speed limit of each segment [m/s].
    segment_start_s, segment_end_s : ndarray
        When each segment starts and ends, before the filter [s].
    filter : FilterShape
        The post-interpolation filter [-].
    segment_cause : ndarray of int
        What sets each segment's speed limit (``speedlimits.SEGMENT_CAUSES``) [-].
    junction_limit_m_per_s : ndarray
        Speed limit of each junction before the look-ahead [m/s].
    junction_cause : ndarray of int
        What sets it (``speedlimits.JUNCTION_CAUSES``) [-].
    segment_peak_m_per_s : ndarray
        Highest speed each segment reaches [m/s].
    jerk_limited : bool
        Whether the feed profile is jerk-limited (S-curve) [-].
    """

    command: Command
    path: PathArrays
    junction_speed_m_per_s: np.ndarray
    segment_vmax_m_per_s: np.ndarray
    segment_start_s: np.ndarray
    segment_end_s: np.ndarray
    filter: FilterShape
    segment_cause: np.ndarray | None = None
    junction_limit_m_per_s: np.ndarray | None = None
    junction_cause: np.ndarray | None = None
    segment_peak_m_per_s: np.ndarray | None = None
    jerk_limited: bool = False

    def sample_range(self, i: int) -> tuple[int, int]:
        """Samples ``[first, stop)`` of the filtered command that belong to segment ``i``.

        The unfiltered range shifted by the filter's group delay, rounded [-].
        """
        dt = self.command.period_s
        shift = self.filter.delay_s
        first = int(np.ceil((self.segment_start_s[i] + shift) / dt - 1e-9))
        stop = int(np.floor((self.segment_end_s[i] + shift) / dt + 1e-9)) + 1
        return first, stop


def used_axes(p: PathArrays) -> list[int]:
    used = {0, 1}
    if p.n:
        moved = np.any(np.abs(p.end - p.start) > 0.0, axis=0)
        used |= {i for i in range(3) if moved[i]}
        arc = p.kind == ARC
        # a set of the plain lists: np.unique would import numpy.ma (8 ms of a command)
        used |= set(p.ia[arc].tolist()) | set(p.ib[arc].tolist())
    return sorted(used)


def check_samples(dur, dt: float, line, n_samples: int | None = None,
                  streamed: bool = False) -> None:
    """Refuse a command of more than :data:`MAX_SAMPLES` samples, naming the line of the
    longest segment.

    Parameters
    ----------
    dur : ndarray
        Duration of each segment [s].
    dt : float
        Interpolation period [s].
    line : ndarray of int
        Source line of each segment, -1 where unknown [-].
    n_samples : int, optional
        The command's samples; by default the segments' durations over the period [-].
    streamed : bool
        Whether these are the segments of one chunk of a program streamed: they are then
        too long alone, and streaming is no remedy [-].
    """
    total = float(np.sum(dur)) / dt if n_samples is None else float(n_samples)
    if total <= MAX_SAMPLES:  # not NaN either
        return
    i = int(np.argmax(np.where(np.isnan(dur), np.inf, dur)))
    # a stream plans a block whole: one block too long alone is refused there too
    remedy = ("" if streamed or not dur[i] / dt <= MAX_SAMPLES else
              ", and for a program this long, stream it: tcpmm simulate ... -o RUN.parquet, "
              "tcpmm path --chunk-blocks N")
    whole = "a chunk of blocks streamed" if streamed else "a command made whole"
    raise InputError(
        f"the command would last {total * dt:.4g} s ({total:.4g} samples), more than "
        f"the limit of {MAX_SAMPLES} samples of {whole}; the longest segment takes "
        f"{dur[i]:.4g} s: check its feed rate and coordinates{remedy}",
        line=None if line[i] < 0 else int(line[i]),
    )


def _starting_path(segments, start_position_m) -> list:
    """The segments to interpolate, checked against where the axes stand.

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell
        The continuous tool path [-].
    start_position_m : sequence of float or None
        Where the axes stand before the first segment (X, Y, Z) [m].

    Returns
    -------
    list
        The segments; a zero dwell at the start position when the path is empty and a
        start position is given [-].
    """
    segments = list(segments)
    if start_position_m is not None:
        start = tuple(float(c) for c in start_position_m)
        if len(start) != 3:
            raise InputError("start_position_m must have three coordinates (X, Y, Z) in m")
        if segments and np.linalg.norm(np.subtract(segments[0].start_m, start)) > 1e-9:
            raise InputError(
                f"the path starts at {tuple(segments[0].start_m)} m but the axes stand at "
                f"{start} m; start the path where the axes are"
            )
        if not segments:
            segments = [Dwell(start, 0.0)]
    if not segments:
        raise InputError("the path is empty: give at least one motion or dwell")
    return segments


def settings_meta(settings: InterpolatorSettings, filt: FilterShape | None = None) -> dict:
    """What a command's meta data says of the interpolator that made it: its period,
    profile and filter, and the filter's delay [s], [-].

    Parameters
    ----------
    settings : InterpolatorSettings
        The interpolator's settings [-].
    filt : FilterShape, optional
        Its filter, when made already [-].
    """
    filt = filt or filter_shape(settings.filter_kind, settings.filter_time_s,
                                settings.period_s, settings.corner_tolerance_m)
    return {"source": "interpolator", "period_s": settings.period_s,
            "profile": settings.profile, "filter_kind": settings.filter_kind,
            "filter_time_s": settings.filter_time_s, "filter_delay_s": filt.delay_s}


def _command(p: PathArrays, settings: InterpolatorSettings, filt: FilterShape, seg, s,
             seg_start, dur, n_samples: int) -> Command:
    """The filtered position command of the sampled path, with its meta data.

    Parameters
    ----------
    p : PathArrays
        The path as arrays [-].
    settings : InterpolatorSettings
        Interpolator settings [-].
    filt : FilterShape
        The post-interpolation filter [-].
    seg, s : ndarray
        Segment index [-] and distance along it [m] of each sample before the filter.
    seg_start, dur : ndarray
        When each segment starts [s] and how long it lasts [s].
    n_samples : int
        Samples before the filter [-].

    Returns
    -------
    Command
        Positions of the used axes after the filter [m]; of a program's path,
        ``meta["nc_line"]`` and ``meta["rapid"]`` per sample
        (:class:`~tcpmm.path.blocktrack.BlockTrack`) [-].
    """
    dt = settings.period_s
    pos = evaluate(p, seg, s)
    cum = np.concatenate([[0.0], np.cumsum(p.length)])
    path_s = cum[seg] + s
    positions = {AXES[a]: apply_filter(pos[:, a], filt) for a in used_axes(p)}
    n_out = next(iter(positions.values())).size
    time_s = np.arange(n_out) * dt
    meta = {
        **settings_meta(settings, filt),
        "path_s_m": np.concatenate([path_s, np.full(n_out - n_samples, path_s[-1])]),
        "path_length_m": float(cum[-1]),
        "segment_line": p.line.copy(),
        "segment_start_s": seg_start,
        "segment_end_s": seg_start + dur,
    }
    if (p.line >= 0).any():  # a program's: which block each sample is in
        meta["nc_line"], meta["rapid"] = BlockTrack(filt.kernel.size).push(p, seg, True)
    return Command(time_s=time_s, positions=positions, meta=meta)


def interpolate_detailed(
    segments, settings: InterpolatorSettings | None = None, start_position_m=None
) -> Interpolation:
    """Interpolate a tool path and keep the intermediate results.

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell
        The continuous tool path [-].
    settings : InterpolatorSettings, optional
        Interpolator settings; defaults when omitted [-].
    start_position_m : sequence of float, optional
        Where the axes stand before the first segment (X, Y, Z); must be the start of
        the first segment, and is where an empty path rests [m].

    Returns
    -------
    Interpolation
        The command and the look-ahead results; where corners are blended (``G64 P``,
        ``blend_tolerance_m``) its per-segment arrays describe the blended path, a blend arc
        after each such corner [-].
    """
    settings = settings or InterpolatorSettings()
    dt = settings.period_s
    segments = blended_path(_starting_path(segments, start_position_m),
                            settings.blend_tolerance_m)
    p = to_arrays(segments, settings.rapid())
    filt = filter_shape(settings.filter_kind, settings.filter_time_s, dt,
                        settings.corner_tolerance_m)
    vmax, acc, seg_cause, vj, junction_cause, _ = path_limits(p, settings, filt)
    v = ck.lookahead(p.length, vj, acc, settings.jerk())
    prof = ck.segment_profiles(p.length, v, vmax, acc, settings.jerk())
    durations = prof[:, 1] + prof[:, 4] + prof[:, 5]
    # before the compiled timeline counts the periods in 64-bit integers, which a feed of
    # 1e-21 mm/min overflowed into a command of two samples
    check_samples(np.where(p.kind == DWELL, p.dwell_s, durations), dt, p.line)
    settle = filt.kernel.size - 1
    k0, off, dur, k_end = ck.timeline(p.kind, durations, v, p.dwell_s, dt, settle)
    n_samples = max(int(k_end) + 1, 2)
    check_samples(dur, dt, p.line, n_samples)
    seg, s = ck.sample(k0, off, dur, p.length, v, prof, n_samples, dt)
    seg_start = k0 * dt + off
    return Interpolation(
        command=_command(p, settings, filt, seg, s, seg_start, dur, n_samples),
        path=p,
        junction_speed_m_per_s=v,
        segment_vmax_m_per_s=vmax,
        segment_start_s=seg_start,
        segment_end_s=seg_start + dur,
        filter=filt,
        segment_cause=seg_cause,
        junction_limit_m_per_s=vj,
        junction_cause=junction_cause,
        segment_peak_m_per_s=prof[:, 0].copy(),
        jerk_limited=settings.profile == "scurve",
    )


def interpolate(
    segments, settings: InterpolatorSettings | None = None, start_position_m=None
) -> Command:
    """Interpolate a tool path into the sampled position command.

    Parameters
    ----------
    segments : sequence of Line, Rapid, Arc, Dwell
        The continuous tool path, SI [-].
    settings : InterpolatorSettings, optional
        Interpolator settings; defaults when omitted [-].
    start_position_m : sequence of float, optional
        Where the axes stand before the first segment (X, Y, Z); must be the start of
        the first segment [m].

    Returns
    -------
    Command
        Positions of X and Y (and Z when the path uses it), uniformly sampled from rest
        to rest, extended by the filter length [m]. ``meta`` holds ``path_s_m`` (distance
        along the path per sample, before the filter) and the segment times.
    """
    return interpolate_detailed(segments, settings, start_position_m).command
