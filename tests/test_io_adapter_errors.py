"""Bad input to the TDMS and MATLAB adapters gives an InputError that names the culprit."""

from __future__ import annotations

import h5py
import numpy as np
import pytest
import scipy.io
import scipy.sparse
from nptdms import ChannelObject, TdmsWriter

from tcpmm.errors import InputError
from tcpmm.io.matfile import read_record_mat, read_sweep_mat
from tcpmm.io.signalmap import parse_signal_map
from tcpmm.io.tdms import read_record_tdms, read_sweep_tdms

FS = 1000.0
N = 100
NAMES = ("excitation_A", "current_cmd_A", "motor_angle_rad", "scale_mm")
T = np.arange(N) / FS
R = np.sin(2 * np.pi * 50 * T)
PROPS = {"wf_increment": 1 / FS, "wf_start_offset": 0.0}


def write_mat(path, **over):
    data = {"time_s": T, **dict.fromkeys(NAMES, R), **over}
    scipy.io.savemat(path, {k: v for k, v in data.items() if v is not None})
    return path


def write_mat73(path, **over):
    """A v7.3 file laid out as MATLAB does; ``over`` maps names to (data, attrs)."""
    with h5py.File(path, "w", userblock_size=512) as f:
        for k in ("time_s", *NAMES):
            f.create_dataset(k, data=(T if k == "time_s" else R)[:, None])
        for k, (data, attrs) in over.items():
            if k in f:
                del f[k]
            if data is None:
                f.create_group(k)
                continue
            ds = f.create_dataset(k, data=data)
            ds.attrs.update(attrs)
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file".ljust(128, b" "))
    return path


def write_tdms(path, props=PROPS, extra=(), **over):
    data = {**dict.fromkeys(NAMES, R), **over}
    chans = [ChannelObject("DAQ", k, v, properties=props) for k, v in data.items()]
    with TdmsWriter(path) as w:
        w.write_segment([*chans, *extra])
    return path


TMAP = {k: f"DAQ/{k}" for k in NAMES}
MMAP = {k: k for k in NAMES}


@pytest.mark.parametrize("fmt", ["mat", "tdms"])
@pytest.mark.parametrize(
    ("entry", "match"),
    [
        (("scale_mm", "abc"), "scale factor 'abc'.*not a number"),
        ({"name": "scale_mm", "scale": None}, "scale factor None.*not a number"),
        (("scale_mm", [1, 2]), "not a number"),
        (("scale_mm", 1j), "not a number"),
        (("scale_mm", True), "not a number"),
        ({"name": None}, "name must be a non-empty string"),
        ((3, 1.0), "name must be a non-empty string"),
    ],
)
def test_bad_map_entry_names_the_entry(tmp_path, fmt, entry, match):
    if fmt == "mat":
        path, base, read = write_mat(tmp_path / "x.mat"), MMAP, read_sweep_mat
    else:
        path, base, read = write_tdms(tmp_path / "x.tdms"), TMAP, read_sweep_tdms
    if isinstance(entry, tuple) and isinstance(entry[0], str) and fmt == "tdms":
        entry = ("DAQ/" + entry[0], entry[1])
    with pytest.raises(InputError, match=match) as exc:
        read(path, {**base, "scale_mm": entry})
    assert exc.value.column == "scale_mm" and exc.value.file == str(path)


@pytest.mark.parametrize(
    ("mapping", "kind", "match"),
    [
        (list(NAMES), "sweep", "must be a dict"),
        ("excitation_A", "sweep", "must be a dict"),
        (None, "swept", "unknown record kind 'swept'; use one of sweep, friction"),
    ],
)
def test_bad_map_or_kind(tmp_path, mapping, kind, match):
    with pytest.raises(InputError, match=match):
        parse_signal_map(mapping, kind, file="x.mat")
    with pytest.raises(InputError, match=match):
        read_record_tdms(write_tdms(tmp_path / "x.tdms"), kind, mapping)
    with pytest.raises(InputError, match=match):
        read_record_mat(write_mat(tmp_path / "x.mat"), kind, mapping)


def _complex_tdms(p):
    return read_sweep_tdms(write_tdms(p / "c.tdms", excitation_A=R + 1j * R))


def _string_tdms(p):
    return read_sweep_tdms(write_tdms(p / "s.tdms", excitation_A=np.array(["a"] * N)))


def _complex_mat(p):
    return read_sweep_mat(write_mat(p / "c.mat", excitation_A=R + 1j * R))


def _complex_mat73(p):
    # MATLAB stores complex data as a compound of 'real' and 'imag'
    cplx = np.zeros((N, 1), dtype=[("real", "f8"), ("imag", "f8")])
    cplx["real"][:, 0], cplx["imag"][:, 0] = R, R
    return read_sweep_mat(write_mat73(p / "c73.mat", excitation_A=(cplx, {})))


@pytest.mark.parametrize(
    ("read", "match"),
    [
        (_complex_tdms, "holds complex values"),
        (_complex_mat, "holds complex values"),
        (_complex_mat73, "holds complex values"),
        (_string_tdms, "not numbers"),
    ],
)
def test_non_real_data_is_refused(tmp_path, read, match):
    with pytest.raises(InputError, match=match) as exc:
        read(tmp_path)
    assert exc.value.column == "excitation_A"


def test_timestamp_time_channel_becomes_seconds(tmp_path):
    stamps = np.datetime64("2024-01-01T00:00:00", "us") + (T * 1e6).astype("timedelta64[us]")
    path = write_tdms(tmp_path / "t.tdms", props={}, extra=[ChannelObject("DAQ", "t", stamps)])
    rec = read_sweep_tdms(path, {**TMAP, "time_s": "DAQ/t"})
    assert rec.fs_hz == pytest.approx(FS)
    np.testing.assert_allclose(rec.time_s, T, atol=1e-9)


@pytest.mark.parametrize(
    ("props", "match"),
    [
        ({"wf_increment": "abc"}, "property wf_increment .* is 'abc', not a number"),
        ({"wf_increment": 1 / FS, "wf_start_offset": "x"}, "wf_start_offset .* not a number"),
        ({"wf_increment": -1 / FS}, "wf_increment of 'excitation_A' is -0.001 s; it must be"),
        ({"wf_increment": 0.0}, "wf_increment of 'excitation_A' is 0.0 s"),
        ({"wf_increment": float("nan")}, "wf_increment of 'excitation_A' is nan s"),
    ],
)
def test_bad_wf_properties(tmp_path, props, match):
    with pytest.raises(InputError, match=match) as exc:
        read_sweep_tdms(write_tdms(tmp_path / "w.tdms", props=props))
    assert exc.value.column == "excitation_A"


@pytest.mark.parametrize("cut", [600, 3000])
def test_damaged_mat73(tmp_path, cut):
    good = write_mat73(tmp_path / "g.mat")
    bad = tmp_path / "bad.mat"
    bad.write_bytes(good.read_bytes()[:cut])
    with pytest.raises(InputError, match=r"cannot read as a MATLAB v7\.3"):
        read_sweep_mat(bad)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda p: write_mat(p / "s.mat", excitation_A={"a": R}), "is a struct.*excitation_A.a"),
        (lambda p: write_mat(p / "c.mat", excitation_A="1"), r"is text \(char\)"),
        (
            lambda p: write_mat(p / "sp.mat", excitation_A=scipy.sparse.csc_matrix(R[:, None])),
            r"sparse matrix; save full\(excitation_A\)",
        ),
        (lambda p: write_mat73(p / "g.mat", excitation_A=(None, {})), "is a struct"),
        (
            lambda p: write_mat73(
                p / "c.mat",
                excitation_A=(np.array([[104, 105]], np.uint16), {"MATLAB_class": b"char"}),
            ),
            r"is text \(char\)",
        ),
        (
            lambda p: write_mat73(
                p / "e.mat",
                excitation_A=(np.array([0, 0], np.uint64), {"MATLAB_empty": np.uint8(1)}),
            ),
            "'excitation_A': 0,",
        ),
    ],
)
def test_wrong_kind_of_variable_says_what_it_is(tmp_path, make, match):
    with pytest.raises(InputError, match=match) as exc:
        read_sweep_mat(make(tmp_path), fs_hz=FS)
    assert exc.value.file is not None


@pytest.mark.parametrize(
    ("fmt", "spec", "suggestion"),
    [
        ("mat", "excitaton_A", "excitation_A"),
        ("mat", "meas.rr", "meas.r"),
        ("tdms", "DAQ/excitaton_A", "DAQ/excitation_A"),
        ("tdms", "DQA/excitation_A", "DAQ/excitation_A"),
    ],
)
def test_missing_name_suggests_a_close_one(tmp_path, fmt, spec, suggestion):
    if fmt == "mat":
        path = write_mat(tmp_path / "x.mat", meas={"r": R})
        read, base = read_sweep_mat, MMAP
    else:
        path, read, base = write_tdms(tmp_path / "x.tdms"), read_sweep_tdms, TMAP
    with pytest.raises(InputError, match=rf"not found \(did you mean '{suggestion}'\?\)") as e:
        read(path, {**base, "excitation_A": spec})
    assert e.value.column == "excitation_A"


def _ambiguous(p):
    extra = [ChannelObject("TCP", "excitation_A", R, properties=PROPS)]
    return read_sweep_tdms(write_tdms(p / "a.tdms", extra=extra))


@pytest.mark.parametrize(
    ("read", "column"),
    [
        (
            lambda p: read_sweep_mat(write_mat(p / "x.mat"), {**MMAP, "excitation_A": "a b"}),
            "excitation_A",
        ),
        (lambda p: read_sweep_mat(write_mat(p / "x.mat", excitation_A="abc")), "excitation_A"),
        (_ambiguous, "excitation_A"),
        (lambda p: read_sweep_tdms(write_tdms(p / "x.tdms"), group="DQA"), "DQA"),
    ],
)
def test_errors_name_the_signal(tmp_path, read, column):
    with pytest.raises(InputError) as exc:
        read(tmp_path)
    assert exc.value.column == column


def test_single_column_matrix_selects_column_1(tmp_path):
    path = tmp_path / "x.mat"
    scipy.io.savemat(path, {"t": T, "d": R[:, None], "m": np.column_stack([R, R])})
    vmap = {
        "time_s": "t(:,1)",
        "excitation_A": "d(:,1)",
        "current_cmd_A": "m(:,2)",
        "motor_angle_rad": "d",
        "scale_mm": "m(:,1)",
    }
    rec = read_sweep_mat(path, vmap)
    np.testing.assert_allclose(rec.excitation_A, R)
    with pytest.raises(InputError, match="column 2 does not exist"):
        read_sweep_mat(path, {**vmap, "excitation_A": "d(:,2)"})


def test_tdms_group_name_with_slash(tmp_path):
    path = tmp_path / "g.tdms"
    with TdmsWriter(path) as w:
        w.write_segment([ChannelObject("rig/1", k, R, properties=PROPS) for k in NAMES])
    rec = read_sweep_tdms(path, {k: f"rig/1/{k}" for k in NAMES})
    np.testing.assert_allclose(rec.current_cmd_A, R)


@pytest.mark.parametrize("read", [read_sweep_mat, read_sweep_tdms])
def test_folder_as_file(tmp_path, read):
    with pytest.raises(InputError, match="this is a directory; give the path of the"):
        read(tmp_path)


@pytest.mark.parametrize("fs", [[FS], object()])
def test_bad_fs_hz(tmp_path, fs):
    path = write_mat(tmp_path / "x.mat", time_s=None)
    with pytest.raises(InputError, match="fs_hz must be a number"):
        read_sweep_mat(path, fs_hz=fs)


def test_channels_starting_at_different_times_are_refused(tmp_path):
    """Only the first channel's wf_start_offset set the time base: a position channel that
    started 10 ms after the drive's was laid on the drive's samples without a word, and
    the FRFs took a delay that was the logger's."""
    from nptdms import ChannelObject, TdmsWriter

    path = tmp_path / "skew.tdms"
    chans = [ChannelObject("DAQ", k, R, properties={
        "wf_increment": 1 / FS, "wf_start_offset": 0.01 if k == "scale_mm" else 0.0})
        for k in NAMES]
    with TdmsWriter(path) as w:
        w.write_segment(chans)
    with pytest.raises(InputError, match="channels start at different times") as e:
        read_sweep_tdms(path)
    assert "scale_mm 0.01 s" in str(e.value)
    read_sweep_tdms(write_tdms(tmp_path / "ok.tdms"))  # one start for all: read
