"""One direction's terms that rest on reading its ellipse as a squareness.

The circles are those of ``test_circle_diagnostics`` (each error injected as the position
error it is), on R 22 mm at F5000 sampled at 250 Hz: a servo mismatch of 0.93 ms is a
quarter of a sample, so the reversals' placing (``_unplaced``) leaves nothing open, and
yet the lag read as a squareness moved a backlash of -5.45 um to -4.98 um and a bow of
-4.20 um to -4.39 um. Tolerance as there: 2 % or 0.1 um of the radial error a term makes.
"""

import numpy as np
import pytest

import test_circle_diagnostics as gen
from tcpmm.analysis.circle_single import diagnose_single

R, DT, FEED = 0.022, 4e-3, 5000.0  # m, s, mm/min
ERRORS = {"tau_y": 0.93e-3, "b_x": -5.45e-6, "str_y": -4.2e-6, "cx": 2.31e-6,
          "eps_x": 30e-6, "alpha": 20e-6, "b_y": 2e-6, "str_x": 1e-6, "cy": -1e-6}
#: the injected terms, by their names in the diagnostics, and the radial error per unit
TRUE = {"backlash_X": ("b_x", 0.5), "backlash_Y": ("b_y", 0.5),
        "straightness_X": ("str_x", 1.0), "straightness_Y": ("str_y", 1.0),
        "centre_offset_X": ("cx", 1.0), "centre_offset_Y": ("cy", 1.0)}


def single(monkeypatch, err, direction, start_deg):
    monkeypatch.setattr(gen, "R", R)
    monkeypatch.setattr(gen, "DT", DT)
    n = round(2 * np.pi * R / (FEED / 60e3 * DT))
    return diagnose_single(*gen.circle(direction, err, 1, start_deg=start_deg, n=n),
                           direction, R)


def readings(text):
    """The two values a reason gives, as a squareness and as a servo mismatch [um]."""
    words = text.split(": ", 1)[1].split()
    return float(words[0]), float(words[words.index("squareness,") + 1])


@pytest.mark.parametrize("direction", ["ccw", "cw"])
@pytest.mark.parametrize("start_deg", [30.1, 45.3, 60.7])
def test_a_term_the_ellipse_moves_is_open_with_both_readings(monkeypatch, direction,
                                                             start_deg):
    """Every term is within tolerance of what was injected, or open with both readings,
    the injected value between them (within tolerance)."""
    diag = single(monkeypatch, ERRORS, direction, start_deg)
    for term, (key, per_unit) in TRUE.items():
        true, tol = ERRORS[key], max(0.02 * abs(ERRORS[key]), 0.1e-6 / per_unit)
        if np.isfinite(diag[term]):
            assert abs(diag[term] - true) <= tol, (term, diag[term])
            continue
        why = diag.undetermined[term]
        if "cannot place the axes' reversals" in why:
            continue
        lo, hi = sorted(v * 1e-6 for v in readings(why))
        assert lo - tol <= true <= hi + tol, (term, why)


def test_a_squareness_alone_leaves_every_term_determined(monkeypatch):
    """The same ellipse's size as a squareness of 20 um/m, no lag: nothing is opened."""
    err = {k: v for k, v in ERRORS.items() if k != "tau_y"}
    diag = single(monkeypatch, err, "ccw", 45.3)
    assert not [k for k, v in diag.undetermined.items() if "rests on it" in v]
