"""A jerk limit given to ``tcpmm compensate`` on a model whose interpolator is a trapezoid
(as ``tcpmm identify`` makes them): the NC program is planned with an S-curve at the jerk
given less the headroom, so that the command written keeps it (:func:`tcpmm.compensate.
headroom.within_bounds`)."""

import pytest

from tcpmm.cli import main
from tcpmm.path import InterpolatorSettings, read_command_csv
from tcpmm.path.limits import OVER_SHARE, peak
from tcpmm.path.program import program_to_command

J = 50.0  # the axes' jerk given [m/s^3]
#: a line into a CCW circle of R 35 mm at F5000, then out: the trapezoid's ramps and the
#: tangent joins, both beyond J where nothing plans them within it
LEADIN = "G21 G17 G90\nG0 X35 Y-20\nG1 X35 Y0 F5000\nG3 X35 Y0 I-35 J0\nG1 X35 Y20\nM30\n"
#: the trapezoid the model's interpolator plans with [-]
TRAPEZOID = {"period_s": 1e-3, "profile": "trapezoid", "path_accel_m_per_s2": 1.0}


@pytest.fixture(scope="module")
def trapezoid_model(tmp_path_factory):
    """The built-in machine with a trapezoid interpolator of 1 m/s^2, no transition
    limit [-]."""
    from tcpmm import builtin_machine, save_model

    path = tmp_path_factory.mktemp("model") / "trapezoid.yaml"
    save_model(builtin_machine().model_copy(update={"interpolation": TRAPEZOID}), path)
    return path


def compensated(model, tmp_path, *extra) -> tuple:
    """The command ``tcpmm compensate`` writes of :data:`LEADIN` and its largest axis
    jerk, from rest, at its own period [m, m/s^3]."""
    prog, out = tmp_path / "leadin.nc", tmp_path / "c.csv"
    prog.write_text(LEADIN)
    assert main(["compensate", str(model), "--gcode", str(prog), "-o", str(out),
                 "--draws", "0", "--iterations", "3", *map(str, extra)]) == 0
    cmd = read_command_csv(out)
    return out, max(peak(x, 3, cmd.period_s, from_rest=True) for x in cmd.positions.values())


def test_a_jerk_given_is_kept_on_a_trapezoid_model(tmp_path, capsys, trapezoid_model):
    """The command written went to 933 m/s^3 against the 50 given: the trapezoid planned
    with headroom steps the acceleration by 0.75 m/s^2 within 1 ms at every ramp (750
    m/s^3 for a sample, the correction the rest), and the warning put it down to the
    model's interpolator. Planned with an S-curve at 37.5 along the path and at the joins,
    the correction adding no more than the headroom, it keeps
    50, and the console says which profile and why. The tolerance is the one the warnings
    use (``OVER_SHARE``, a command file's rounding)."""
    _, most = compensated(trapezoid_model, tmp_path, "--jerk-m-per-s3", J)
    said = capsys.readouterr()
    assert most <= J * (1 + OVER_SHARE), most
    assert "jerk up to" not in said.err, said.err
    assert ("planned with an S-curve, 37.5 m/s³ along the path and 37.5 at block "
            "transitions" in said.out), said.out


def test_without_a_jerk_the_trapezoid_plan_is_kept(tmp_path, capsys, trapezoid_model):
    """Without ``--jerk-m-per-s3`` the program is planned as before, with the model's
    trapezoid at 0.75 of its acceleration: the plan written with ``--reference-out`` is
    that one to the bit, its ramps beyond 50 m/s^3, and nothing speaks of an S-curve."""
    from tcpmm.compensate.headroom import DEFAULT_HEADROOM, planned_settings
    from tcpmm.path import write_command_csv

    ref, own = tmp_path / "ref.csv", tmp_path / "own.csv"
    _, most = compensated(trapezoid_model, tmp_path, "--reference-out", ref)
    assert "S-curve" not in capsys.readouterr().out
    write_command_csv(program_to_command(LEADIN, planned_settings(
        InterpolatorSettings(**TRAPEZOID), DEFAULT_HEADROOM)), own)
    assert ref.read_bytes() == own.read_bytes()
    assert most > 10 * J


def test_as_programmed_the_warning_names_the_remedy(tmp_path, capsys, trapezoid_model):
    """``--headroom 0`` writes the program as programmed, the trapezoid's ramps beyond the
    jerk given: the warning says so, and that a headroom above 0 plans it with an S-curve
    within it."""
    _, most = compensated(trapezoid_model, tmp_path, "--jerk-m-per-s3", J, "--headroom", 0)
    err = capsys.readouterr().err
    assert most > 10 * J
    assert "plans it with no jerk limit" in err, err
    assert "--headroom above 0: it is then planned with an S-curve" in err, err

