"""Two long-period cyclic errors, one on each axis, chosen together
(:mod:`tcpmm.analysis.circle_cyclic_pair`): over few periods along the travel a sine of
X's position and one of Y's are much alike, and each axis searched beside the other's,
found off, settled off too."""

import numpy as np
import pytest

import test_circle_diagnostics as gen
from tcpmm.analysis import circle_cyclic_pair as cp
from tcpmm.analysis.circle_model import cyclic_columns

#: Pitch errors of X and Y (amplitude, period, phase) whose pair the axes searched one
#: at a time read off: 0.62 um at 17.43 mm and 1.00 um at 21.06 mm with a scale mismatch
#: of -21 ppm; 0.78 um at 21.8 mm and 0.81 um at 17.2 mm
PAIRS = {"18-22": ((0.8e-6, 18e-3, 0.0), (1.0e-6, 22e-3, 0.0)),
         "20-16": ((1.0e-6, 20e-3, 0.0), (0.7e-6, 16e-3, 0.0))}
#: Other errors beside them: the bows, a backlash, a squareness, a scale mismatch and a
#: servo mismatch, which the pair's columns overlap in part
OTHERS = {"alone": {},
          "with others": {"str_x": 2e-6, "str_y": -1.5e-6, "b_y": 2e-6, "alpha": 40e-6,
                          "eps_x": 30e-6, "tau_y": 0.2e-3}}


@pytest.mark.parametrize(("pair", "others", "noise"), [
    ("18-22", "alone", 0.0), ("18-22", "with others", gen.NOISE),
    ("20-16", "alone", gen.NOISE), ("20-16", "with others", 0.0)])
def test_two_long_periods_are_found_together(pair, others, noise):
    """Each pitch error, its period, and every other term within 2 % or 0.1 um of radial
    error, and no scale mismatch beyond the one injected: the pair fitted together leaves
    the noise alone."""
    cyc_x, cyc_y = PAIRS[pair]
    err = {"cyc_x": cyc_x, "cyc_y": cyc_y, **OTHERS[others]}
    d = gen.diagnose(err, noise=noise)
    for axis, (amp, period, _) in zip("XY", (cyc_x, cyc_y), strict=True):
        assert d[f"cyclic_period_{axis}"] == pytest.approx(period, rel=0.02), axis
        assert d[f"cyclic_amplitude_{axis}"] == pytest.approx(amp, rel=0.02), axis
    gen.assert_recovered(d, gen.expected(err))
    assert abs(d["scale_mismatch"] - err.get("eps_x", 0.0)) < 2e-6


def test_the_pair_power_is_the_drop_of_the_four_columns_fitted_together():
    """The drop of the sum of squares that the sine and cosine of X and of Y bring
    together, for every pair of a grid of each, is what fitting the four columns, less
    their parts in the basis, takes off the residual."""
    rng = np.random.default_rng(7)
    n, r = 4000, gen.R
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    pos = (r * np.cos(th), r * np.sin(th))
    ws = (np.cos(th), np.sin(th))
    basis = np.linalg.qr(np.c_[np.ones(n), np.cos(th), np.sin(th), np.cos(2 * th),
                               np.sin(2 * th)])[0]
    y = (1e-6 * rng.standard_normal(n) + 0.8e-6 * ws[0] * np.sin(2 * np.pi * pos[0] / 18e-3)
         + 1e-6 * ws[1] * np.sin(2 * np.pi * pos[1] / 22e-3 + 0.4))
    resid = y - basis @ (basis.T @ y)
    kx, ky = np.array([50.0, 55.6, 61.0]), np.array([40.0, 45.5])
    got = cp.pair_power(pos, ws, resid, basis)(kx, ky)
    for i, j in np.ndindex(got.shape):
        a = np.column_stack([*cyclic_columns(pos[0], ws[0], kx[i]),
                             *cyclic_columns(pos[1], ws[1], ky[j])])
        a = a - basis @ (basis.T @ a)
        left = resid - a @ np.linalg.lstsq(a, resid, rcond=None)[0]
        assert got[i, j] == pytest.approx(resid @ resid - left @ left, rel=1e-9)


def test_the_best_pair_is_refined_to_the_one_of_least_residual():
    """Started a third of a grid step off on each axis, where each refined beside the
    other's stays off, the pair refined over both at once is the one injected."""
    n, r = 4000, gen.R
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    pos = (r * np.cos(th), r * np.sin(th))
    ws = (np.cos(th), np.sin(th))
    basis = np.linalg.qr(np.c_[np.ones(n), np.cos(th), np.sin(th)])[0]
    y = (0.8e-6 * ws[0] * np.sin(2 * np.pi * pos[0] / 18e-3)
         + 1e-6 * ws[1] * np.sin(2 * np.pi * pos[1] / 22e-3))
    resid = y - basis @ (basis.T @ y)
    step = 1.0 / (4.0 * r)
    band = (3.0 / (2 * r), 1000.0)
    power = cp.pair_power(pos, ws, resid, basis)
    got = cp.best_pair(power, ([1 / 18e-3 + step / 3], [1 / 22e-3 - step / 3]), 2 * step,
                       band)
    assert got == pytest.approx((1 / 18e-3, 1 / 22e-3), rel=1e-4)
