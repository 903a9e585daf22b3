"""The compensated command as an NC program: one G1 block per interpolator period."""

from __future__ import annotations

import numpy as np

from ..path.gcode_words import ZERO_MOVE_M


def dense_program(command, title: str = "compensated command", settle_s: float = 0.0) -> str:
    """G-code text: absolute G1 moves in mm, one per sample, each at the feed that covers
    its step in one period, in continuous-path mode (G64: under G61 each block would
    come to rest); a sample that rounds to within :data:`~tcpmm.path.gcode_words.ZERO_MOVE_M`
    on every axis of where the tool was last sent is a dwell of one period (a reader skips
    such a G1 as a move of zero length, as controllers do, and the program would lose that
    period; a step of the last written digit, 1 nm, is one) [-].

    Parameters
    ----------
    command : Command
        The command to write [m].
    title : str
        Comment at the head of the program [-].
    settle_s : float
        Dwell after the rapid to the first sample: the compensated command starts from
        rest there, and a machine still settling from the rapid starts off its path [s].

    The samples of the program's G0 rapids (``command.blocks()``) are G1 blocks too, at
    the speed the command was planned to: a controller's own rapid would run them at its
    rapid speed and the program would no longer keep the compensated command's timing.
    A comment under the title says so, with the lines they are (:func:`rapid_note`).
    """
    axes = [a for a in command.axes if a in ("X", "Y", "Z")]
    # rounded as written, and -0 made 0: "-0.000000" and "0.000000" are one place
    pos = np.round(np.array([command.positions[a] for a in axes]) * 1e3, 6) + 0.0  # mm
    step = np.linalg.norm(np.diff(pos, axis=1), axis=0)
    feed = step / command.period_s * 60.0  # mm/min
    words = [" ".join(f"{a}{p:.6f}" for a, p in zip(axes, pos[:, k], strict=True))
             for k in range(pos.shape[1])]
    lines = [f"({title}: {pos.shape[1]} samples at {command.period_s:g} s)",
             "G90 G17 G21 G64", f"G0 {words[0]}"]
    if settle_s > 0:
        lines.append(f"G4 P{settle_s:g}")
    # the reader's test on the text's millimetres, with room for their conversion to m
    near, last = ZERO_MOVE_M * 1e3 * (1 + 1e-6), pos[:, 0]
    moved = np.zeros(pos.shape[1], dtype=bool)
    for k in range(1, pos.shape[1]):
        if np.max(np.abs(pos[:, k] - last)) <= near:
            lines.append(f"G4 P{command.period_s:g}")
        else:
            lines.append(f"G1 {words[k]} F{feed[k - 1]:.4f}")
            last, moved[k] = pos[:, k], True
    # the note goes under the title: the second sample's line is one further down
    note = rapid_note(command, moved, len(lines) - pos.shape[1] + 3)
    lines[1:1] = [note] if note else []
    lines.append("M30")
    return "\n".join(lines) + "\n"


#: The most runs of rapid lines :func:`rapid_note` lists one by one [-].
NOTE_RUNS = 12


def rapid_note(command, moved, first_line: int) -> str:
    """A comment saying which lines of the dense program are the program's G0 rapids,
    written as G1 at the planned speed; empty where the command has no rapid after its
    first sample (which the program's own G0 reaches) or no blocks (a command file) [-].

    Parameters
    ----------
    command : Command
        The command written, one line per sample [m].
    moved : ndarray of bool
        Per sample: written as a G1, not as a dwell (the hold after a program that ends
        on a rapid is no rapid written as G1) [-].
    first_line : int
        The line of the second sample in the program, 1 for the first line [-].
    """
    blocks = command.blocks()
    if blocks is None:
        return ""
    rapid = np.asarray(blocks[1][1:], dtype=bool) & moved[1:]
    edges = np.flatnonzero(np.diff(np.concatenate([[0], rapid.astype(int), [0]])))
    runs = [(first_line + a, first_line + b - 1) for a, b in zip(edges[::2], edges[1::2],
                                                                 strict=True)]
    if not runs:
        return ""
    shown = ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs[:NOTE_RUNS])
    more = f" and {len(runs) - NOTE_RUNS} runs more" if len(runs) > NOTE_RUNS else ""
    return (f"(the program's G0 rapids are written as G1 at the speed the command was planned "
            f"to, so that it keeps the command's timing: lines {shown}{more})")


#: How far the dense program's command, as a controller set as the model's interpolator
#: plans it, may lie from the command it is written from, at any sample, before it is
#: said: below the servo's bandwidth the TCP follows a departure of its command about one
#: to one, so a figure after can move by as much; 1 µm keeps that below the draws' spread
#: of the figures (several µm on the benches' circles) and well above the program's
#: rounding (1 nm coordinates, F to 4 decimals) [m].
REPLAY_TOL_M = 1e-6


def replay_departure(command, text: str, settings, settle_s: float) -> dict | None:
    """The dense program planned again with the interpolator, compared with the command it
    was written from sample by sample at the command's clock (its start where the rapid
    and the settling dwell end, the interpolator's filter delay taken in); ``None`` for a
    program that only dwells [-].

    Parameters
    ----------
    command : Command
        The command the program was written from [m].
    text : str
        The program (:func:`dense_program`) [-].
    settings : InterpolatorSettings
        The controller's interpolator [-].
    settle_s : float
        The dwell after the rapid to the start, 0 for none [s].

    Returns
    -------
    dict
        ``departure_m`` (largest distance over the command's axes) with ``axes_m`` (each
        axis's largest), ``at_s`` (the command's time of the largest), ``line`` (the
        program's line written for that sample), ``share_beyond`` (of the samples more than
        ``tolerance_m`` apart), ``duration_s`` and ``command_duration_s`` (the program's
        motion after the rapid and dwell, and the command's) [m], [s], [-].
    """
    from ..path.program import program_to_interpolation

    if "\nG1 " not in text:
        return None
    run = program_to_interpolation(text, settings)
    lines = text.splitlines()
    head, k0 = _start(run, lines, settle_s)
    T = command.period_s
    axes = [a for a in command.axes if a in ("X", "Y", "Z")]
    want = np.array([command.positions[a] for a in axes])
    got = np.array([run.command.positions[a] for a in axes])[:, k0:]
    n = max(want.shape[1], got.shape[1])
    diff = _held(got, n) - _held(want, n)
    dist = np.sqrt(np.sum(diff**2, axis=0))
    k = int(np.argmax(dist))
    return {"departure_m": float(dist[k]),
            "axes_m": {a: float(np.max(np.abs(d))) for a, d in zip(axes, diff, strict=True)},
            "at_s": float(command.time_s[0] + k * T),
            "line": head + min(k, len(lines) - head - 1) if k else head - (settle_s > 0),
            "share_beyond": float(np.mean(dist > REPLAY_TOL_M)),
            "tolerance_m": REPLAY_TOL_M,
            "duration_s": float(run.command.time_s[-1] - k0 * T),
            "command_duration_s": float(command.time_s[-1] - command.time_s[0])}


def _start(run, lines: list, settle_s: float) -> tuple[int, int]:
    """The line that ends the rapid to the start and its settling dwell (1 for the first),
    and the sample of the planned command where the command written starts: where the
    segment after them starts, delayed by the interpolator's filter [-]."""
    g0 = next(k for k, ln in enumerate(lines) if ln.startswith("G0 "))
    head = g0 + 1 + (settle_s > 0)
    after = np.flatnonzero(run.path.line > head)
    start_s = run.segment_start_s[after[0]] if after.size else run.segment_end_s[-1]
    return head, round((start_s + run.filter.delay_s) / run.command.period_s)


def _held(pos, n: int):
    """``pos`` (axes by samples) held at its last sample to ``n`` samples [-]."""
    return np.concatenate([pos, np.repeat(pos[:, -1:], n - pos.shape[1], axis=1)], axis=1)
