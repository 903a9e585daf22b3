"""A run that holds only its command is no measurement: the circular test, the comparison
and the report refuse it by name (exit 2, one line), rather than measuring the command
against the nominal circle and showing every figure 0.00."""

import numpy as np
import pytest

from tcpmm.cli import main

R_MM = 35.0


def _circle_csv(path, sensors=()):
    """A CCW and a CW circle of radius :data:`R_MM`, as a run file with the command and
    the ``sensors`` given (each the command) [mm]."""
    a = np.linspace(0.0, 2.0 * np.pi, 2001)
    a = np.concatenate([a, a[::-1]])
    x, y = R_MM * np.cos(a), R_MM * np.sin(a)
    cols = {"time_s": 1e-3 * np.arange(a.size), "x_cmd_mm": x, "y_cmd_mm": y}
    for s in sensors:
        cols[f"x_{s}_mm"], cols[f"y_{s}_mm"] = x, y
    lines = [",".join(cols)] + [",".join(f"{v:.8f}" for v in row)
                                for row in zip(*cols.values(), strict=True)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _said(capsys) -> str:
    cap = capsys.readouterr()
    return " ".join((cap.out + cap.err).split())


@pytest.mark.parametrize("extra", [[], ["--json"]])
def test_circle_of_the_command_alone_is_refused(tmp_path, capsys, extra):
    run = _circle_csv(tmp_path / "cmd_only.csv")
    assert main(["circle", str(run), "--radius", str(R_MM), *extra]) == 2
    text = _said(capsys)
    assert f"error: {run}: the run has no sensor columns" in text
    assert "<axis>_tcp_mm, <axis>_scale_mm, <axis>_motor_mm" in text
    assert "found: x_cmd_mm, y_cmd_mm" in text and "--sensor cmd" in text
    assert "Traceback" not in text and "circle diagnostics" not in text


def test_circle_of_the_command_is_given_where_asked_for(tmp_path, capsys):
    run = _circle_csv(tmp_path / "cmd_only.csv")
    assert main(["circle", str(run), "--radius", str(R_MM), "--sensor", "cmd"]) == 0
    assert "circle diagnostics (cmd)" in capsys.readouterr().out


def test_a_sensor_of_one_axis_alone_is_no_measurement_of_the_circle(tmp_path, capsys):
    run = _circle_csv(tmp_path / "half.csv", ["tcp"])
    run.write_text(run.read_text().replace("y_tcp_mm", "z_tcp_mm"))
    assert main(["circle", str(run), "--radius", str(R_MM)]) == 2
    text = _said(capsys)
    assert "no sensor columns that both X and Y have" in text and "x_tcp_mm" in text


def test_compare_and_report_refuse_the_command_alone(tmp_path, capsys):
    measured = _circle_csv(tmp_path / "measured.csv", ["scale"])
    bare = _circle_csv(tmp_path / "cmd_only.csv")
    for args in (["compare", measured, bare], ["compare", bare, measured],
                 ["report", "-o", tmp_path / "r.html", "--run", bare]):
        assert main([str(a) for a in args] + ["--radius", str(R_MM)]) == 2, args
        text = _said(capsys)
        assert f"{bare}: the run has no sensor columns" in text, args
        assert "Traceback" not in text
    assert not (tmp_path / "r.html").exists()
    # the same circle with a sensor stands
    assert main(["compare", str(measured), str(measured), "--radius", str(R_MM)]) == 0
