"""A draws design's intervals: per point of the grid, the draws' quantiles of each figure
and of its change from the first point, draw by draw."""

import json

import numpy as np
import pandas as pd
import pytest

from tcpmm.model import AxisUncertainty
from tcpmm.whatif.sweep import (
    CircleProgram,
    canonical_name,
    draw_intervals,
    draws_design,
    parse_param,
    run_sweep,
)

#: A short circle: 5 mm at 6000 mm/min, CCW then CW.
SHORT = CircleProgram(radius_m=5e-3, feed_m_per_s=0.1)


def test_quantiles_per_point_and_the_change_taken_draw_by_draw():
    """Two points of four draws: the figure's quantiles over each point's draws; its change
    from the first point on the same draw, whose spread cancels what the points share; a
    draw with a fault is counted and left out."""
    draw = [0, 1, 2, 3] * 2
    k = np.array([0.0, 10.0, 20.0, 30.0])  # what every point shares: the drawn machine
    summary = pd.DataFrame({
        "index": range(8), "variant": list("abcdefgh"), "X.servo.K_pp": [30] * 4 + [40] * 4,
        "draw": draw, "seed": 0, "spike_max_um": np.r_[5.0 + k, 3.0 + k],
        "warning": "", "fault": [""] * 7 + ["X runs away"], "error": ""})
    got = draw_intervals(summary).set_index("X.servo.K_pp")
    assert list(got.index) == [30, 40]
    assert got.loc[30, "draws"] == 4 and got.loc[40, "draws_faulty"] == 1
    assert got.loc[30, "spike_max_median_um"] == pytest.approx(20.0)
    assert got.loc[30, "spike_max_low_um"] == pytest.approx(np.quantile(5.0 + k, 0.05))
    assert got.loc[40, "spike_max_high_um"] == pytest.approx(np.quantile(3.0 + k[:3], 0.95))
    assert got.loc[30, ["spike_max_change_low_um", "spike_max_change_high_um"]].tolist() == [
        0.0, 0.0]
    assert got.loc[40, ["spike_max_change_low_um", "spike_max_change_median_um",
                        "spike_max_change_high_um"]].tolist() == pytest.approx([-2.0] * 3)


def test_a_draws_sweep_writes_its_intervals_and_says_so(vmc, tmp_path, capsys):
    """A draws design wrote one row per draw and nothing per point: whether a higher gain
    helps under the model's uncertainty was left to the user."""
    from tcpmm import save_model
    from tcpmm.cli import main

    m = vmc.model_copy(update={"axes": {n: a.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.05 * a.mechanics.M_t})) for n, a in vmc.axes.items()}})
    specs = [parse_param("X.servo.K_pp=30,40", lambda n: canonical_name(m, n, "circle"))]
    res = run_sweep(m, SHORT, draws_design(specs, 3, seed=2), tmp_path / "o", workers=1)
    got = pd.read_csv(res.intervals)
    assert got["X.servo.K_pp"].tolist() == [30, 40] and got["draws"].tolist() == [3, 3]
    rows = pd.read_csv(res.summary)
    first = rows[rows["X.servo.K_pp"] == 30]["spike_max_um"]
    assert got.loc[0, "spike_max_median_um"] == pytest.approx(first.median())
    assert res.to_dict()["intervals"] == str(res.intervals)
    save_model(m, tmp_path / "m.yaml")
    base = ["sweep", str(tmp_path / "m.yaml"), "-p", "X.servo.K_pp=30,40", "--circle",
            "5,6000", "--workers", "1"]
    assert main([*base, "-o", str(tmp_path / "g")]) == 0
    said = " ".join(capsys.readouterr().err.split())
    assert "without its uncertainty" in said and "--design draws" in said
    assert main([*base, "-o", str(tmp_path / "d"), "--design", "draws", "--n", "2"]) == 0
    out, err = (" ".join(t.split()) for t in capsys.readouterr())
    assert "intervals" in out and "2 draws a point" in err
    assert not (tmp_path / "g" / "intervals.csv").exists()
    assert json.loads((tmp_path / "d" / "study.json").read_text())
