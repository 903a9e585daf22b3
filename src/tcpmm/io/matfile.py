"""MATLAB .mat adapter: v4/v5/v7 via scipy.io.loadmat, v7.3 (HDF5) via h5py.

Variable names in a map may address struct fields (``meas.enc``) and a matrix column or
row, 1-based as in MATLAB (``data(:,3)``, ``data(3,:)``; :mod:`tcpmm.io.matindex`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from tcpmm.errors import InputError
from tcpmm.io.declared import name_unit
from tcpmm.io.matindex import parse_reference, pick
from tcpmm.io.signalmap import build_record, parse_signal_map, read_mapped
from tcpmm.io.text import existing_file

#: One part of a dotted name: a field, with an element of a struct array (``runs(2)``)
_PART = re.compile(r"^([A-Za-z]\w*)(?:\((\d+)\))?$")


def load(path: Path):
    """The variables of a .mat file of any version.

    Parameters
    ----------
    path : Path
        The .mat file [-].

    Returns
    -------
    tuple
        Top-level names, dotted paths of all variables and the getter of a dotted path,
        which returns an ndarray, a dict (struct), a str (char) or None when absent [-].
    """
    import h5py

    existing_file(path, ".mat file", "MAT file")
    return _load_v73(path) if h5py.is_hdf5(path) else _load_v5(path)


def _load_v73(path: Path):
    """:func:`load` of a MATLAB v7.3 file, which is HDF5: read a variable at a time
    (parameters and result as there)."""
    import h5py

    paths = []

    def visit(key, obj):
        if isinstance(obj, h5py.Dataset) and not key.startswith("#"):
            name = key.replace("/", ".")
            if h5py.check_dtype(ref=obj.dtype) is not None and "." in name:  # struct array
                head, field = name.rsplit(".", 1)
                paths.extend(f"{head}({k + 1}).{field}" for k in range(min(obj.size, _SHOWN)))
            else:
                paths.append(name)

    try:
        with h5py.File(path, "r") as f:
            names = [k for k in f if not k.startswith("#")]
            f.visititems(visit)
    except OSError as exc:  # damaged or truncated HDF5
        raise InputError(
            f"cannot read as a MATLAB v7.3 (HDF5) file: {exc}. Save it again from MATLAB",
            file=path,
        ) from None

    def get73(dotted: str):
        try:
            with h5py.File(path, "r") as f:
                obj = _v73_object(f, dotted, path)
                if isinstance(obj, h5py.Group):  # a struct: report its fields
                    return dict.fromkeys(obj)
                if not isinstance(obj, h5py.Dataset):
                    return None
                cls = obj.attrs.get("MATLAB_class", b"")
                if obj.attrs.get("MATLAB_empty", 0):  # MATLAB stores [] as its size
                    return np.zeros(0)
                a = obj[()]
        except OSError as exc:
            raise InputError(
                f"cannot read variable '{dotted}' of a MATLAB v7.3 file: {exc}", file=path
            ) from None
        if cls in (b"char", "char"):
            return "".join(map(chr, np.ravel(a)))
        # MATLAB stores column-major, so h5py sees the transpose
        return np.asarray(a).T

    return names, paths, get73


def _v73_object(f, dotted: str, path: Path):
    """The HDF5 object of ``dotted`` (``runs(2).field``) in the open v7.3 file ``f``, or
    ``None``: a struct array is a group whose fields hold a reference per element
    (MATLAB's layout); an element out of range, or none named, an InputError [-]."""
    import h5py

    obj, where, index = f, "", None
    for part in dotted.split("."):
        m = _PART.match(part)
        if m is None or not isinstance(obj, h5py.Group) or m.group(1) not in obj:
            return None
        obj, where = obj[m.group(1)], where + m.group(1)
        refs = isinstance(obj, h5py.Dataset) and h5py.check_dtype(ref=obj.dtype) is not None
        if refs and index is None:
            raise InputError(f"'{where.rsplit('.', 1)[0]}' is a struct array of {obj.size} "
                             f"elements; address one as {where.rsplit('.', 1)[0]}(k)."
                             f"{m.group(1)}, k from 1 to {obj.size}", file=path)
        if refs:
            if not 1 <= index <= obj.size:
                raise InputError(f"'{where.rsplit('.', 1)[0]}({index})': the struct array has "
                                 f"{obj.size} elements", file=path)
            obj, index = f[np.ravel(obj[()], order="F")[index - 1]], None
        if m.group(2) is not None:
            index = int(m.group(2))
        where += "."
    return obj


def _load_v5(path: Path):
    """:func:`load` of a MATLAB v4 to v7 file, read whole by scipy (parameters and result
    as there)."""
    from scipy.io import loadmat

    try:
        data = loadmat(path, simplify_cells=True)
    except Exception as exc:  # scipy raises ValueError/TypeError/... on a bad file
        raise InputError(
            f"cannot read as a MATLAB .mat file: {exc}. Save it with MATLAB's save "
            "(formats v4 to v7.3)",
            file=path,
        ) from None
    names = [k for k in data if not k.startswith("__")]

    def walk(obj, prefix):
        for k, v in obj.items():
            if isinstance(v, dict):
                yield from walk(v, f"{prefix}{k}.")
            elif (elements := _elements(v)) is not None:  # a struct array: each element's fields
                for i, e in enumerate(elements[:_SHOWN]):
                    yield from walk(e, f"{prefix}{k}({i + 1}).")
            else:
                yield prefix + k

    paths = list(walk({k: data[k] for k in names}, ""))

    def get(dotted: str):
        obj, where = data, ""
        for part in dotted.split("."):
            m = _PART.match(part)
            if m is None or not isinstance(obj, dict) or m.group(1) not in obj:
                return None
            obj, where = obj[m.group(1)], where + m.group(1)
            obj = _element(obj, m.group(2), where, path)
            where += "" if m.group(2) is None else f"({m.group(2)})"
            where += "."
        return obj

    return names, paths, get


#: Elements of a struct array whose fields are offered as names [-].
_SHOWN = 10


def _elements(value):
    """The elements of a struct array as scipy reads it (a list or object array of
    structs), else ``None`` [-]."""
    if isinstance(value, np.ndarray) and value.dtype == object:
        value = list(value.ravel())
    if isinstance(value, list) and value and all(isinstance(e, dict) for e in value):
        return value
    return None


def _element(obj, index, name: str, path: Path):
    """Element ``index`` (1-based, as MATLAB counts) of the struct array ``obj``; ``obj``
    itself where no index is given and it is not a struct array; an
    :class:`InputError` where the index is missing or out of range [-]."""
    elements = _elements(obj)
    if index is None:
        if elements is not None:
            raise InputError(
                f"'{name}' is a struct array of {len(elements)} elements; address one as "
                f"{name}(k).field, k from 1 to {len(elements)}", file=path)
        return obj
    if elements is None:
        raise InputError(f"'{name}' is not a struct array; write {name} without ({index})",
                         file=path)
    k = int(index)
    if not 1 <= k <= len(elements):
        raise InputError(f"'{name}({k})': the struct array has {len(elements)} elements",
                         file=path)
    return elements[k - 1]


def mat_array(value, name: str, path: Path) -> np.ndarray:
    """A variable as a numeric ndarray (may be complex), or an InputError saying what it is."""
    if isinstance(value, dict):
        fields = ", ".join(f"{name}.{k}" for k in value) or "none"
        raise InputError(
            f"variable '{name}' is a struct; map one of its fields: {fields}", file=path
        )
    if isinstance(value, str):
        raise InputError(
            f"variable '{name}' is text (char), not numbers; map a numeric vector", file=path
        )
    if hasattr(value, "toarray"):
        raise InputError(
            f"variable '{name}' is a sparse matrix; save full({name}) instead", file=path
        )
    a = np.asarray(value)
    if a.dtype.names is not None and {"real", "imag"} <= set(a.dtype.names):  # v7.3 complex
        a = a["real"] + 1j * a["imag"]
    if a.dtype.kind not in "biufc":
        raise InputError(
            f"variable '{name}' is not a numeric array (a cell array, struct array or object); "
            "store the samples as a double vector",
            file=path,
        )
    return a


def _fetcher(get, path: Path):
    def fetch(spec: str):
        name, part, k = parse_reference(spec, path)
        value = get(name)
        if value is None:
            return None
        return pick(mat_array(value, name, path), spec, part, k, path)

    return fetch


def _sample_rate(fs_hz, fetch, path: Path) -> float:
    """The sample rate given for a record without a time vector.

    Parameters
    ----------
    fs_hz : float or str or None
        Sample rate, or the name of a scalar variable holding it [Hz].
    fetch : callable
        Returns a variable's samples by name, None when absent [-].
    path : Path
        The .mat file, for the messages [-].

    Returns
    -------
    float
        The positive, finite sample rate [Hz].
    """
    if isinstance(fs_hz, str):
        v = fetch(fs_hz)
        if v is None or np.size(v) != 1 or v.dtype.kind not in "biuf":
            raise InputError(f"fs_hz variable '{fs_hz}' not found or not a scalar", file=path)
        fs_hz = float(np.ravel(v)[0])
    if fs_hz is None:
        raise InputError(
            "no time base: map a time vector as variable_map['time_s'] or give fs_hz",
            file=path,
        )
    try:
        fs_hz = float(fs_hz)
    except (TypeError, ValueError):
        raise InputError(
            f"fs_hz must be a number [Hz] or the name of a scalar variable, got {fs_hz!r}",
            file=path,
        ) from None
    if not (np.isfinite(fs_hz) and fs_hz > 0):
        raise InputError(f"fs_hz must be positive, got {fs_hz!r}", file=path)
    return fs_hz


def read_record_mat(
    path: str | Path,
    kind: str,
    variable_map: Mapping | None = None,
    axis: str | None = None,
    fs_hz: float | str | None = None,
):
    """Read a MATLAB .mat file into a sweep or friction record.

    Parameters
    ----------
    path : str or Path
        .mat file, any version [-].
    kind : {"sweep", "friction"}
        Record kind [-].
    variable_map : mapping, optional
        tcpmm name to variable (``"name"``, ``"struct.field"``, ``"data(:,k)"``,
        ``"data(k,:)"``),
        optionally ``(name, scale)``; None means the variables carry the tcpmm names [-].
    axis : str, optional
        Axis name stored in the record [-].
    fs_hz : float or str, optional
        Sample rate, or the name of a scalar variable holding it; used when no
        ``time_s`` is mapped (time then starts at 0) [Hz].

    Returns
    -------
    SweepRecord or FrictionRecord
        The record, SI.
    """
    path = Path(path)
    names, paths, get = load(path)
    smap = parse_signal_map(variable_map, kind, file=path)
    fetch = _fetcher(get, path)
    try:
        cols = read_mapped(smap, fetch, file=path, candidates=paths,
                           unit_of=lambda name: (name_unit(name), "its name", False))
    except InputError as exc:
        raise InputError(
            f"{exc.message}. Variables in the file: {', '.join(names) or 'none'}",
            file=path,
            column=exc.column,
        ) from None
    if "time_s" not in cols:
        fs = _sample_rate(fs_hz, fetch, path)
        cols["time_s"] = np.arange(next(iter(cols.values())).size) / fs
    return build_record(kind, cols, path, axis)


def read_sweep_mat(
    path: str | Path,
    variable_map: Mapping | None = None,
    axis: str | None = None,
    fs_hz: float | str | None = None,
):
    """Read a servo-excitation record from a MATLAB .mat file (v5, v7 or v7.3).

    Parameters
    ----------
    path : str or Path
        .mat file [-].
    variable_map : mapping, optional
        tcpmm name (``excitation_A``, ``current_cmd_A``, ``motor_angle_rad``, ``scale_mm``,
        ``tcp_mm``, ``time_s``) to variable, as in :func:`read_record_mat` [-].
    axis : str, optional
        Axis name stored in the record [-].
    fs_hz : float or str, optional
        Sample rate or the name of its variable, when no time vector is mapped [Hz].

    Returns
    -------
    SweepRecord
        The record, SI.
    """
    return read_record_mat(path, "sweep", variable_map, axis, fs_hz)


def read_friction_mat(
    path: str | Path,
    variable_map: Mapping | None = None,
    axis: str | None = None,
    fs_hz: float | str | None = None,
):
    """Read constant-velocity runs from a MATLAB .mat file (see :func:`read_sweep_mat`).

    Parameters
    ----------
    path : str or Path
        .mat file [-].
    variable_map : mapping, optional
        tcpmm name (``current_cmd_A``, ``motor_angle_rad``, ``scale_mm``, ``time_s``) to
        variable [-].
    axis : str, optional
        Axis name stored in the record [-].
    fs_hz : float or str, optional
        Sample rate or the name of its variable, when no time vector is mapped [Hz].

    Returns
    -------
    FrictionRecord
        The record, SI.
    """
    return read_record_mat(path, "friction", variable_map, axis, fs_hz)
