"""TDMS and MATLAB adapters produce the same SI records as sweep.csv."""

from __future__ import annotations

import math
import warnings

import h5py
import numpy as np
import pytest
import scipy.io
from nptdms import ChannelObject, TdmsWriter

from tcpmm.errors import InputError, InputWarning
from tcpmm.io.matfile import read_friction_mat, read_sweep_mat
from tcpmm.io.records import FrictionRecord, SweepRecord
from tcpmm.io.tdms import read_friction_tdms, read_sweep_tdms

FS = 2000.0
N = 500
COUNTS = 10000


def signals():
    t = np.arange(N) / FS
    r = np.sin(2 * np.pi * (5 * t + 100 * t**2))
    counts = np.round(3000 * np.sin(2 * np.pi * 3 * t))
    scale_um = counts * 10.0 / COUNTS * 1e3
    return {
        "t": t,
        "r": r,
        "ic": 1.2 * r,
        "counts": counts,
        "scale_um": scale_um,
        "tcp_mm": scale_um * 1e-3 + 1e-4 * r,
    }


def check_sweep(rec, s, tcp=True):
    assert isinstance(rec, SweepRecord)
    assert rec.fs_hz == pytest.approx(FS, rel=1e-9)
    np.testing.assert_allclose(rec.time_s, s["t"], atol=1e-12)
    np.testing.assert_allclose(rec.excitation_A, s["r"], rtol=1e-12)
    np.testing.assert_allclose(rec.current_cmd_A, s["ic"], rtol=1e-12)
    np.testing.assert_allclose(rec.motor_angle_rad, s["counts"] * 2 * np.pi / COUNTS, rtol=1e-12)
    np.testing.assert_allclose(rec.scale_m, s["scale_um"] * 1e-6, rtol=1e-12, atol=1e-18)
    if tcp:
        np.testing.assert_allclose(rec.tcp_m, s["tcp_mm"] * 1e-3, rtol=1e-12, atol=1e-18)
    else:
        assert rec.tcp_m is None


MAP = {
    "excitation_A": "DAQ/ai0",
    "current_cmd_A": "DAQ/ai1",
    "motor_angle_rad": ("DAQ/enc", 2 * math.pi / COUNTS),
    "scale_mm": {"name": "DAQ/ls", "scale": 1e-3},
    "tcp_mm": "TCP/x",
}


def write_tdms(path, s, props=True, time_channel=False):
    p = {"wf_increment": 1 / FS, "wf_start_offset": 0.0} if props else {}
    chans = [
        ChannelObject("DAQ", "ai0", s["r"], properties=p),
        ChannelObject("DAQ", "ai1", s["ic"], properties=p),
        ChannelObject("DAQ", "enc", s["counts"], properties=p),
        ChannelObject("DAQ", "ls", s["scale_um"], properties=p),
        ChannelObject("TCP", "x", s["tcp_mm"], properties=p),
    ]
    if time_channel:
        chans.append(ChannelObject("DAQ", "time", s["t"]))
    with TdmsWriter(path) as w:
        w.write_segment(chans)
    return path


def test_tdms_with_wf_increment_and_scale_factors(tmp_path):
    s = signals()
    rec = read_sweep_tdms(write_tdms(tmp_path / "x.tdms", s), MAP, axis="X")
    check_sweep(rec, s)
    assert rec.axis == "X" and rec.source.endswith("x.tdms")


@pytest.mark.parametrize("unit, per_s", [("ms", 1e3), ("Milliseconds", 1e3), ("us", 1e6),
                                         ("µs", 1e6), ("s", 1.0), ("Seconds", 1.0),
                                         ("", 1.0)])
def test_tdms_waveform_x_unit_is_applied(tmp_path, unit, per_s):
    """A waveform in ms (wf_xunit_string "ms", wf_increment 0.5) was read with the
    increment taken as seconds: 2 Hz for 2 kHz, with no word."""
    s = signals()
    p = {"wf_increment": per_s / FS, "wf_start_offset": 0.25 * per_s,
         "wf_xunit_string": unit, "wf_xname": "Time"}
    chans = [ChannelObject(g, c, s[k], properties=p) for g, c, k in
             (("DAQ", "ai0", "r"), ("DAQ", "ai1", "ic"), ("DAQ", "enc", "counts"),
              ("DAQ", "ls", "scale_um"), ("TCP", "x", "tcp_mm"))]
    with TdmsWriter(tmp_path / "w.tdms") as w:
        w.write_segment(chans)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        rec = read_sweep_tdms(tmp_path / "w.tdms", MAP)
    assert rec.fs_hz == pytest.approx(FS, rel=1e-9)
    np.testing.assert_allclose(rec.time_s, 0.25 + s["t"], rtol=1e-12)


def test_tdms_waveform_over_no_time_is_refused_naming_the_property(tmp_path):
    s = signals()
    p = {"wf_increment": 1 / FS, "wf_xunit_string": "Hz"}
    chans = [ChannelObject("DAQ", c, s[k], properties=p) for c, k in
             (("ai0", "r"), ("ai1", "ic"), ("enc", "counts"), ("ls", "scale_um"))]
    with TdmsWriter(tmp_path / "hz.tdms") as w:
        w.write_segment(chans)
    with pytest.raises(InputError, match=r"property wf_xunit_string of channel 'ai0' is "
                                         r"'Hz', not a unit of time") as refused:
        read_sweep_tdms(tmp_path / "hz.tdms", {k: v for k, v in MAP.items() if k != "tcp_mm"})
    assert refused.value.column == "excitation_A"


def test_tdms_time_channel_and_group_default(tmp_path):
    s = signals()
    path = write_tdms(tmp_path / "x.tdms", s, props=False, time_channel=True)
    cmap = {k: v for k, v in MAP.items() if k != "tcp_mm"}
    cmap = {k: (v.split("/", 1)[1] if isinstance(v, str) else v) for k, v in cmap.items()}
    cmap["motor_angle_rad"] = ("enc", 2 * math.pi / COUNTS)
    cmap["scale_mm"] = ("ls", 1e-3)
    cmap["time_s"] = "time"
    check_sweep(read_sweep_tdms(path, cmap, group="DAQ"), s, tcp=False)


def test_tdms_errors_list_what_is_there(tmp_path):
    s = signals()
    path = write_tdms(tmp_path / "x.tdms", s)
    with pytest.raises(InputError, match=r"'DAQ/ai9'.*not found.*DAQ: ai0, ai1, enc, ls"):
        read_sweep_tdms(path, {**MAP, "excitation_A": "DAQ/ai9"})
    with pytest.raises(InputError, match="unknown tcpmm signal") as exc:
        read_sweep_tdms(path, {**MAP, "scale_um": "DAQ/ls"})
    assert exc.value.column == "scale_um"
    with pytest.raises(InputError, match="lacks current_cmd_A"):
        read_sweep_tdms(path, {k: v for k, v in MAP.items() if k != "current_cmd_A"})
    nt = write_tdms(tmp_path / "nt.tdms", s, props=False)
    with pytest.raises(InputError, match="no time base"):
        read_sweep_tdms(nt, MAP)
    bad = tmp_path / "bad.tdms"
    bad.write_bytes(b"not a tdms file at all")
    with pytest.raises(InputError, match="cannot read as TDMS"):
        read_sweep_tdms(bad, MAP)


def test_tdms_friction_with_tcpmm_channel_names(tmp_path):
    s = signals()
    p = {"wf_increment": 1 / FS}
    with TdmsWriter(tmp_path / "f.tdms") as w:
        w.write_segment(
            [
                ChannelObject("run", "current_cmd_A", s["ic"], properties=p),
                ChannelObject("run", "motor_angle_rad", s["counts"], properties=p),
                ChannelObject("run", "scale_mm", s["scale_um"], properties=p),
            ]
        )
    rec = read_friction_tdms(tmp_path / "f.tdms")
    assert isinstance(rec, FrictionRecord)
    np.testing.assert_allclose(rec.scale_m, s["scale_um"] * 1e-3)
    np.testing.assert_allclose(rec.time_s, s["t"], atol=1e-12)


VMAP = {
    "excitation_A": "meas.r",
    "current_cmd_A": "data(:,1)",
    "motor_angle_rad": ("data(:,2)", 2 * math.pi / COUNTS),
    "scale_mm": ("meas.ls", 1e-3),
    "tcp_mm": "tcp",
}


@pytest.mark.parametrize("signal, key", [("ls", "scale_mm"), ("tcp", "tcp_mm")])
def test_a_gap_in_a_mat_signal_names_the_signal_mapped(tmp_path, signal, key):
    """A NaN in the scale's variable was said as in column 'scale_m', a name of no file
    and of no map."""
    s = signals()
    ls, tcp = s["scale_um"].copy(), s["tcp_mm"].copy()
    (ls if signal == "ls" else tcp)[100] = np.nan
    scipy.io.savemat(tmp_path / "x.mat", {
        "meas": {"r": s["r"], "ls": ls}, "data": np.column_stack([s["ic"], s["counts"]]),
        "tcp": tcp[:, None]})
    with pytest.raises(InputError, match=rf"column '{key}': value is NaN at sample 100"):
        read_sweep_mat(tmp_path / "x.mat", VMAP, fs_hz=FS)


def test_mat_v5_struct_fields_columns_and_fs_variable(tmp_path):
    s = signals()
    path = tmp_path / "x.mat"
    scipy.io.savemat(
        path,
        {
            "meas": {"r": s["r"], "ls": s["scale_um"]},
            "data": np.column_stack([s["ic"], s["counts"]]),
            "tcp": s["tcp_mm"][:, None],
            "fs": FS,
            "t": s["t"],
        },
    )
    check_sweep(read_sweep_mat(path, VMAP, fs_hz="fs"), s)
    check_sweep(read_sweep_mat(path, {**VMAP, "time_s": "t"}), s)
    with pytest.raises(InputError, match=r"column 3 does not exist"):
        read_sweep_mat(path, {**VMAP, "current_cmd_A": "data(:,3)"}, fs_hz=FS)
    with pytest.raises(InputError, match=r"'meas.x'.*not found.*Variables in the file"):
        read_sweep_mat(path, {**VMAP, "excitation_A": "meas.x"}, fs_hz=FS)
    with pytest.raises(InputError, match="no time base"):
        read_sweep_mat(path, VMAP)


def test_mat_v73_struct_array_reads_as_its_v5_twin(tmp_path):
    """``runs(2).field`` of a v7.3 file (MATLAB's layout: the struct array a group, each
    field a dataset of one object reference per element) was 'not found', and the hint
    it gave, ``runs.field``, 'not a numeric array'."""
    s = signals()
    one = {"r": s["r"], "ic": s["ic"], "counts": s["counts"], "ls": s["scale_um"],
           "t": s["t"]}
    path = tmp_path / "runs.mat"
    with h5py.File(path, "w", userblock_size=512) as f:
        refs, g = f.create_group("#refs#"), f.create_group("runs")
        for name, v in one.items():
            rr = [refs.create_dataset(f"{name}{k}", data=(v * k)[:, None]).ref
                  for k in (0, 1)]
            g.create_dataset(name, data=np.array(rr, dtype=h5py.ref_dtype)[:, None])
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file".ljust(128, b" "))
    vmap = {"time_s": "runs(2).t", "excitation_A": "runs(2).r", "current_cmd_A": "runs(2).ic",
            "motor_angle_rad": ("runs(2).counts", 2 * math.pi / COUNTS),
            "scale_mm": ("runs(2).ls", 1e-3)}
    got = read_sweep_mat(path, vmap)
    np.testing.assert_array_equal(got.scale_m, s["scale_um"] * 1e-3 * 1e-3)
    np.testing.assert_array_equal(got.time_s, s["t"])
    with pytest.raises(InputError, match=r"'runs' is a struct array of 2 elements; address "
                                         r"one as runs\(k\)\.t"):
        read_sweep_mat(path, {**vmap, "time_s": "runs.t"})
    with pytest.raises(InputError, match=r"'runs\(3\)': the struct array has 2 elements"):
        read_sweep_mat(path, {**vmap, "time_s": "runs(3).t"})


def test_mat_v73_via_hdf5(tmp_path):
    s = signals()
    path = tmp_path / "x73.mat"
    with h5py.File(path, "w", userblock_size=512) as f:
        # MATLAB writes column-major: a 1xN row vector appears as (N, 1) in HDF5
        for name in ("r", "ic", "counts", "scale_um", "t"):
            f.create_dataset(name, data=s[name][:, None])
        g = f.create_group("dev")
        g.create_dataset("tcp", data=s["tcp_mm"][None, :])
    with open(path, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file".ljust(128, b" "))
    vmap = {
        "time_s": "t",
        "excitation_A": "r",
        "current_cmd_A": "ic",
        "motor_angle_rad": ("counts", 2 * math.pi / COUNTS),
        "scale_mm": ("scale_um", 1e-3),
        "tcp_mm": "dev.tcp",
    }
    check_sweep(read_sweep_mat(path, vmap), s)
    fr = read_friction_mat(
        path, {k: vmap[k] for k in ("time_s", "current_cmd_A", "motor_angle_rad", "scale_mm")}
    )
    np.testing.assert_allclose(fr.current_cmd_A, s["ic"])


ROWS = ("t", "r", "ic", "counts", "scale_um", "tcp_mm")
RMAP = {"time_s": "data(1,:)", "excitation_A": "data(2,:)", "current_cmd_A": "data(3,:)",
        "motor_angle_rad": ("data(4,:)", 2 * math.pi / COUNTS),
        "scale_mm": ("data(5,:)", 1e-3), "tcp_mm": "data(6,:)"}


def as_columns(vmap):
    """``vmap`` with each ``data(k,:)`` written ``data(:,k)``."""
    col = lambda v: v.replace(",:)", ")").replace("data(", "data(:,")  # noqa: E731
    return {k: col(v) if isinstance(v, str) else (col(v[0]), v[1]) for k, v in vmap.items()}


@pytest.mark.parametrize("version", ["v5", "v7.3"])
def test_mat_signals_in_rows_are_read_by_row_and_a_column_is_refused(tmp_path, version):
    """A matrix [t; exc; icmd; ...] (6 x N) mapped as data(:,k) was refused as "only 6
    samples; at least 64 are needed. Record longer", and data(k,:) was "not a variable
    reference"."""
    s = signals()
    path = tmp_path / "rows.mat"
    rows = np.vstack([s[k] for k in ROWS])
    if version == "v5":
        scipy.io.savemat(path, {"data": rows})
    else:
        with h5py.File(path, "w", userblock_size=512) as f:
            f.create_dataset("data", data=rows.T)  # MATLAB's 6 x N, column-major
        with open(path, "r+b") as fh:
            fh.write(b"MATLAB 7.3 MAT-file".ljust(128, b" "))
    check_sweep(read_sweep_mat(path, RMAP), s)
    with pytest.raises(InputError, match=rf"'data\(:,1\)': the matrix is 6 x {N}, its "
                                         r"signals in the rows \(a column holds 6 samples\); "
                                         r"map data\(1,:\), or save data\.'") as refused:
        read_sweep_mat(path, as_columns(RMAP))
    assert refused.value.column == "time_s"
    with pytest.raises(InputError, match=r"row 7 does not exist"):
        read_sweep_mat(path, {**RMAP, "tcp_mm": "data(7,:)"})


def test_mat_a_row_of_a_matrix_of_columns_is_refused_with_the_column_to_map(tmp_path):
    s = signals()
    path = tmp_path / "cols.mat"
    scipy.io.savemat(path, {"data": np.column_stack([s[k] for k in ROWS])})
    check_sweep(read_sweep_mat(path, as_columns(RMAP)), s)
    with pytest.raises(InputError, match=rf"'data\(1,:\)': the matrix is {N} x 6, its "
                                         r"signals in the columns .* map data\(:,1\)"):
        read_sweep_mat(path, RMAP)


def test_mat_length_mismatch_and_garbage(tmp_path):
    s = signals()
    path = tmp_path / "x.mat"
    scipy.io.savemat(
        path,
        {
            "meas": {"r": s["r"][:-1], "ls": s["scale_um"]},
            "data": np.column_stack([s["ic"], s["counts"]]),
            "tcp": s["tcp_mm"],
        },
    )
    with pytest.raises(InputError, match="differ in length"):
        read_sweep_mat(path, VMAP, fs_hz=FS)
    bad = tmp_path / "bad.mat"
    bad.write_bytes(b"\x00" * 300)
    with pytest.raises(InputError, match="cannot read as a MATLAB"):
        read_sweep_mat(bad, VMAP, fs_hz=FS)


def test_tdms_unit_string_against_the_maps_factor(tmp_path):
    """A channel whose unit_string says m, mapped to scale_mm without the factor 1000, was
    read a thousandfold small without a word; it is refused with the entry to write."""
    s = signals()
    p = {"wf_increment": 1 / FS, "wf_start_offset": 0.0}
    chans = [ChannelObject("DAQ", "ai0", s["r"], properties=p),
             ChannelObject("DAQ", "ai1", s["ic"], properties=p),
             ChannelObject("DAQ", "enc", s["counts"], properties=p),
             ChannelObject("DAQ", "ls", s["scale_um"] * 1e-6,
                           properties={**p, "unit_string": "m"}),
             ChannelObject("TCP", "x", s["tcp_mm"], properties={**p, "unit_string": "mm"})]
    with TdmsWriter(tmp_path / "u.tdms") as w:
        w.write_segment(chans)
    cmap = {**MAP, "scale_mm": "DAQ/ls"}
    with pytest.raises(InputError, match=r"'DAQ/ls' is in m \(unit_string\).*"
                                         r"\(\"DAQ/ls\", 1000\)") as e:
        read_sweep_tdms(tmp_path / "u.tdms", cmap)
    assert e.value.column == "scale_mm"
    with pytest.raises(InputError, match=r"with the factor 0\.001"):
        read_sweep_tdms(tmp_path / "u.tdms", {**cmap, "scale_mm": ("DAQ/ls", 1e-3)})
    check_sweep(read_sweep_tdms(tmp_path / "u.tdms", {**cmap, "scale_mm": ("DAQ/ls", 1e3)}),
                s)


def test_tdms_unit_string_of_no_kind_tcpmm_converts_is_said(tmp_path):
    """A motor channel in counts, or a current in volts, mapped with no factor read as rad
    and A without a word (the counts 4e6 rad off); the unit is said, and a factor given
    is taken as the user's."""
    s = signals()
    p = {"wf_increment": 1 / FS, "wf_start_offset": 0.0}
    chans = [ChannelObject("DAQ", "ai0", s["r"], properties=p),
             ChannelObject("DAQ", "ai1", s["ic"], properties=p),
             ChannelObject("DAQ", "enc", s["counts"], properties={**p, "unit_string": "counts"}),
             ChannelObject("DAQ", "ls", s["scale_um"], properties=p),
             ChannelObject("TCP", "x", s["tcp_mm"], properties=p)]
    with TdmsWriter(tmp_path / "c.tdms") as w:
        w.write_segment(chans)
    bare = {**MAP, "motor_angle_rad": "DAQ/enc"}
    with pytest.warns(InputWarning, match=r"'DAQ/enc' is in counts \(unit_string\), a unit "
                                          r"tcpmm does not convert to rad"):
        read_sweep_tdms(tmp_path / "c.tdms", bare)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        check_sweep(read_sweep_tdms(tmp_path / "c.tdms", MAP), s)


DEG = math.pi / 180


@pytest.mark.parametrize("unit, column, factor", [
    ("Degrees", "enc", DEG), ("degree", "enc", DEG), ("°", "enc", DEG),
    ("Meters", "ls", 1e3), ("metres", "ls", 1e3), ("Micrometers", "ls", 1e-3),
    ("Milliamps", "ai1", 1e-3), ("AMPERES", "ai1", 1.0)])
def test_tdms_unit_string_in_daqmx_words_is_held_against_the_factor(tmp_path, unit, column,
                                                                     factor):
    """NI DAQmx writes units as words: an angle in "Degrees" mapped with no factor was read
    57.3 times too large, a scale in "Meters" 1000 times too small, each with a warning
    that tcpmm "does not convert" the unit; they are refused as "deg" and "m" are."""
    s = signals()
    p = {"wf_increment": 1 / FS, "wf_start_offset": 0.0}
    in_unit = {"ai0": s["r"], "ai1": s["ic"] / factor,
               "enc": s["counts"] * 2 * np.pi / COUNTS / factor,
               "ls": s["scale_um"] * 1e-3 / factor}
    chans = [ChannelObject("DAQ", c, v, properties={**p, "unit_string": unit})
             for c, v in in_unit.items() if c == column]
    chans += [ChannelObject("DAQ", c, s[k], properties=p) for c, k in
              (("ai0", "r"), ("ai1", "ic"), ("enc", "counts"), ("ls", "scale_um")) if c != column]
    with TdmsWriter(tmp_path / "w.tdms") as w:
        w.write_segment([*chans, ChannelObject("TCP", "x", s["tcp_mm"], properties=p)])
    key = {"enc": "motor_angle_rad", "ls": "scale_mm", "ai1": "current_cmd_A"}[column]
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        check_sweep(read_sweep_tdms(tmp_path / "w.tdms", {**MAP, key: (f"DAQ/{column}",
                                                                       factor)}), s)
    if factor == 1.0:
        return
    with pytest.raises(InputError, match=rf"'DAQ/{column}' is in {unit} \(unit_string\) "
                                         rf"but is mapped to {key} with no factor; .*"
                                         rf"\(\"DAQ/{column}\", {factor:.12g}\)"):
        read_sweep_tdms(tmp_path / "w.tdms", {**MAP, key: f"DAQ/{column}"})


@pytest.mark.parametrize("given", [0.0174533, 0.0174532925199])
def test_the_factor_as_printed_or_to_six_digits_is_taken(given):
    """The refusal of a channel in degrees said to map it with 0.0174533, and refused that
    factor in turn as not the degree's."""
    from tcpmm.io.declared import check_declared

    check_declared("motor_angle_rad", "enc", given, "deg", "unit_string", "f.tdms", True)
    with pytest.raises(InputError, match=r"with the factor 0\.01745;"):
        check_declared("motor_angle_rad", "enc", 0.01745, "deg", "unit_string", "f.tdms", True)


@pytest.mark.parametrize("unit", ["Volts", "V", "counts"])
def test_tdms_unit_string_of_another_kind_is_read_as_it_stands_and_said(tmp_path, unit):
    s = signals()
    p = {"wf_increment": 1 / FS, "wf_start_offset": 0.0}
    chans = [ChannelObject("DAQ", "ai0", s["r"], properties=p),
             ChannelObject("DAQ", "ai1", s["ic"], properties={**p, "unit_string": unit}),
             ChannelObject("DAQ", "enc", s["counts"], properties=p),
             ChannelObject("DAQ", "ls", s["scale_um"], properties=p),
             ChannelObject("TCP", "x", s["tcp_mm"], properties=p)]
    with TdmsWriter(tmp_path / "v.tdms") as w:
        w.write_segment(chans)
    with pytest.warns(InputWarning, match=rf"'DAQ/ai1' is in {unit} \(unit_string\), a unit "
                                          r"tcpmm does not convert to A: it is read "
                                          r"unconverted"):
        check_sweep(read_sweep_tdms(tmp_path / "v.tdms", MAP), s)


def test_mat_unit_in_a_name_is_warned_and_struct_arrays_addressed(tmp_path):
    """A variable named t_ms mapped to time_s without a factor gave a sample rate of
    8 Hz without a word; a 1x2 struct array had no syntax and a hint that named the
    struct as if it were the answer."""
    s = signals()
    run = {"t_ms": s["t"] * 1e3, "exc": s["r"], "icmd": s["ic"], "enc": s["counts"],
           "ls": s["scale_um"]}
    other = {**run, "exc": 2 * s["r"]}
    scipy.io.savemat(tmp_path / "r.mat", {"runs": np.array([other, run], dtype=object)})
    vmap = {"time_s": "runs(2).t_ms", "excitation_A": "runs(2).exc",
            "current_cmd_A": "runs(2).icmd",
            "motor_angle_rad": ("runs(2).enc", 2 * math.pi / COUNTS),
            "scale_mm": ("runs(2).ls", 1e-3)}
    with pytest.warns(UserWarning, match=r"'runs\(2\).t_ms' is in ms \(its name\)"):
        read_sweep_mat(tmp_path / "r.mat", vmap)
    vmap["time_s"] = ("runs(2).t_ms", 1e-3)
    rec = read_sweep_mat(tmp_path / "r.mat", vmap)
    check_sweep(rec, s, tcp=False)
    with pytest.raises(InputError, match=r"'runs' is a struct array of 2 elements; "
                                         r"address one as runs\(k\).field"):
        read_sweep_mat(tmp_path / "r.mat", {k: (v.replace("(2)", "") if isinstance(v, str)
                                                else (v[0].replace("(2)", ""), v[1]))
                                            for k, v in vmap.items()})
    with pytest.raises(InputError, match=r"'runs\(3\)': the struct array has 2 elements"):
        read_sweep_mat(tmp_path / "r.mat", {**vmap, "excitation_A": "runs(3).exc"})


@pytest.mark.parametrize("key, unit, factor", [
    ("scale_mm", "m", 1e3), ("scale_mm", "um", 1e-3), ("scale_mm", "µm", 1e-3),
    ("tcp_mm", "in", 25.4), ("time_s", "ms", 1e-3), ("time_s", "us", 1e-6),
    ("current_cmd_A", "mA", 1e-3), ("excitation_A", "A", 1.0),
    ("motor_angle_rad", "deg", math.pi / 180), ("motor_angle_rad", "rev", 2 * math.pi),
    ("scale_mm", "counts", None), ("time_s", "m", None), ("current_cmd_A", "", None),
    ("motor_angle_rad", "Degrees", math.pi / 180), ("motor_angle_rad", "Radians", 1.0),
    ("scale_mm", "Millimetres", 1.0), ("scale_mm", "µm", 1e-3), ("time_s", "Seconds", 1.0),
    ("time_s", "Milliseconds", 1e-3), ("time_s", "µs", 1e-6), ("current_cmd_A", "Amps", 1.0),
    ("current_cmd_A", "MILLIAMPS", 1e-3), ("current_cmd_A", "Volts", None),
    ("scale_mm", "Seconds", None), ("motor_angle_rad", "turns", 2 * math.pi)])
def test_declared_unit_factors(key, unit, factor):
    from tcpmm.io.declared import factor_for, name_unit

    got = factor_for(key, unit)
    assert got == (None if factor is None else pytest.approx(factor, rel=1e-15))
    assert name_unit("meas.t_ms") == "ms" and name_unit("data(:,2)") is None
    assert name_unit("I_cmd") == "cmd" and factor_for("current_cmd_A", "cmd") is None
