"""Frequency-response files: CSV, MATLAB .mat and Sinumerik Operate XML, read into an FRF.

CSV (header names decide, case-insensitive; see ``docs/frf_files.md``):

* frequency: ``freq_hz``, ``frequency_hz``, ``f_hz``, ``frequency``, ``freq``, ``f`` [Hz];
* the response, one of: ``re`` and ``im`` (also ``real``/``imag``); ``magnitude_db`` (also
  ``mag_db``, ``db``) or ``magnitude`` (also ``mag``, ``abs``, linear) with ``phase_deg``
  (also ``phase``, refused where every value lies within +-pi) [deg] or ``phase_rad``
  (refused where it steps by more than 4 pi between neighbouring lines) [rad];
* optional ``coherence`` (also ``coh``) [-];
* optional ``averages`` (also ``n_averages``): the number of averages behind the
  coherence, the same on every row [-].

MATLAB .mat: a frequency vector (same names as CSV) and either a complex vector ``H``
(also ``frf``, ``G``, ``resp``) or ``re`` and ``im``; optional ``coherence`` and
``averages`` (a number).

Without a coherence, bins are taken as well measured (coherence 1). A coherence without
the number of averages is taken as of :data:`AVERAGES` (``meta["averages_assumed"]``);
``read_frf(path, averages=N)`` gives the count.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..frfdata import FRF, coherence_rel_std
from .csvutil import atomic_write_columns, read_header, read_numeric_csv, warn_input
from .matfile import load, mat_array
from .sinumerik import read_sinumerik_frf
from .text import existing_file

__all__ = ["read_frf", "read_frf_csv", "read_frf_mat", "with_averages", "write_frf_csv"]

FREQ = ("freq_hz", "frequency_hz", "f_hz", "frequency", "freq", "f")
RE, IM = ("re", "real"), ("im", "imag")
MAG_DB = ("magnitude_db", "mag_db", "db")
MAG = ("magnitude", "mag", "abs")
PHASE_DEG, PHASE_RAD = ("phase_deg", "phase"), ("phase_rad",)
COH = ("coherence", "coh")
AVG = ("averages", "n_averages")
COMPLEX = ("H", "frf", "G", "resp")
#: Averages assumed when a file gives a coherence but not how many averages made it.
AVERAGES = 10.0


def read_frf(path, averages: float | None = None) -> FRF:
    """Read a frequency response from CSV, MATLAB .mat or Sinumerik Operate XML.

    Parameters
    ----------
    path : str or Path
        The file; its extension (``.csv``, ``.mat``, ``.xml``) says the format [-].
    averages : float, optional
        Number of averages behind the coherence, for a file that does not say it; a file
        that says another is refused [-].

    Returns
    -------
    FRF
        The response [unit].
    """
    path = Path(path)
    ext = path.suffix.lower()
    read = {".csv": read_frf_csv, ".mat": read_frf_mat, ".xml": read_sinumerik_frf}.get(ext)
    if read is not None:
        return with_averages(read(path), averages, path)
    raise InputError(f"unknown FRF file type '{path.suffix}'; use .csv, .mat or a Sinumerik "
                     "Operate .xml", file=path)


def with_averages(frf: FRF, averages: float | None, path=None) -> FRF:
    """``frf`` with ``averages`` behind its coherence where its file did not say how many
    (the same where it did, and the two agree) [-]."""
    if averages is None:
        return frf
    if not (np.isfinite(averages) and averages >= 1):
        raise InputError(f"the number of averages must be >= 1, got {averages:g}", file=path)
    if not frf.meta.get("averages_assumed"):
        if float(averages) != frf.n_averages:
            raise InputError(f"the file says {frf.n_averages:g} averages, not the "
                             f"{averages:g} given; leave out the count", file=path)
        return frf
    meta = {k: v for k, v in frf.meta.items() if k != "averages_assumed"}
    return replace(frf, n_averages=float(averages),
                   rel_std=coherence_rel_std(frf.coherence, float(averages)), meta=meta)


def _pick(names, choices):
    lower = {n.lower(): n for n in names}
    return next((lower[c.lower()] for c in choices if c.lower() in lower), None)


def _named_once(names, groups, path, what="columns", line=1):
    """Refuse two names of one quantity (``groups`` of accepted names): one would be read
    and the other left, whatever it holds [-]."""
    lower = {n.lower(): n for n in names}
    for group in groups:
        both = [lower[c.lower()] for c in group if c.lower() in lower]
        if len(both) > 1:
            raise InputError(f"{what} {' and '.join(both)} name one quantity; keep one",
                             file=path, line=line, column=both[1])


def _columns(names, path):
    """The columns to read: frequency, response kind and its two columns, coherence."""
    _named_once(names, (FREQ, RE, IM, MAG_DB, MAG, PHASE_DEG, PHASE_RAD, COH, AVG), path)
    f = _pick(names, FREQ)
    if f is None:
        raise InputError(f"no frequency column; name it one of {', '.join(FREQ)} [Hz] (the "
                         f"file has {', '.join(names)})", file=path, line=1)
    re_, im_ = _pick(names, RE), _pick(names, IM)
    mag_db, mag = _pick(names, MAG_DB), _pick(names, MAG)
    deg, rad = _pick(names, PHASE_DEG), _pick(names, PHASE_RAD)
    if re_ and im_:
        kind, a, b = "reim", re_, im_
    elif (mag_db or mag) and (deg or rad):
        kind = ("db" if mag_db else "lin") + ("deg" if deg else "rad")
        a, b = mag_db or mag, deg or rad
    else:
        raise InputError("no response columns; give re and im, or magnitude_db (or "
                         "magnitude) with phase_deg (or phase_rad) (the file has "
                         f"{', '.join(names)})", file=path, line=1)
    return f, kind, a, b, _pick(names, COH), _pick(names, AVG)


def _phase_unit_checked(name, phase, path) -> None:
    """Refuse a column named ``phase`` whose every value lies within +-pi: read as
    degrees (its documented unit), a phase in radians turns the response by less than 4
    degrees over the band. Warn of a ``phase_deg`` column that reads so [-]."""
    largest = float(np.max(np.abs(phase)))
    if largest > np.pi * (1 + 1e-9):
        return
    if name.lower() == "phase":
        raise InputError(
            f"every value lies within +-pi (largest |phase| {largest:.4g}): radians, or "
            "degrees of a response that hardly turns? The column name decides: phase_rad "
            "[rad] or phase_deg [deg]", file=path, line=1, column=name)
    span = float(np.ptp(phase))
    if span > 1.0:
        warn_input(f"every value lies within +-pi, spanning {span:.3g}: read as degrees, "
                   "as its name says; if it is in radians, name the column phase_rad",
                   file=path, line=1, column=name)


def _phase_rad_checked(name, phase, path) -> None:
    """Refuse a ``phase_rad`` column that steps by more than two turns between neighbouring
    lines: a phase in radians steps by at most one turn, 2 pi, where it wraps (less where
    it is unwrapped, however far it goes); one in degrees wraps by about 360 [-]."""
    step = np.abs(np.diff(phase))
    big = np.flatnonzero(step > 4 * np.pi)
    if not big.size:
        return
    i = int(np.argmax(step))
    raise InputError(
        f"the phase steps by more than 4 pi between neighbouring lines {big.size} times, by "
        f"up to {step[i]:.4g} (from {phase[i]:.6g} on line {i + 2} to {phase[i + 1]:.6g}; "
        f"largest |phase| {float(np.max(np.abs(phase))):.4g}), where radians step by 2 pi "
        "at most, as they wrap: degrees, which wrap by 360? Name the column phase_deg",
        file=path, line=i + 3, column=name)


def _complex(kind, a, b):
    if kind == "reim":
        return a + 1j * b
    mag = 10.0 ** (a / 20.0) if kind.startswith("db") else a
    ph = np.radians(b) if kind.endswith("deg") else b
    return mag * np.exp(1j * ph)


def read_frf_csv(path) -> FRF:
    """Read a frequency response from a CSV file (columns: see the module).

    Parameters
    ----------
    path : str or Path
        CSV file with a header line [-].

    Returns
    -------
    FRF
        The response [unit].
    """
    path = Path(path)
    names = read_header(path)
    f_col, kind, a, b, coh_col, avg_col = _columns(names, path)
    response = {_pick(names, c) for c in (RE, IM, MAG_DB, MAG, PHASE_DEG, PHASE_RAD)} - {None}
    cols = read_numeric_csv(path, [f_col, a, b], [c for c in (coh_col, avg_col) if c],
                            {c: f"the response is read from {a} and {b}"
                             for c in response - {a, b}})
    f = cols[f_col]
    bad = np.flatnonzero(f <= 0)
    if bad.size:
        raise InputError(f"frequency {f[bad[0]]:g} Hz is not > 0; leave out the 0 Hz row",
                         file=path, line=int(bad[0]) + 2, column=f_col)
    bad = np.flatnonzero(np.diff(f) <= 0)
    if bad.size:
        raise InputError("frequencies must increase from row to row", file=path,
                         line=int(bad[0]) + 3, column=f_col)
    if kind.startswith("lin"):
        bad = np.flatnonzero(cols[a] < 0)
        if bad.size:
            raise InputError("a linear magnitude cannot be negative (is it in dB? name the "
                             "column magnitude_db)", file=path, line=int(bad[0]) + 2, column=a)
    if kind.endswith("deg"):
        _phase_unit_checked(b, cols[b], path)
    elif kind.endswith("rad"):
        _phase_rad_checked(b, cols[b], path)
    coh = _coherence(cols.get(coh_col), f.size, path, coh_col)
    return _frf(f, _complex(kind, cols[a], cols[b]), coh, path, coh_col not in cols,
                _averages(cols.get(avg_col), path, avg_col))


def _averages(n, path, name, rows: bool = True) -> float | None:
    """The one number of averages of a column (``rows``) or variable, or None without
    one [-]."""
    if n is None:
        return None
    bad = np.flatnonzero((n != n[0]) | (n < 1))
    if bad.size:
        raise InputError(f"averages {n[bad[0]]:g}: give one count >= 1"
                         + (", the same on every row" if rows else ""), file=path,
                         line=int(bad[0]) + 2 if rows else None, column=name)
    return float(n[0])


def _coherence(coh, n, path, name):
    if coh is None:
        return np.ones(n)
    bad = np.flatnonzero((coh < 0) | (coh > 1))
    if bad.size:
        raise InputError(f"coherence {coh[bad[0]]:g} is outside 0..1", file=path,
                         line=int(bad[0]) + 2, column=name)
    return coh


def _frf(f, H, coh, path, assumed: bool = False, averages: float | None = None) -> FRF:
    """The FRF of a file; ``assumed``: the file gives no coherence, and every bin is taken
    as well measured (``meta["coherence_assumed"]``); without ``averages``, the coherence
    is taken as of :data:`AVERAGES` (``meta["averages_assumed"]``) [-]."""
    n = AVERAGES if averages is None else averages
    meta = {"file": str(path), **({"coherence_assumed": True} if assumed else {}),
            **({"averages_assumed": True} if averages is None else {})}
    return FRF(freq_hz=f, H=H, coherence=coh, n_averages=n,
               rel_std=coherence_rel_std(coh, n), name=Path(path).stem, meta=meta)


def write_frf_csv(frf: FRF, path, polar: bool = False) -> Path:
    """Write a frequency response as CSV, atomically.

    Parameters
    ----------
    frf : FRF
        The response [unit].
    path : str or Path
        Target file [-].
    polar : bool
        Columns ``magnitude_db, phase_deg`` instead of ``re, im`` [-]. An ``averages``
        column follows the coherence where the FRF knows its count (not assumed) [-].

    Returns
    -------
    Path
        The file written [-].
    """
    cols = {"freq_hz": frf.freq_hz}
    if polar:
        cols["magnitude_db"] = frf.magnitude_db
        cols["phase_deg"] = np.degrees(np.angle(frf.H))
    else:
        cols["re"], cols["im"] = frf.H.real, frf.H.imag
    cols["coherence"] = frf.coherence
    if not frf.meta.get("averages_assumed"):
        cols["averages"] = np.full(frf.freq_hz.size, float(frf.n_averages))
    return atomic_write_columns(path, cols, float_format="%.17g")


def _mat_names(names, path) -> None:
    """Refuse a MAT file's quantity given twice (H beside frf, or beside re and im); say
    the variables not read [-]."""
    _named_once(names, (FREQ, (*COMPLEX, RE[0]), (*COMPLEX, IM[0]), RE, IM, COH, AVG), path,
                "variables", None)
    known = {c.lower() for c in FREQ + COMPLEX + RE + IM + COH + AVG}
    re_, im_ = _pick(names, RE), _pick(names, IM)
    response = _pick(names, COMPLEX) or (re_ and im_ and f"{re_} and {im_}")
    why = (f"the response is read from {response}" if response else
           "no variable holds a response: H (or frf, G, resp), or re and im")
    for other in (n for n in names if n.lower() not in known):
        warn_input(f"variable '{other}' is not read ({why})", file=path)


def _mat_vector(names, get, path, choices, what):
    """``(name, vector)`` of the first of ``choices`` among a MAT file's ``names``,
    ``(None, None)`` for none; a matrix an :class:`InputError` [-]."""
    name = _pick(names, choices)
    if name is None:
        return None, None
    a = mat_array(get(name), name, path)
    if a.ndim > 2 or (a.ndim == 2 and 1 not in a.shape):
        raise InputError(f"variable '{name}' ({what}) has shape {a.shape}; store a vector",
                         file=path, column=name)
    return name, a.reshape(-1)


def read_frf_mat(path) -> FRF:
    """Read a frequency response from a MATLAB .mat file (variables: see the module).

    Parameters
    ----------
    path : str or Path
        The .mat file (v4 to v7.3) [-].

    Returns
    -------
    FRF
        The response [unit].
    """
    path = existing_file(path, ".mat file", "MAT file")
    names, _, get = load(path)
    _mat_names(names, path)

    def var(choices, what):
        return _mat_vector(names, get, path, choices, what)

    fname, f = var(FREQ, "frequency")
    if f is None:
        raise InputError(f"no frequency variable; name it one of {', '.join(FREQ)} [Hz] (the "
                         f"file has {', '.join(names) or 'none'})", file=path)
    hname, H = var(COMPLEX, "response")
    if H is not None and not np.iscomplexobj(H):  # a magnitude would read as a phase of 0
        raise InputError(f"variable '{hname}' holds real numbers only; store the complex "
                         "response", file=path, column=hname)
    if H is None:
        _, re_ = var(RE, "real part")
        _, im_ = var(IM, "imaginary part")
        if re_ is None or im_ is None:
            raise InputError("no response variable; store a complex vector H (or frf, G, "
                             f"resp) or re and im (the file has {', '.join(names)})",
                             file=path)
        hname, H = "re", np.asarray(re_, float) + 1j * np.asarray(im_, float)
    cname, coh = var(COH, "coherence")
    aname, avg = var(AVG, "averages")
    if avg is not None and avg.size != 1:
        raise InputError(f"variable '{aname}' has {avg.size} values; store one count",
                         file=path, column=aname)
    f, H = np.asarray(f).real.astype(float), np.asarray(H, dtype=complex)
    for name, a in ((fname, f), (hname, H), (cname, coh)):
        if a is not None and a.size != f.size:
            raise InputError(f"variable '{name}' has {a.size} values for {f.size} "
                             "frequencies", file=path, column=name)
        if a is not None and not np.all(np.isfinite(a)):
            raise InputError(f"variable '{name}' holds values that are not finite",
                             file=path, column=name)
    if np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise InputError(f"variable '{fname}' must hold frequencies > 0 Hz, increasing",
                         file=path, column=fname)
    coh = None if coh is None else np.asarray(coh, float).real
    return _frf(f, H, _coherence(coh, f.size, path, cname), path, coh is None,
                _averages(None if avg is None else np.asarray(avg, float).real, path, aname,
                          rows=False))
