"""Identification judged on machines of an independent simulator (``../shared/data``).

Machines C, D and E are identified from their ``bundle/`` alone and predict the four
measured circles of each (R 35 mm, F5000 and F10000, CCW and CW). The target is every TCP
reversal spike within 1 um and the TCP contour error within 0.5 um of the measurement; the
noise floor of the comparison is about 0.1 um, and the true parameters in the model reach
it (``test_sim_structure.py``). Where the identified model does not meet the target today
the case is marked as an expected failure with what was measured, so that a change that
meets it shows up (strict). The measured figures and what limits them are in
docs/validation/reference_machines.md.
"""

import dataclasses
import warnings

import numpy as np
import pytest

from conftest import SWEEP_SAMPLES, bench_path, bench_x_alone, refusal
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.compare import compare_circles
from tcpmm.errors import InputWarning
from tcpmm.ident.physical.skew import SKEW_MIN_SAMPLES
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.runfile import read_run_csv
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path.commandfile import read_command_csv
from tcpmm.sim.simulate import simulate

R = 0.035  # [m]
CASES = ("ccw", "cw", "ccw_fast", "cw_fast")
SPIKE_TARGET_UM, CONTOUR_TARGET_UM = 1.0, 0.5

#: Cases that miss the target today, and by how much (spike / contour, um): by letter and
#: kind, or by letter, kind and case.
KNOWN: dict = {}

#: The guideway share of every axis of machines C, D, E (true 0.28-0.66) comes from the
#: TCP deflection of the sweep within 0.007 of the truth (standard deviations
#: 0.002-0.006); the friction runs' 1 um scales left two of them open and put another
#: 0.07 off. Tolerance 0.03: three standard deviations.
SHARE_TOL = 0.03


@pytest.fixture(scope="module")
def identified(once):
    """``identified(letter)``: the identification of reference machine ``letter`` from its
    bundle, once for the whole run [-]."""

    def get(letter):
        def make():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                # the verdict is judged by the tests that need it, on the measured circles
                return identify_bundle(read_bundle(bench_path(letter) / "bundle"),
                                       verdict=False)

        return once(f"bench_{letter}", make)

    return get


def test_axes_identified_side_by_side_give_the_same_bits(identified):
    """Machine D's two axes identified at once in processes of their own: the
    identification of one axis after the other (the shared one), every number to the bit
    (its dictionary as JSON, where NaN is text; the verdict's varied models, run side by
    side the same way, are left out here)."""
    import json

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        two = identify_bundle(read_bundle(bench_path("d") / "bundle"), jobs=2, verdict=False)

    def dump(idn):
        return json.dumps({k: v for k, v in idn.to_dict().items() if k != "verdict"},
                          sort_keys=True, default=repr)

    assert dump(two) == dump(identified("d"))
    assert two.machine == identified("d").machine


#: :func:`tcp_row` by machine and case: the spike and contour tests of a case read the same
#: prediction [-].
_ROWS: dict = {}


def tcp_row(identified, letter, case):
    """The TCP row of the comparison of machine ``letter``'s measured circle ``case`` with
    its identified model's, and the model's run, once per module [-]."""
    if (letter, case) not in _ROWS:
        d = bench_path(letter)
        run = simulate(identified(letter).machine,
                       read_command_csv(d / f"circle_{case}_cmd.csv"))
        meas = analyse_circle(read_run_csv(d / f"circle_{case}_meas.csv"), R)
        pred = analyse_circle(run, R)
        _ROWS[letter, case] = (next(r for r in compare_circles(meas, pred).rows
                                    if r["sensor"] == "tcp"), run)
    return _ROWS[letter, case]


def known(letter, what, case=None):
    reason = KNOWN.get((letter, what)) or KNOWN.get((letter, what, case))
    return [pytest.mark.xfail(strict=True, reason=reason)] if reason else []


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_identification_passes_its_gates_and_every_axis_moves(letter, identified):
    """No physically absurd parameter (identify_bundle raises on one), and in every
    predicted circle each axis travels the span of its command: none sits stuck."""
    idn = identified(letter)
    for a in idn.machine.axes.values():
        fr = a.friction
        for c in (fr.screw, fr.guideway):
            assert c.fs_pos < 2.0 * c.fc_pos and c.fs_neg < 2.0 * c.fc_neg
    _, run = tcp_row(identified, letter, "ccw")
    for name, r in run.axes.items():
        assert r.scale.max() - r.scale.min() > 0.99 * (r.cmd.max() - r.cmd.min()), name


@pytest.mark.parametrize("letter", ["c", "d", "e", "h", "r05", "r17"])
def test_channels_recorded_in_step_read_no_skew(letter, identified):
    """The independent simulator records every channel in step: no delay of the scale
    against the motor encoder or of the TCP against the scale is called a skew, and each
    reads within half a sample of none."""
    for name, a in identified(letter).axes.items():
        read = {k.frf: k.samples for k in a.channel_skews}
        assert set(read) == {"G_T", "G_tcp"}, (name, read)
        assert not any(k.skewed for k in a.channel_skews), (name, read)
        assert all(abs(v) < SKEW_MIN_SAMPLES for v in read.values()), (name, read)


@pytest.mark.parametrize("column, channel", [("tcp_m", "TCP"), ("scale_m", "scale")])
def test_a_channel_recorded_a_sample_late_is_refused_naming_it(column, channel):
    """Machine D's X with one channel of its sweep shifted a sample late, as a recorder
    whose channels are not sampled together writes it: the fit would take the lag for
    dynamics (the TCP's moved the F5000 spikes by 3 um, the scale's the F10000 ones by
    18 um), so identification refuses, names the channel, how late it reads, and the
    shift that puts it back."""
    refused = refusal(bench_x_alone("d", lambda sw: dataclasses.replace(sw, **{
        column: np.r_[getattr(sw, column)[:1], getattr(sw, column)[:-1]]})))
    first = refused.findings[0]
    assert first.parameter == f"delay of the {channel}", str(first)
    assert len(refused.findings) == 1 or "delay" not in refused.findings[1].parameter
    assert 0.7 < first.value < 1.3, str(first)
    col = "tcp_mm" if channel == "TCP" else "scale_mm"
    assert f"shift the {col} column 1 sample earlier" in str(refused)


def test_a_tcp_device_reading_nine_tenths_of_the_motion_is_refused():
    """Machine R17's X with its TCP column scaled by 0.9 (a probe's scaling, or its
    alignment 26 deg off the axis): the fit took the gain for the structure, and the
    predicted F10000 contour error came out 38 um off. Identification refuses, with the
    gain read against the model below the first mode and the scaling that puts it back."""
    refused = refusal(bench_x_alone(
        "r17", lambda sw: dataclasses.replace(sw, tcp_m=0.9 * sw.tcp_m)))
    (gain,) = [f for f in refused.findings if "TCP device" in f.parameter]
    assert gain.value == pytest.approx(0.9, abs=0.002), str(gain)
    assert "scale tcp_mm by 1.11" in gain.remedy


@pytest.mark.parametrize("letter, case", [
    pytest.param(x, c, marks=known(x, "spikes", c)) for x in "cde" for c in CASES])
def test_tcp_reversal_spikes_within_1um(letter, case, identified):
    row, _ = tcp_row(identified, letter, case)
    worst = max(abs(row[f"spike_{q}_um"]) for q in "BCD")  # A lies on the feed-in
    assert worst < SPIKE_TARGET_UM, worst


@pytest.mark.parametrize("letter, case", [
    pytest.param(x, c, marks=known(x, "contour", c)) for x in "cde" for c in CASES])
def test_tcp_contour_error_within_half_a_micrometre(letter, case, identified):
    row, _ = tcp_row(identified, letter, case)
    assert abs(row["contour_error_um"]) < CONTOUR_TARGET_UM, row["contour_error_um"]


#: Inertias, masses and stiffnesses of machines C, D and E come out within 1.6 % of the
#: truth (most within 0.6 %; D's motor inertia is the widest). With the hold of the
#: current modelled although the 10 kHz records read the held current of the 8 kHz loop
#: themselves, all of them came out 0.4-2.3 % high together. Tolerance 2 %.
INERTIA_TOL = 0.02


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_inertias_and_stiffnesses_are_the_machines_own(letter, identified):
    truth = machine_from_truth(bench_path(letter) / "truth.yaml")
    for name, a in identified(letter).axes.items():
        m, t = a.axis.mechanics, truth.axes[name].mechanics
        for p in ("J_m", "J_L", "K_L", "M_t", "K_t", "M_b", "K_b", "M_h", "K_h"):
            assert getattr(m, p) == pytest.approx(getattr(t, p), rel=INERTIA_TOL), (name, p)


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_the_share_comes_from_the_tcp_deflection_of_the_sweep(letter, identified):
    """Every axis's guideway share is the one its travelling sweep's column deflection
    implies (``tcpmm.ident.friction.sweepforce``), near the truth of the reference simulator;
    its deviation holds the datum between scale and TCP, a step of each sensor (0.03-0.11
    on these machines, 0.002-0.006 from the deflection's scatter alone)."""
    truth = machine_from_truth(bench_path(letter) / "truth.yaml")
    for name, a in identified(letter).axes.items():
        split = a.friction_split
        assert split.source == "sweep", name
        assert 0.0 < split.guideway_share_std < 0.15
        t = truth.axes[name].friction
        true = t.guideway.fc_pos / (t.guideway.fc_pos + t.screw.fc_pos)
        assert abs(split.guideway_share - true) < SHARE_TOL, (name, split.guideway_share, true)


def test_what_the_friction_runs_leave_open_is_measured_in_spikes(identified):
    """Without a TCP record, machine C's Y has only its friction runs, on a 1 um scale at
    speeds locked to its steps: the share stays open and a lost motion of up to three
    standard deviations could hide; identify measures in spikes what each could do (true
    share 0.66, no lost motion)."""
    bundle = read_bundle(bench_path("c") / "bundle")
    y = bundle.axes["Y"]
    y = dataclasses.replace(y, sweep=dataclasses.replace(y.sweep, tcp_m=None))
    bundle = dataclasses.replace(bundle, axes={**bundle.axes, "Y": y})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = identify_bundle(bundle, verdict=False).axes["Y"]
    assert a.friction_split.source == "prior"
    # told once, for the fit kept, not for each refit of the mechanics
    prior = [str(w.message) for w in caught if "prior guideway share" in str(w.message)]
    assert len(prior) == 1 and "Y/friction.csv: axis Y: " in prior[0], prior
    share = a.share_sensitivity
    assert share.shares == (0.05, 0.95) and share.spike_change_m > 0.5e-6
    hidden = a.lost_motion_sensitivity
    assert hidden.lost_motion_m[1] > 0.2e-6 and hidden.spike_change_m > 0.0
    assert identified("d").axes["X"].share_sensitivity is None


def test_a_split_the_runs_leave_open_is_told_once_without_its_estimate():
    """Machine D's X with half its sweep: the FRFs leave the nut stiffness a guess, and
    the refits of the mechanics each read the friction runs with another one. The split
    falls back to the prior share; that is told once, for the fit kept, and the plateaus'
    share, whose standard deviation runs into the thousands, is not given as a number."""
    b = bench_x_alone("d", lambda sw: dataclasses.replace(sw, **{
        f: getattr(sw, f)[:sw.time_s.size // 2] for f in SWEEP_SAMPLES}))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        split = identify_bundle(b, verdict=False).axes["X"].friction_split
    assert split.source == "prior"
    prior = [str(w.message) for w in caught if "prior guideway share" in str(w.message)]
    assert len(prior) == 1, prior
    assert f"{split.estimate.guideway_share:.2f}" not in prior[0], prior


def test_a_standing_sweep_is_named_with_its_cause():
    """Machine C's sweep in torque mode from rest sticks, slips and pre-slides: no part of
    it shows the linear mechanics, and identification says so for each axis."""
    with pytest.warns(InputWarning) as caught:
        identify_bundle(read_bundle(bench_path("c") / "bundle_openloop"), verdict=False)
    said = [str(w.message) for w in caught if "the sweep does not travel" in str(w.message)]
    assert len(said) == 2 and any("axis X:" in s for s in said)
    assert any("axis Y:" in s for s in said)
    assert all("travels at constant speed" in s for s in said)


def test_an_identification_shares_the_result_protocol(tmp_path, identified):
    """``to_pandas`` (the parameters), ``to_dict`` (JSON-ready), ``plot`` returning the
    Bode figure of one axis, and a report folder whose entries are the files written."""
    import json

    from tcpmm.errors import InputError

    idn = identified("d")
    table = idn.to_pandas()
    assert set(table["axis"]) == {"X", "Y"} and {"value", "std"} <= set(table.columns)
    json.dumps(idn.to_dict())
    fig = idn.plot("Y", path=tmp_path / "bode_Y.png")
    assert fig.axes and (tmp_path / "bode_Y.png").stat().st_size > 0
    with pytest.raises(InputError, match="no axis 'Q'"):
        idn.plot("Q")
    files = idn.write_report(tmp_path / "report")
    assert files and all(p.is_file() for p in files.values())


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_a_share_from_the_sweep_carries_its_spread_into_the_model(letter, identified):
    """The model's share uncertainty, which ``tcpmm spread`` draws from, is the sweep
    share's standard deviation (an infinite one drew any share and settled no point)."""
    idn = identified(letter)
    for name, a in idn.axes.items():
        split = a.friction_split
        assert split.source == "sweep", name
        got = idn.machine.axis(name).uncertainty.guideway_share
        assert got == pytest.approx(split.guideway_share_std) and 0 < got < 0.15, name


def _measured_figures(letter):
    """The measured circles that hold a full circle as tests, and their TCP figures."""
    from tcpmm.errors import InputError
    from tcpmm.uncertainty import CircleTest, circle_figures

    d, tests, meas = bench_path(letter), [], {}
    for case in CASES:
        try:
            res = analyse_circle(read_run_csv(d / f"circle_{case}_meas.csv"), R)
        except InputError:  # a lagging circle the analysis does not find whole
            continue
        tests.append(CircleTest(case, read_command_csv(d / f"circle_{case}_cmd.csv"), R))
        meas.update(circle_figures(res, case))
    return tests, meas


@pytest.mark.parametrize("letter", ["c", "d", "e", "h", "r05", "r17"])
def test_a_firm_figure_meets_its_target_and_the_interval_holds_the_measurement(letter, identified):
    """On the measured circles, no figure called firm misses its target, and at least nine
    in ten measured figures lie inside their predicted 90 % interval (the calibration of
    docs/validation/calibration.md). H's Y share, read from a nut deflection of about one
    scale step, is open; the C, D and E models are firm on some."""
    from tcpmm.uncertainty import prediction_verdict

    tests, meas = _measured_figures(letter)
    v = prediction_verdict(identified(letter).machine, tests)
    judged = [(f, abs(meas[(f.test, f.direction, f.figure)] - f.nominal)) for f in v.figures
              if (f.test, f.direction, f.figure) in meas]
    assert len(judged) >= 12
    misses = [f for f, err in judged if f.verdict == "firm" and err > f.target]
    assert not misses, misses
    inside = sum(err <= f.half_width for f, err in judged)
    assert inside >= 0.9 * len(judged), (inside, len(judged))
    if letter in "cde":
        assert any(f.verdict == "firm" for f, _ in judged)
    if letter == "h":
        assert "backlash" in {r["quantity"] for r in v.axes["Y"]["open"]}


def test_a_lost_motion_of_one_scale_step_leaves_the_share_to_the_sweep(identified):
    """Machine H's Y friction runs show 1.6 um of lost motion on a 1 um scale, where the
    machine has none: within two scale steps it is not taken as found, so the travelling
    sweep gives the share (true 0.665 and 0.676: guideway 350 and 450 N against screws of
    0.9 and 1.1 N m on a 32 mm lead), no play is modelled, and the lost motion the runs
    cannot rule out stays open."""
    idn = identified("h")
    for name, truth in (("X", 0.665), ("Y", 0.676)):
        split = idn.axes[name].friction_split
        assert split.source == "sweep" and split.backlash == 0.0
        assert split.guideway_share == pytest.approx(truth, abs=SHARE_TOL)
    assert idn.axes["Y"].friction_split.backlash_at_resolution > 1e-6


def test_the_parameter_table_and_the_summary_say_alike_what_the_data_determine(identified):
    """The screw damping B_L the FRFs do not determine, which the model takes from the
    friction runs with their deviation, read 'not determined' beside a deviation of 0.9 %;
    the motor bearing's B_m, set to 0 without one, read 'determined' in the CSV and not in
    the report. Each says where the model's value comes from, and the table, the summary
    (the report's) and the deviations agree."""
    idn = identified("c")
    table = idn.parameters_table()
    summary = idn.to_dict()["axes"]
    for _, row in table.iterrows():
        undetermined = summary[row["axis"]]["undetermined"]
        assert row["determined"] == (row["parameter"] not in undetermined), row["parameter"]
        if row["from"] == "set":
            assert not row["determined"] and not np.isfinite(row["std"])
        if row["determined"]:
            assert np.isfinite(row["std"]) and row["rel_std_percent"] < 50.0, row["parameter"]
    rows = table.set_index(["axis", "parameter"])
    assert rows.loc[("X", "B_m"), "from"] == "set"
    assert rows.loc[("X", "B_L"), "from"] == "friction runs"
    assert rows.loc[("X", "B_L"), "determined"]


def test_a_sweep_short_of_the_column_mode_does_not_blame_the_tcp_device():
    """Machine C's Y with its sweep cut to the first 4 s (2-10 Hz): the TCP over the scale
    rises towards the column's mode, 1.016 at 3.75 Hz to 1.109 at 10.5 Hz, against a model
    that holds no such mode; the median, 1.064, was read as the device's gain, the model
    refused and the readings to be scaled by 0.94. At zero frequency the ratio reads 1:
    no finding names the TCP device, and the structure the sweep does not reach is left
    open by the verdict."""
    import dataclasses

    from tcpmm.ident.gates.finding import SuspectModelError
    from tcpmm.ident.pipeline import identify_bundle
    from tcpmm.io.bundle import read_bundle

    b = read_bundle(bench_path("c") / "bundle")
    y = b.axes["Y"]
    keep = y.sweep.time_s < y.sweep.time_s[0] + 4.0
    cut = dataclasses.replace(y.sweep, **{k: getattr(y.sweep, k)[keep] for k in SWEEP_SAMPLES})
    short = dataclasses.replace(b, axes={"Y": dataclasses.replace(y, sweep=cut)})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            identify_bundle(short, fmin_hz=3.0, fmax_hz=800.0, verdict=False)
        except SuspectModelError as exc:
            assert not [f for f in exc.findings if "TCP device" in f.parameter], str(exc)
