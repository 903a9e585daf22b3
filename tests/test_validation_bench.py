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

import warnings

import pytest

from conftest import bench_path
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.compare import compare_circles
from tcpmm.errors import InputWarning
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.io.runfile import read_run_csv
from tcpmm.path.commandfile import read_command_csv
from tcpmm.simulate import simulate

R = 0.035  # [m]
CASES = ("ccw", "cw", "ccw_fast", "cw_fast")
SPIKE_TARGET_UM, CONTOUR_TARGET_UM = 1.0, 0.5
_MODELS = {}

#: Cases that miss the target today, and by how much (spike / contour, um).
KNOWN = {
    ("c", "spikes"): "Y's guideway share is not determined by its 1 um scale (prior 0.70, "
                     "true 0.66): spikes 3.5-3.6 um off at F5000, and at F10000 a sign flip "
                     "between lobes that are each within 0.6 um",
    ("e", "spikes"): "X's guideway share is not determined by its 1 um scale (prior 0.70, "
                     "true 0.29; identify warns that it moves the spikes by up to 84 um) "
                     "and Y's comes out 0.26 (true 0.33): spikes 40-43 um off",
    ("e", "contour"): "contour 3.5-9.1 um off, from the same friction split",
    ("d", "contour"): "pre-sliding of the contacts (true 1.5-3.5 um, assumed 0.5 um): "
                      "0.85 um off at F5000",
}


def identified(letter):
    if letter not in _MODELS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _MODELS[letter] = identify_bundle(read_bundle(bench_path(letter) / "bundle"))
    return _MODELS[letter]


def tcp_row(letter, case):
    d = bench_path(letter)
    run = simulate(identified(letter).machine, read_command_csv(d / f"circle_{case}_cmd.csv"))
    meas = analyse_circle(read_run_csv(d / f"circle_{case}_meas.csv"), R)
    pred = analyse_circle(run, R)
    return next(r for r in compare_circles(meas, pred).rows if r["sensor"] == "tcp"), run


def known(letter, what):
    reason = KNOWN.get((letter, what))
    return [pytest.mark.xfail(strict=True, reason=reason)] if reason else []


@pytest.mark.parametrize("letter", ["c", "d", "e"])
def test_identification_passes_its_gates_and_every_axis_moves(letter):
    """No physically absurd parameter (identify_bundle raises on one), and in every
    predicted circle each axis travels the span of its command: none sits stuck."""
    idn = identified(letter)
    for a in idn.machine.axes.values():
        fr = a.friction
        for c in (fr.screw, fr.guideway):
            assert c.fs_pos < 2.0 * c.fc_pos and c.fs_neg < 2.0 * c.fc_neg
    _, run = tcp_row(letter, "ccw")
    for name, r in run.axes.items():
        assert r.scale.max() - r.scale.min() > 0.99 * (r.cmd.max() - r.cmd.min()), name


@pytest.mark.parametrize("letter, case", [
    pytest.param(x, c, marks=known(x, "spikes")) for x in "cde" for c in CASES])
def test_tcp_reversal_spikes_within_1um(letter, case):
    row, _ = tcp_row(letter, case)
    worst = max(abs(row[f"spike_{q}_um"]) for q in "BCD")  # A lies on the feed-in
    assert worst < SPIKE_TARGET_UM, worst


@pytest.mark.parametrize("letter, case", [
    pytest.param(x, c, marks=known(x, "contour") if not (x == "d" and "fast" in c) else [])
    for x in "cde" for c in CASES])
def test_tcp_contour_error_within_half_a_micrometre(letter, case):
    row, _ = tcp_row(letter, case)
    assert abs(row["contour_error_um"]) < CONTOUR_TARGET_UM, row["contour_error_um"]


def test_what_the_records_leave_open_is_measured_in_spikes():
    """Machine C's Y has a 1 um scale on speeds locked to its steps: the share stays open
    and a lost motion of up to three standard deviations could hide; identify measures in
    spikes what each could do (true share 0.66, no lost motion)."""
    a = identified("c").axes["Y"]
    share = a.physical.extra["share_sensitivity"]
    assert share["shares"] == [0.05, 0.95] and share["spike_change_m"] > 5e-6
    hidden = a.physical.extra["lost_motion_sensitivity"]
    assert hidden["lost_motion_m"][1] > 0.2e-6 and hidden["spike_change_m"] > 0.0
    assert "share_sensitivity" not in identified("d").axes["X"].physical.extra


def test_a_standing_sweep_is_named_with_its_cause():
    """Machine C's sweep in torque mode from rest sticks, slips and pre-slides: no part of
    it shows the linear mechanics, and identification says so for each axis."""
    with pytest.warns(InputWarning) as caught:
        identify_bundle(read_bundle(bench_path("c") / "bundle_openloop"))
    said = [str(w.message) for w in caught if "the sweep does not travel" in str(w.message)]
    assert len(said) == 2 and any("axis X:" in s for s in said)
    assert any("axis Y:" in s for s in said)
    assert all("travels at constant speed" in s for s in said)
