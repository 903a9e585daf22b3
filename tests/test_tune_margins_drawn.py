"""The proposal's margins over the machines drawn from an identified model's uncertainty."""

import json

import pytest

from tcpmm.cli import main
from tcpmm.model import AxisUncertainty


@pytest.fixture(scope="module")
def identified(vmc, tmp_path_factory):
    from tcpmm import save_model

    m = vmc.model_copy(update={"axes": {n: a.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.05 * a.mechanics.M_t})) for n, a in vmc.axes.items()}})
    path = tmp_path_factory.mktemp("m") / "m.yaml"
    save_model(m, path)
    return path


def test_the_margins_met_carry_their_range_over_the_draws(identified, capsys):
    """`tcpmm tune` said the margins met on the model alone (velocity phase margin 45.1
    deg), while the true machines with the proposal reach 44.4 deg (bench D's Y): the
    model is identified, not known, and the draws it already ran the path on say how far
    the margins may be off."""
    assert main(["tune", str(identified), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)
    for name, axis in got["axes"].items():
        model = axis["margins_after"]["velocity"]["phase_margin_deg"]
        drawn = axis["margins_after_drawn"]["velocity"]
        low, high = drawn["phase_margin_deg"]
        assert drawn["draws"] == 8 and low < high and model > 0, (name, drawn)
        assert 0 <= drawn["missed"] <= 8
        # "met" is met on the model and on every draw: it said true where the console
        # said "NOT MET on 6 of 8 machines drawn", and a script reading it took the proposal
        assert axis["met"] == (axis["met_on_model"] and axis["draws_not_met"] == 0), axis
    missed = {n: a["draws_not_met"] for n, a in got["axes"].items() if a["draws_not_met"]}
    assert missed and not any(got["axes"][n]["met"] for n in missed)
    assert main(["tune", str(identified)]) == 0
    text = capsys.readouterr().out
    assert "after, 8 draws" in text
    assert "on the model" in text and "machines drawn from its uncertainty" in text
    for n, k in missed.items():
        assert any(line.startswith(f"axis {n}: ") and f"NOT MET on {k} of 8 machines" in line
                   for line in text.splitlines()), (n, k)


def test_a_model_without_uncertainty_says_met_alone(vmc):
    from tcpmm.whatif.tuning_draws import drawn_margins, margins_missed

    assert drawn_margins(vmc, vmc, 6.0, 45.0) is None and margins_missed(None) == 0


def test_the_draws_missed_are_counted_once_whichever_loops_miss():
    """The heading counted the larger of the loops' misses: a velocity loop short on
    draws 0 and 1 and a position loop short on draw 2 read "NOT MET on 2 of 8". Each
    draw is counted once, whichever loops miss on it."""
    from tcpmm.whatif.tuning_draws import margins_missed

    drawn = {"velocity": {"draws": 8, "missed": 2, "missed_draws": [0, 1]},
             "position": {"draws": 8, "missed": 2, "missed_draws": [1, 2]}}
    assert margins_missed(drawn) == 3
    assert margins_missed({"velocity": {"draws": 8, "missed": 0, "missed_draws": []}}) == 0
