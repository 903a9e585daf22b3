"""Bad input to the flat public API (``tcpmm.*``) is an :class:`InputError` that names the
argument, the value and the fix, never an error from inside or a silent wrong result; and
every result's ``to_dict`` is JSON as ``--json`` prints it."""

import json
import math
import warnings

import pytest

import tcpmm
from tcpmm.errors import InputError, InputWarning
from tcpmm.model import AxisUncertainty


@pytest.fixture(scope="module")
def small_circle():
    """A 10 mm circle that starts at quadrant point A: its spike A is undefined."""
    return tcpmm.circle_command(0.01, 0.05)


@pytest.fixture(scope="module")
def uncertain(vmc):
    """The built-in machine with an uncertainty of nothing: a spread's draws are it."""
    return vmc.model_copy(update={"axes": {
        n: a.replace(uncertainty=AxisUncertainty()) for n, a in vmc.axes.items()}})


def test_a_spread_dict_is_json_with_a_missing_spike_null(uncertain, small_circle):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = tcpmm.circle_spread(uncertain, small_circle, 0.01, n=10, floors=None).to_dict()
    json.dumps(d, allow_nan=False)
    assert d["spikes"][0]["point"] == "A" and d["spikes"][0]["spike_um"] is None


def test_json_ready_turns_what_is_not_finite_into_none():
    from tcpmm.result import json_ready

    assert json_ready({"a": [1.0, math.nan, (math.inf, "x")], "b": 2}) == {
        "a": [1.0, None, [None, "x"]], "b": 2}


@pytest.mark.parametrize("gm, pm", [(6, 200), (-6, 45), (0, 45), (41, 45), (6, 90),
                                    (math.nan, 45), ("6", 45), (None, 45)])
def test_tune_servos_refuses_margins_the_command_line_refuses(vmc, small_circle, gm, pm):
    with pytest.raises(InputError, match=r"gm_db=.*pm_deg=.*\(0, 40\] dB.*\(0, 90\) deg"):
        tcpmm.tune_servos(vmc, gm_db=gm, pm_deg=pm, command=small_circle)


def test_tune_servos_warns_of_a_phase_margin_in_radians(vmc):
    from tcpmm.servo.tune import check_margins

    with pytest.warns(InputWarning, match="radians, give pm_deg=45.8"):
        check_margins(6, 0.8)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_margins(6, 45)


def test_a_compensation_dict_is_json_with_a_missing_spike_null(vmc, small_circle):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = tcpmm.compensate(vmc, small_circle, draws=0, radius_m=0.01).to_dict()
    json.dumps(d, allow_nan=False)
    assert d["scores"]["before"]["circle"]["passes"][0]["spikes_um"]["A"] is None


@pytest.mark.parametrize("kw, said", [({"noise_m": math.nan}, "noise_m must be a finite"),
                                      ({"noise_m": -1e-6}, "noise_m must be 0 or more"),
                                      ({"seed": -1}, "seed must be a whole number"),
                                      ({"seed": 1.5}, "seed must be a whole number")])
def test_virtual_run_refuses_bad_noise_and_seed(vmc, small_circle, kw, said):
    with pytest.raises(InputError, match=said):
        tcpmm.virtual_run(vmc, small_circle, **kw)


@pytest.mark.parametrize("kw, said", [({"axes": ("Q",)}, r"no axis Q \(it has X, Y, Z\)"),
                                      ({"axes": ()}, "none named"),
                                      ({"axes": ("X",), "seed": -1}, "seed must be a whole")])
def test_virtual_bundle_refuses_an_unknown_axis_and_a_bad_seed(vmc, tmp_path, kw, said):
    with pytest.raises(InputError, match=said):
        tcpmm.virtual_bundle(vmc, tmp_path / "b", **kw)
    assert not (tmp_path / "b").exists()


@pytest.fixture(scope="module")
def small_run(vmc, small_circle):
    return tcpmm.simulate(vmc, small_circle)


def test_analyse_circle_takes_a_run_file_and_its_table(small_run, tmp_path):
    import pandas as pd

    small_run.write_csv(tmp_path / "run.csv")
    want = tcpmm.analyse_circle(tcpmm.read_run(tmp_path / "run.csv"), 0.01).to_dict()
    assert tcpmm.analyse_circle(tmp_path / "run.csv", 0.01).to_dict() == want
    assert tcpmm.analyse_circle(str(tmp_path / "run.csv"), 0.01).to_dict() == want
    assert tcpmm.analyse_circle(pd.read_csv(tmp_path / "run.csv"), 0.01).to_dict() == want
    assert tcpmm.analyse_circle(small_run.to_pandas(), 0.01).to_dict()["passes"]


@pytest.mark.parametrize("run", [None, 5, [1.0, 2.0]])
def test_analyse_circle_refuses_what_is_no_run(run):
    with pytest.raises(InputError, match="run must be a Run, a run file's path or its table"):
        tcpmm.analyse_circle(run, 0.01)


@pytest.mark.parametrize("sensors, said", [(("TCP",), None), ("tcp", None),
                                           (("foo",), "'foo' is no sensor"),
                                           ("tpc", "'tpc' is no sensor .did you mean 'tcp'"),
                                           ((), "no sensor named")])
def test_analyse_circle_reads_sensor_names_or_names_the_sensors(small_run, sensors, said):
    if said is None:
        res = tcpmm.analyse_circle(small_run, 0.01, sensors=sensors)
        assert set(res.passes[0].sensors) == {"tcp"}
        return
    with pytest.raises(InputError, match=f"{said}.*give (one|some) of cmd, motor, scale, tcp"):
        tcpmm.analyse_circle(small_run, 0.01, sensors=sensors)


def test_spread_and_verdict_name_the_sensors(vmc, uncertain, small_circle):
    with pytest.raises(InputError, match="'foo' is no sensor; give one of cmd, motor"):
        tcpmm.circle_spread(uncertain, small_circle, 0.01, n=10, sensor="foo")
    with pytest.raises(InputError, match="'foo' is no sensor; give one of cmd, motor"):
        tcpmm.prediction_verdict(vmc, tests=[tcpmm.CircleTest("s", small_circle, 0.01)],
                                 sensor="foo")


@pytest.mark.parametrize("centre", [(0.0, 0.0, 5.0), 0, (0.0, math.nan), ("0", "0")])
def test_a_circle_centre_is_two_finite_coordinates(small_run, centre):
    with pytest.raises(InputError, match="centre_m must be two finite coordinates in m"):
        tcpmm.analyse_circle(small_run, 0.01, centre_m=centre)
    with pytest.raises(InputError, match="centre_m must be two finite coordinates in m"):
        tcpmm.compare(small_run, small_run, radius_m=0.01, centre_m=centre)
    with pytest.raises(InputError, match="centre_m must be two finite coordinates in m"):
        tcpmm.circle_command(0.01, 0.05, centre_m=centre)


@pytest.mark.parametrize("radius", [None, "0.01", -0.01, math.inf, True])
def test_a_circle_radius_is_a_positive_number(small_run, radius):
    with pytest.raises(InputError, match="radius_m must be"):
        tcpmm.analyse_circle(small_run, radius)
    with pytest.raises(InputError, match="radius_m must be"):
        tcpmm.compare(small_run, small_run, radius_m=radius if radius is not None else "x")
    with pytest.raises(InputError, match="radius_m must be"):
        tcpmm.circle_command(radius, 0.05)


def test_a_circle_of_metres_is_taken_for_millimetres_and_warned_of():
    with pytest.warns(InputWarning, match=r"radius_m=35: .*for 35 mm give radius_m=0.035"):
        tcpmm.circle_command(35, 5000 / 60000, turns=0.02, feed_in=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        tcpmm.circle_command(1.0, 0.05, turns=0.02, feed_in=False)


@pytest.mark.parametrize("kw, said", [({"draws": -1}, "draws must be a whole number of at "
                                       "least 0, got -1"),
                                      ({"draws": 1.5}, "draws must be a whole number"),
                                      ({"seed": -1}, "seed must be a whole number")])
def test_compensate_refuses_negative_draws(vmc, small_circle, kw, said):
    with pytest.raises(InputError, match=said):
        tcpmm.compensate(vmc, small_circle, radius_m=0.01, **{"draws": 0, **kw})


@pytest.mark.parametrize("call, said", [
    (lambda m, c, r: tcpmm.paper_circle_command(turns="1"), "turns must be a finite number"),
    (lambda m, c, r: tcpmm.simulate(m, c, record_period_s="0.001"),
     "record_period_s must be a finite number in s"),
    (lambda m, c, r: tcpmm.simulate(m, c, record_period_s=0.0), "record_period_s must be above"),
    (lambda m, c, r: tcpmm.contour_error(r, plane=5), "plane '5' must be two different axes"),
    (lambda m, c, r: tcpmm.program_to_command("G1 X10 F1000\n", start_position_m=0),
     r"start_position_m must be three finite coordinates \(X, Y, Z\) in m"),
    (lambda m, c, r: tcpmm.simulate(None, c), "machine must be a Machine, a model file's path"),
    (lambda m, c, r: tcpmm.simulate(m, c.to_pandas()), "command must be a Command, an NC prog"),
    (lambda m, c, r: tcpmm.as_command(c.to_pandas()), "command must be a Command, an NC prog"),
    (lambda m, c, r: tcpmm.compensate(m, c.to_pandas(), draws=0),
     "command must be a Command, an NC prog"),
    (lambda m, c, r: tcpmm.load_model(None), "source must be a Machine, a model file's path"),
    (lambda m, c, r: tcpmm.save_model("x", "m.yaml"), "machine must be a Machine"),
    (lambda m, c, r: tcpmm.save_model(m, None), "path must be a file's path"),
    (lambda m, c, r: tcpmm.read_run(None), "path must be a file's path"),
    (lambda m, c, r: tcpmm.circle_diagnostics(r), "result must be a CircleResult"),
    (lambda m, c, r: tcpmm.contour_error(r, command=c.to_pandas()), "command must be a Command"),
    (lambda m, c, r: tcpmm.prediction_verdict(m, tests=c), "tests must be a list of CircleTest"),
])
def test_a_wrong_kind_of_argument_is_named(vmc, small_circle, small_run, call, said):
    with pytest.raises(InputError, match=said):
        call(vmc, small_circle, small_run)


@pytest.mark.parametrize("kw, said", [
    ({"delay_s": -1.0}, "delay_s .* must be 0 or more"),
    ({"delay_s": "abc"}, "delay_s .* must be a finite number"),
    ({"max_poles": 0}, "max_poles must be a whole number of at least 1"),
    ({"poles": 2.5}, "poles must be a whole number"),
    ({"min_coherence": 1.5}, "min_coherence must be within 0 and 1")])
def test_fit_frf_names_the_argument_at_fault(kw, said):
    """A delay of -1 s, a delay of text or a largest pole count of 0 were refused as "813
    bins are too few to fit any order; widen the band"."""
    from conftest import BENCH_DATA

    frf = tcpmm.read_frf(BENCH_DATA / "sinumerik" / "freq_trace.XML")
    with pytest.raises(InputError, match=said):
        tcpmm.fit_frf(frf, **kw)
    with pytest.raises(InputError, match="frf must be a measured response"):
        tcpmm.fit_frf("freq_trace.XML")
