"""A dead TCP channel and a motor angle wrapped to one turn, refused as the bundle is
read. Before, a tcp_mm of zeros was refused after the columns' gates as a "physically
suspect model, tcp_mm / scale_mm = nan ... a column swapped", and an angle within one
turn (0 to 2 pi) as a swapped column or a wrong lead_mm: neither named the fix."""

import shutil

import numpy as np
import pandas as pd
import pytest

from conftest import bench_path
from tcpmm.errors import InputError
from tcpmm.io.bundle import read_bundle


def _bundle(tmp_path, change):
    """Bench C's bundle with its X sweep as ``change(frame)`` writes it [-]."""
    folder = tmp_path / "bundle"
    shutil.copytree(bench_path("c") / "bundle", folder)
    f = folder / "X" / "sweep.csv"
    d = pd.read_csv(f)
    change(d)
    d.to_csv(f, index=False, float_format="%.9f")
    return folder, d


@pytest.mark.parametrize("value", [0.0, 12.5])
def test_a_constant_tcp_column_is_refused_as_recorded_nothing(tmp_path, value):
    folder, _ = _bundle(tmp_path, lambda d: d.__setitem__("tcp_mm", value))
    with pytest.raises(InputError) as refused:
        read_bundle(folder)
    e = refused.value
    assert e.file.endswith("sweep.csv") and "X" in e.file and e.column == "tcp_mm"
    assert "recorded nothing" in e.message and f"({value:g} mm)" in e.message
    assert "delete the tcp_mm column" in e.message and "again" in e.message
    assert "swapped" not in str(e)


def test_a_motor_angle_wrapped_to_one_turn_is_refused_at_its_first_jump(tmp_path):
    def wrap(d):
        d["motor_angle_rad"] = np.mod(d["motor_angle_rad"], 2 * np.pi)

    folder, d = _bundle(tmp_path, wrap)
    first = int(np.flatnonzero(np.abs(np.diff(d["motor_angle_rad"].to_numpy())) > np.pi)[0])
    with pytest.raises(InputError) as refused:
        read_bundle(folder)
    e = refused.value
    assert e.file.endswith("sweep.csv") and e.column == "motor_angle_rad"
    assert e.line == first + 3  # the header is line 1, the jump's second sample the next
    assert "Unwrap" in e.message and "lead" not in e.message.replace("lead_mm", "")


def test_a_genuine_glitch_of_more_than_pi_is_no_wrap(tmp_path):
    from tcpmm.io.recordfaults import refuse_wrapped_angle

    folder, _ = _bundle(tmp_path, lambda d: None)
    b = read_bundle(folder)
    rec, cfg = b.axes["X"].sweep, b.machine.axes["X"]
    th = rec.motor_angle_rad.copy()
    th[1000:] += 5.0  # a jump of 5 rad: no whole turn, so another check's
    refuse_wrapped_angle(type("R", (), {"motor_angle_rad": th, "source": None})(), cfg)
