"""Frequency-response measurements saved by Sinumerik Operate (Setup/Optimize) as XML.

The file holds one ``PlatformSignalNode`` per measured signal, each with

* its time series (one per run, e.g. per direction of travel): ``TimeSeries`` with a
  base-85 ``m_ValueVector`` and ``m_TimeVector.start``/``.end``/``.length`` [s];
* its averaged auto-spectrum (``m_autospectrumInfo``) and cross-spectra with other nodes
  (``m_crossSpecInfoList``; ``m_uSignodeId`` names the other node): complex
  ``m_ValueVector`` on ``m_FrequencyVector`` [Hz]. The cross-spectrum stored with node A
  for node B is ``S_AB = E[conj(X_A) X_B]``.

``PrimaryFreqRespSigNodeData`` names the input and output nodes of the frequency response
by their ``m_iUniqueInstanceId``. The response is ``H = S_io / S_ii`` and the coherence
``|S_io|^2 / (S_ii S_oo)``; bins at 0 Hz or without input power are left out. Without
stored spectra, they are formed from the time series the same way: the discrete Fourier
transform of each run, averaged over the runs.

Signals are in the SI unit of the measured quantity (for a speed-loop measurement,
``m_eControlLoopType`` 2, motor speed in rad/s); the frequency response is their ratio.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..frfdata import FRF, coherence_rel_std
from .csvutil import warn_input
from .sinumerik_b85 import decode_doubles
from .text import existing_file

__all__ = ["SinumerikTrace", "TimeTrace", "read_sinumerik", "read_sinumerik_frf"]

#: Control loops by ``m_eControlLoopType``: name and unit of the measured signals.
LOOPS = {2: ("speed", "rad/s")}
_FIX = "export the measurement again from Sinumerik Operate (Setup/Optimize, save as XML)"


@dataclass(frozen=True)
class TimeTrace:
    """The time series of one measured signal.

    Parameters
    ----------
    name : str
        Signal name, ``"node <id>"`` [-].
    time_s : ndarray
        Sample times of each run, shape ``(n,)`` [s].
    values : ndarray
        Samples, shape ``(runs, n)`` [unit].
    unit : str
        Unit of the samples, "" if the file does not say [-].
    """

    name: str
    time_s: np.ndarray
    values: np.ndarray
    unit: str = ""


@dataclass(frozen=True)
class SinumerikTrace:
    """A Sinumerik Operate frequency-response measurement.

    Parameters
    ----------
    frf : FRF
        Output per input of the primary frequency response [unit/unit].
    traces : dict of str to TimeTrace
        Time series per signal, keyed by name (input first) [-].
    meta : dict
        Loop, axis, sample time [s], date, number of averages, node ids [-].
    """

    frf: FRF
    traces: dict[str, TimeTrace]
    meta: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """Summary: band [Hz], bins, coherence range [-], signals and the file's facts."""
        f = self.frf.freq_hz
        return {
            "name": self.frf.name,
            "input": self.frf.input,
            "output": self.frf.output,
            "bins": int(f.size),
            "freq_min_hz": float(f[0]),
            "freq_max_hz": float(f[-1]),
            "coherence_min": float(np.min(self.frf.coherence)),
            "coherence_median": float(np.median(self.frf.coherence)),
            "traces": {k: {"runs": int(t.values.shape[0]), "samples": int(t.time_s.size),
                           "unit": t.unit} for k, t in self.traces.items()},
            **self.meta,
        }

    def to_pandas(self):
        """The frequency response, one row per bin (see :meth:`FRF.to_pandas`)."""
        return self.frf.to_pandas()

    def plot(self, ax=None, path=None):
        """Bode plot of the response with its coherence; see :func:`tcpmm.plot.frf.plot_frf`."""
        from ..plot.frf import plot_frf  # tcpmm.plot is a floor above this one

        return plot_frf(self.frf, path=path, ax=ax)


def read_sinumerik_frf(path) -> FRF:
    """The primary frequency response of a Sinumerik Operate XML file.

    Parameters
    ----------
    path : str or Path
        The XML file [-].

    Returns
    -------
    FRF
        Output per input, with coherence [unit/unit].
    """
    return read_sinumerik(path).frf


def read_sinumerik(path) -> SinumerikTrace:
    """Read a Sinumerik Operate frequency-response measurement (XML).

    Parameters
    ----------
    path : str or Path
        The XML file [-].

    Returns
    -------
    SinumerikTrace
        Frequency response, time series and measurement facts [-].
    """
    path = existing_file(path, "Sinumerik XML file")
    root = _parse(path)
    loop = _int(root, "m_eControlLoopType", path=path, optional=True)
    loop_name, unit = LOOPS.get(loop, ("", ""))
    nodes = _nodes(root, path)
    i_in, i_out = _primary(root, nodes, path)
    node_in, node_out = nodes[i_in], nodes[i_out]
    traces = {n["name"]: _traces(n, unit, path) for n in (node_in, node_out)}
    traces = {k: v for k, v in traces.items() if v is not None}
    f, s_ii, s_oo, s_io, n_avg = _spectra(node_in, node_out, traces, path)
    keep = (f > 0) & np.isfinite(s_ii) & (s_ii > 0) & np.isfinite(s_io)
    if not np.any(keep):
        raise InputError("the spectra hold no bin above 0 Hz with input power; " + _FIX,
                         file=path)
    f, s_ii, s_oo, s_io = f[keep], s_ii[keep], s_oo[keep], s_io[keep]
    if np.any(np.diff(f) <= 0):
        raise InputError("m_FrequencyVector is not increasing; " + _FIX, file=path)
    with np.errstate(divide="ignore", invalid="ignore"):
        coh = np.nan_to_num(np.clip(np.abs(s_io) ** 2 / (s_ii * s_oo), 0.0, 1.0))
    name = f"{loop_name} loop" if loop_name else "response"
    frf = FRF(freq_hz=f, H=s_io / s_ii, coherence=coh, n_averages=float(n_avg),
              rel_std=coherence_rel_std(coh, float(n_avg)), name=name, input=node_in["name"],
              output=node_out["name"], meta={"unit": "-" if unit else "", "file": str(path)})
    dt = _float(root, "m_dProcessUpdateTime", path=path, optional=True)
    meta = {"file": str(path), "control_loop": loop_name or f"type {loop}",
            "signal_unit": unit, "axis": _int(root, "m_uAxis", path=path, optional=True),
            "sample_time_s": dt, "date": _text(root.find("SatTimeStamp/unsigned_int")),
            "input_node": node_in["id"], "output_node": node_out["id"], "averages": n_avg}
    return SinumerikTrace(frf=frf, traces=traces, meta=meta)


# ----------------------------------------------------------------------------- XML helpers


def _parse(path: Path) -> ET.Element:
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        line, col = exc.position
        raise InputError(f"not well-formed XML ({exc.msg if hasattr(exc, 'msg') else exc}); "
                         + _FIX, file=path, line=line, column=col + 1) from None
    except OSError as exc:
        raise InputError(f"cannot read the file: {exc.strerror}", file=path) from None
    if root.find("LinkedList[@name='m_MeasurementSignalNodeList']") is None:
        raise InputError(f"<{root.tag}> holds no m_MeasurementSignalNodeList: not a "
                         "frequency-response measurement of Sinumerik Operate", file=path)
    return root


def _text(e) -> str | None:
    return None if e is None or e.text is None else e.text.strip()


def _child(e: ET.Element, name: str):
    return next((c for c in e if c.get("name") == name), None)


def _float(e: ET.Element, name: str, where: str = "", path=None, default=None,
           optional: bool = False):
    """The number in ``e``'s child ``name``; missing, ``default`` where one is given or the
    child is ``optional``, else an error naming ``path`` [-]."""
    c = _child(e, name)
    tag = f"<{where}/{name}>" if where else f"<{name}>"
    if c is None:
        if optional or default is not None or path is None:
            return default
        raise InputError(f"element <{where}> lacks <{name}>; " + _FIX, file=path)
    try:
        return float(_text(c))
    except (TypeError, ValueError):
        text = _text(c) or ""
        # a comma for the point is a locale's setting, not damage to the file
        why = ("a decimal comma: write '.'" if re.fullmatch(r"[-+]?\d*,\d+([eE][-+]?\d+)?",
                                                            text) else "not a number; " + _FIX)
        raise InputError(f"element {tag} holds {text!r}, {why}", file=path,
                         line=_line(path, name, c.text)) from None


def _line(path, name: str, text) -> int | None:
    """The line of the element ``name="name"`` holding ``text`` (ElementTree keeps no line
    numbers) [-]."""
    if path is None or text is None:
        return None
    data = Path(path).read_bytes()
    m = re.search(rb'name="' + re.escape(name.encode()) + rb'"[^>]*>' + re.escape(
        text.encode("latin-1", "replace")), data)
    return None if m is None else data.count(b"\n", 0, m.start()) + 1


def _int(e: ET.Element, name: str, where: str = "", path=None, default=None,
         optional: bool = False):
    v = _float(e, name, where, path, default, optional)
    return None if v is None else int(v)


def _array(na: ET.Element, where: str, path) -> np.ndarray:
    """The values of a ``NumericArray``: real, or complex when its elementtype says so."""
    n = _int(na, "m_length", where, path)
    raw = na.find("raw")
    if raw is None:
        raise InputError(f"element <{where}> lacks <raw>; " + _FIX, file=path)
    v = decode_doubles(raw.text or "", f"{where}/raw", path)
    cplx = na.get("elementtype") == "ComplexNumber"
    if v.size != (2 * n if cplx else n):
        raise InputError(f"element <{where}> declares m_length {n} but holds "
                         f"{v.size // 2 if cplx else v.size} values: the data are truncated; "
                         + _FIX, file=path)
    if not np.all(np.isfinite(v)):
        raise InputError(f"element <{where}> holds values that are not finite; " + _FIX,
                         file=path)
    return v[0::2] + 1j * v[1::2] if cplx else v


# ----------------------------------------------------------------------------- nodes


def _nodes(root: ET.Element, path) -> list[dict]:
    nodes = []
    for e in root.find("LinkedList[@name='m_MeasurementSignalNodeList']"):
        nid = _int(e, "m_uNodeId", "PlatformSignalNode", path)
        nodes.append({"id": nid, "name": f"node {nid}", "element": e,
                      "instance": _int(e, "m_iUniqueInstanceId", path=path, default=len(nodes))})
    if len(nodes) < 2:
        raise InputError(f"m_MeasurementSignalNodeList holds {len(nodes)} signal(s); a "
                         "frequency response needs an input and an output", file=path)
    return nodes


def _primary(root, nodes, path) -> tuple[int, int]:
    e = root.find(".//PrimaryFreqRespSigNodeData")
    if e is None:
        raise InputError("no PrimaryFreqRespSigNodeData names the input and output signals; "
                         + _FIX, file=path)
    where = "PrimaryFreqRespSigNodeData"
    ids = [_int(e, f"m_i{k}SigNodeUniqueInstanceID", where, path) for k in ("Input", "Output")]
    inst = [n["instance"] for n in nodes]
    for k, i in zip(("input", "output"), ids, strict=True):
        if i not in inst:
            raise InputError(f"element <{where}> names {k} instance {i}, but the signal "
                             f"nodes are {inst}; " + _FIX, file=path)
    return inst.index(ids[0]), inst.index(ids[1])


def _traces(node: dict, unit: str, path) -> TimeTrace | None:
    where = f"{node['name']}/TimeSeries"
    runs, time = [], None
    for ts in node["element"].iter("TimeSeries"):
        na = ts.find("NumericArray")
        if na is None:
            raise InputError(f"element <{where}> lacks its NumericArray; " + _FIX, file=path)
        v = _array(na, f"{where}/m_ValueVector", path)
        t0 = _float(ts, "m_TimeVector.start", where, path)
        t1 = _float(ts, "m_TimeVector.end", where, path)
        n = _int(ts, "m_TimeVector.length", where, path)
        if n != v.size or not t1 > t0:
            raise InputError(f"element <{where}>: time vector {t0:g}..{t1:g} s with {n} "
                             f"samples does not fit {v.size} values; " + _FIX, file=path)
        t = np.linspace(t0, t1, n)
        if time is not None and (time.size != n or not np.allclose(time, t)):
            raise InputError(f"element <{where}>: the runs have different time vectors; "
                             + _FIX, file=path)
        runs.append(v)
        time = t
    if not runs:
        return None
    return TimeTrace(name=node["name"], time_s=time, values=np.vstack(runs), unit=unit)


def _spectrum(info: ET.Element, where: str, path) -> tuple[np.ndarray, np.ndarray, int]:
    cs = info.find("CrossSpectrum")
    if cs is None:
        raise InputError(f"element <{where}> lacks its CrossSpectrum; " + _FIX, file=path)
    arrays = {na.get("name"): na for na in cs.findall("NumericArray")}
    for k in ("m_ValueVector", "m_FrequencyVector"):
        if k not in arrays:
            raise InputError(f"element <{where}> lacks <{k}>; " + _FIX, file=path)
    s = _array(arrays["m_ValueVector"], f"{where}/m_ValueVector", path)
    f = _array(arrays["m_FrequencyVector"], f"{where}/m_FrequencyVector", path).real
    if f.size != s.size:
        raise InputError(f"element <{where}>: {f.size} frequencies for {s.size} values; "
                         + _FIX, file=path)
    return f, s, _int(info, "m_uNumSpectraInAvg", where, path, default=1)


def _spectra(node_in, node_out, traces, path):
    """Frequencies [Hz], S_ii, S_oo, S_io and the number of averages."""
    autos = []
    for n in (node_in, node_out):
        info = _child(n["element"], "m_autospectrumInfo")
        autos.append(None if info is None
                     else _spectrum(info, f"{n['name']}/m_autospectrumInfo", path))
    cross = None
    for a, b, conj in ((node_in, node_out, False), (node_out, node_in, True)):
        for info in a["element"].iter("SigNodeCrossSpectrumInfo"):
            if info.get("name") != "m_autospectrumInfo" and \
                    _int(info, "m_uSignodeId", path=path, optional=True) == b["id"]:
                f, s, n = _spectrum(info, f"{a['name']}/m_crossSpecInfoList", path)
                cross = (f, np.conj(s) if conj else s, n)
    if None not in autos and cross is not None:
        f = cross[0]
        for g, _, _ in autos:
            if g.size != f.size or not np.allclose(g, f):
                raise InputError("the auto- and cross-spectra have different frequency "
                                 "vectors; " + _FIX, file=path)
        f = _bin_frequencies(f, autos[0][1].real, cross[1], traces, path)
        return f, autos[0][1].real, autos[1][1].real, cross[1], cross[2]
    if len(traces) == 2:
        return _from_time(*traces.values(), path)
    raise InputError("the file holds neither the spectra of the input and output signals "
                     "nor their time series; save the measurement with its data "
                     "(frequency spectra or time series)", file=path)


def _bin_frequencies(f, s_ii, s_io, traces, path):
    """The stored frequency vector; or, where the stored spectra are the DFT of the time
    series in the file and the vector places their bins elsewhere, the DFT's own bins
    (k / (N dt)), with a warning: the time base, not the label, says where a bin lies."""
    if len(traces) != 2:
        return f
    g, t_ii, _, t_io, _ = _from_time(*traces.values(), path)
    g, t_ii, t_io = (a[1:] if f[0] > 0 else a for a in (g, t_ii, t_io))
    if g.size < f.size:
        return f
    g, t_ii, t_io = g[:f.size], t_ii[:f.size], t_io[:f.size]
    with np.errstate(divide="ignore", invalid="ignore"):  # scale-free: the response
        h, t_h = s_io / s_ii, t_io / t_ii
    ok = np.isfinite(h) & np.isfinite(t_h) & (f > 0)  # the mean is taken out of the runs
    same = np.count_nonzero(ok) > f.size // 2 and np.allclose(t_h[ok], h[ok], rtol=1e-6)
    if not same or np.allclose(g, f, rtol=1e-9, atol=0.0):
        return f
    n = next(iter(traces.values())).time_s.size
    warn_input(f"the stored frequency vector steps by {f[1] - f[0]:.6g} Hz, but its spectra "
               f"are the DFT of the {n}-sample time series in the file, whose bins step by "
               f"{g[1] - g[0]:.6g} Hz ({100 * (f[-1] / g[-1] - 1):+.3f} % against them): read "
               "at the DFT's bins, where the time base places them", file=path)
    return g


def _from_time(tin: TimeTrace, tout: TimeTrace, path):
    """Spectra of periodic runs: the DFT of each run, averaged over the runs."""
    if tin.values.shape != tout.values.shape:
        raise InputError("the input and output time series differ in shape "
                         f"{tin.values.shape} vs {tout.values.shape}; " + _FIX, file=path)
    n = tin.time_s.size
    dt = (tin.time_s[-1] - tin.time_s[0]) / (n - 1)
    x = np.fft.rfft(tin.values - tin.values.mean(axis=1, keepdims=True), axis=1)
    y = np.fft.rfft(tout.values - tout.values.mean(axis=1, keepdims=True), axis=1)
    f = np.fft.rfftfreq(n, dt)
    s_ii = np.mean(np.abs(x) ** 2, axis=0)
    s_oo = np.mean(np.abs(y) ** 2, axis=0)
    s_io = np.mean(np.conj(x) * y, axis=0)
    return f, s_ii, s_oo, s_io, tin.values.shape[0]
