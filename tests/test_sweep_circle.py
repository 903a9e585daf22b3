"""A sweep of the circular test: rows of a feed the circle caps, and refusals by the
names and values the user gave."""

import pandas as pd
import pytest

from tcpmm.cli import main
from tcpmm.model import AxisUncertainty
from tcpmm.whatif.sweep import CircleProgram, Variant, evaluate_variant

#: 5 mm: the interpolator's 1 m/s2 holds it at 4243 mm/min.
SMALL = CircleProgram(radius_m=5e-3, feed_m_per_s=0.05)


def test_a_row_of_a_capped_feed_says_so_and_gives_the_feed_run(vmc):
    """The rows of a feed the circle cannot reach held the figures of the feed it reaches
    with an empty warning: only stderr said so, once, and the table read as the feed asked."""
    asked = evaluate_variant(vmc, SMALL, Variant(values=(("program.feed_mm_per_min", 3000),)))
    capped = evaluate_variant(vmc, SMALL, Variant(values=(("program.feed_mm_per_min", 6000),)))
    assert asked["warning"] == "" and asked["feed_run_mm_per_min"] == pytest.approx(3000, 1e-3)
    assert capped["feed_run_mm_per_min"] == pytest.approx(4243, abs=2)
    assert "the circle's feed 6000 mm/min at R5 mm runs at 4243 mm/min" in capped["warning"]


def test_the_summary_holds_the_feed_run(tmp_path, capsys):
    args = ["sweep", "builtin:vmc", "-p", "program.feed_mm_per_min=3000,6000", "--circle",
            "5,3000", "-o", str(tmp_path / "o"), "--workers", "1"]
    assert main(args) == 0
    capsys.readouterr()
    summary = pd.read_csv(tmp_path / "o" / "summary.csv", keep_default_na=False)
    assert list(summary["feed_run_mm_per_min"].round()) == [3000, 4243]
    assert summary["warning"][0] == "" and "runs at 4243 mm/min" in summary["warning"][1]


@pytest.mark.parametrize(("param", "said"), [
    ("program.feed_mm_per_min=0,1000", "program.feed_mm_per_min must be positive, got 0"),
    ("program.radius_mm=-35,35", "program.radius_mm must be positive, got -35"),
])
def test_a_refused_circle_names_what_the_user_gave(param, said, tmp_path, capsys):
    """The refusal named the circle's SI arguments (feed_m_per_s ... in m/s, got 0.0;
    radius_m ... got -0.035), which no one typed."""
    assert main(["sweep", "builtin:vmc", "-p", param, "-o", str(tmp_path / "o"),
                 "--workers", "1"]) == 2
    assert capsys.readouterr().err == f"error: {said}\n"


def test_a_refused_design_prints_no_note_before_its_error(vmc, tmp_path, capsys):
    """The note that the figures are those of the model as identified came before the
    refusal of a value the model cannot take."""
    from tcpmm import save_model

    m = vmc.model_copy(update={"axes": {n: a.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.05 * a.mechanics.M_t})) for n, a in vmc.axes.items()}})
    save_model(m, tmp_path / "m.yaml")
    assert main(["sweep", str(tmp_path / "m.yaml"), "-p", "X.servo.K_pp=-1,20",
                 "-o", str(tmp_path / "o"), "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: X.servo.K_pp = -1") and "note" not in err, err
