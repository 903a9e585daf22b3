"""``tcpmm tune``: proposals meet the margins, stay stable and improve the circle."""

import json

import numpy as np
import pytest

from tcpmm.cli import main
from tcpmm.io.modelfile import read_machine
from tcpmm.servo.margins import axis_margins
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import sampled_spectral_radius
from tcpmm.tuning import polyline_distance, tune_and_predict

GM, PM = 6.0, 45.0


def _meets(mech, servo):
    return (all(m.meets(GM, PM) for m in axis_margins(mech, servo).values())
            and sampled_spectral_radius(mech, servo) < 1.0)


def test_resonant_axes_get_a_notch_meet_the_margins_and_trace_a_better_circle(vmc):
    """A soft motor coupling (K_L / 4) puts a torsion mode of damping 0.001 near 370 Hz
    (X) and 324 Hz (Y); with a computation delay, a current loop and a differenced
    encoder it holds the velocity gain near 0.1 A s/rad. The proposal notches it."""
    axes = {}
    for n in "XY":
        a = vmc.axes[n]
        mech = a.mechanics.scaled(K_L=0.25)
        w_c = 0.08 * mech.K_tc / mech.J_total
        servo = ServoParams.create(**{**a.servo.model_dump(), "delay_samples": 1,
                                      "current_bandwidth_hz": 2000.0,
                                      "velocity_feedback": "difference", "K_vp": 0.08,
                                      "K_vi": 0.08 * w_c / 4})
        axes[n] = a.replace(mechanics=mech, servo=servo)
    m = vmc.model_copy(update={"axes": axes})
    res = tune_and_predict(m, GM, PM)
    for n, t in res.axes.items():
        mech = axes[n].mechanics
        assert t.met and _meets(mech, t.after)
        notch = [f for f in t.after.filters if f.type == "notch"]
        assert len(notch) >= 1
        assert t.after.K_vp > 5 * t.before.K_vp
    for d in ("ccw", "cw"):
        assert res.path_after[d]["contour_error_um"] < 0.5 * res.path_before[d]["contour_error_um"]


def test_tune_builtin_from_the_command_line(capsys, tmp_path):
    out = tmp_path / "tuned.yaml"
    code = main(["tune", "builtin:vmc", "--margins", "6dB,45deg", "-o", str(out), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert code == 0
    tuned = read_machine(out)
    for n, a in tuned.axes.items():
        assert data["axes"][n]["met"]
        assert _meets(a.mechanics, a.servo)
    for d in ("ccw", "cw"):
        assert (data["path_after_um"][d]["contour_error_um"]
                < data["path_before_um"][d]["contour_error_um"])


@pytest.mark.parametrize("text", ["6,45", "6dB", "-6dB,45deg", "6dB,95deg", "six dB,45deg"])
def test_bad_margins_are_errors(capsys, tmp_path, text):
    out = tmp_path / "t.yaml"
    assert main(["tune", "builtin:vmc", "--margins", text, "-o", str(out)]) == 2
    assert "--margins" in capsys.readouterr().err
    assert not out.exists()


def test_polyline_distance_of_an_offset_line():
    t = np.linspace(0, 1, 500)
    path = np.column_stack([t, 2 * t])
    normal = np.array([2.0, -1.0]) / np.sqrt(5)
    pts = path + 3e-6 * normal
    np.testing.assert_allclose(polyline_distance(pts[10:-10], path[10:-10]), 3e-6, rtol=1e-9)


def test_result_shares_the_protocol(vmc, tmp_path):
    import tcpmm
    from tcpmm.servo.tune import AxisTuning
    from tcpmm.tuning import TuneResult

    a = vmc.axes["X"]
    m = axis_margins(a.mechanics, a.servo)
    res = TuneResult(vmc, {"X": AxisTuning(a.servo, a.servo, m, m, True)},
                     {"ccw": {"spike_um": 1.0}}, {"ccw": {"spike_um": 0.5}})
    tab = res.to_pandas()
    assert set(tab["axis"]) == {"X", "path"} and len(tab) > 10
    json.dumps(res.to_dict())
    fig = res.plot(path=tmp_path / "t.png")
    assert fig.axes and (tmp_path / "t.png").stat().st_size > 0
    assert tcpmm.tune_servos is tune_and_predict
