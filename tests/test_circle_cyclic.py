"""The cyclic-error scan of the circle fit (:mod:`tcpmm.analysis.circle_cyclic`): its power
by products against the columns projected out explicitly, and its period found at the
edge of the band it searches."""

import numpy as np
import pytest

from tcpmm.analysis import circle_cyclic as cc
from tcpmm.analysis.circle_model import cyclic_columns

R = 0.035
N = 3000


def _circle(n=N):
    """Angle, X position and its radial weight of a circle of radius R, and an orthonormal
    basis of a circle fit's own columns (radius, centre, an ellipse) [rad], [m], [-]."""
    th = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    cols = np.c_[np.ones(n), np.cos(th), np.sin(th), np.cos(2 * th), np.sin(2 * th)]
    return th, R * np.cos(th), np.cos(th), np.linalg.qr(cols)[0]


def _projected_power(pos, w, resid, basis, k):
    """The drop of the sum of squares that a sine and cosine of wavenumber ``k``, less
    their parts in ``basis``, bring to ``resid`` [m^2]."""
    A = np.column_stack(cyclic_columns(pos, w, k))
    A = A - basis @ (basis.T @ A)
    c = np.linalg.lstsq(A, resid, rcond=None)[0]
    return float(resid @ resid - (resid - A @ c) @ (resid - A @ c))


@pytest.mark.parametrize("ks", [np.arange(40.0, 40.0 + 64 * 7.0, 7.0),
                                np.array([50.0, 50.0, 50.0, 51.3, 52.6]),
                                np.array([123.4])])
def test_the_scan_power_is_the_fit_drop_of_the_projected_columns(ks):
    """Evenly spaced (by the angle sum), clipped at an edge (repeated values) or alone, the
    scan's power is what fitting the projected columns takes off the residual."""
    rng = np.random.default_rng(3)
    _, pos, w, basis = _circle()
    y = 1e-6 * rng.standard_normal(N) + 2e-6 * w * np.sin(2 * np.pi * 61.0 * pos + 0.3)
    resid = y - basis @ (basis.T @ y)
    got = cc._power_of(pos, w, resid, basis)(ks)
    want = [_projected_power(pos, w, resid, basis, k) for k in ks]
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12 * (resid @ resid))


@pytest.mark.parametrize(("count", "centre"), [(1, 0.0), (2, 0.0), (453, 0.0),
                                               (454, 0.25), (97, -1.3)])
def test_the_scan_grid_by_fft_is_the_fit_drop_of_the_projected_columns(count, centre):
    """The grid's power by the non-uniform FFT, odd and even counts, one wavenumber alone,
    a circle off the axis' origin (a machine's axes seldom have it in the middle): each is
    what fitting the projected columns takes off the residual, to a millionth of the
    largest, where the noise floor a cyclic error must stand out of is some tens of
    noise variances."""
    rng = np.random.default_rng(4)
    _, pos, w, basis = _circle()
    pos = pos + centre
    y = 1e-6 * rng.standard_normal(N) + 2e-6 * w * np.sin(2 * np.pi * 61.0 * pos + 0.3)
    resid = y - basis @ (basis.T @ y)
    ks = cc.MIN_PERIODS / (2 * R) + np.arange(count) / (4 * R)
    got = cc._grid_power(pos, w, resid, basis, ks)
    want = [_projected_power(pos, w, resid, basis, k) for k in ks]
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-9 * max(want))


@pytest.mark.parametrize("frac", [0.1, 0.3, 0.7])
def test_a_period_next_to_the_band_edge_is_refined_to_it(frac):
    """A cyclic error a fraction of a grid step above the lowest wavenumber searched: the
    refinement's grid, clipped at the band's edge, took the edge's phase for all of its
    points and gave the edge (a period 5 % long) instead of the error's."""
    _, pos, w, basis = _circle()
    lo, step = cc.MIN_PERIODS / (2 * R), 1.0 / (4 * R)
    k = lo + frac * step
    y = 2e-6 * w * np.sin(2 * np.pi * k * pos + 0.4)
    resid = y - basis @ (basis.T @ y)
    periods = (2.0 * R / cc.MIN_PERIODS, cc.shortest_period(R * 2 * np.pi / N))
    found = cc._scan(pos, w, resid, basis, R, periods)[0][1]
    assert found == pytest.approx(k, rel=1e-4)


@pytest.mark.parametrize("seed", [100, 127, 146])
def test_periods_refined_beside_each_other_leave_the_terms_as_they_are(seed):
    """Every error at once with pitch errors on both axes (the suite's draws): the scan
    places each period with the reversals and centres of a fit without the cyclic errors,
    which they had moved, and read one 0.4-0.6 % off (11.92 mm for 11.96 mm), and the
    backlash 0.11-0.31 um off with it, past what the terms are recovered to. Each period
    is refined beside the other with the fit that holds both: every term within 2 % or
    0.1 um of radial error, and the periods within 0.1 %."""
    import test_circle_diagnostics as gen

    err = gen.draw(np.random.default_rng(seed))
    d = gen.diagnose(err)
    gen.assert_recovered(d, gen.expected(err))
    for axis in "xy":
        assert d[f"cyclic_period_{axis.upper()}"] == pytest.approx(err[f"cyc_{axis}"][1],
                                                                   rel=1e-3)


def test_the_period_carries_a_standard_uncertainty_that_matches_its_scatter():
    """A pitch error of 0.4 um and 7 mm on X under 0.2 um of white noise, measured again
    with fresh noise: its period scatters by some micrometres, and its standard
    uncertainty (the fit linearised in the wavenumber) is that scatter within what 12
    draws can tell (a standard deviation of 12 is known to about 20 %), the injected
    period lies within its ±2 sigma in most draws, and the table shows the ± in mm, the
    period's unit."""
    import test_circle_diagnostics as gen
    from tcpmm.analysis.circle_sigma import shown_uncertainty
    from tcpmm.analysis.diagnostics import diagnose_pair

    n, lam = 3600, 7e-3
    w = 2 * np.pi / (n * gen.DT)
    err = {"cyc_x": (0.4e-6, lam, 0.7), "b_x": 2e-6}
    periods, sigmas = [], []
    for seed in range(12):
        d = diagnose_pair(gen.circle("ccw", err, 300 + seed, noise=0.2e-6, n=n),
                          gen.circle("cw", err, 400 + seed, noise=0.2e-6, n=n),
                          gen.R, (w, w))
        periods.append(d["cyclic_period_X"])
        sigmas.append(d.sigma["cyclic_period_X"])
        assert shown_uncertainty(d, "cyclic_period_X") == pytest.approx(
            2e3 * sigmas[-1])
    periods, sigmas = np.array(periods), np.array(sigmas)
    assert 0.6 <= np.median(sigmas) / np.std(periods) <= 1.7
    assert np.mean(np.abs(periods - lam) <= 2 * sigmas) >= 0.75


@pytest.mark.parametrize("axis", ["x", "y"])
def test_the_period_holds_the_frame_it_is_read_in(axis):
    """The fit reads a period in the tool's travel, which a radius 5 um long, the axis'
    scale 100 ppm long and a 5 um backlash stretch against the axis' own by some 2e-4:
    the period found is 1.5-1.8 um longer than the one injected, whatever the noise. Its
    ±95% holds that, not only what the noise (0.01 um here) moves."""
    import test_circle_diagnostics as gen

    lam = {"x": 7e-3, "y": 9e-3}[axis]
    err = {f"cyc_{axis}": (1e-6, lam, 0.3), "r0": 5e-6, f"eps_{axis}": 100e-6,
           f"b_{axis}": 5e-6}
    d = gen.diagnose(err, noise=0.01e-6)
    name = f"cyclic_period_{axis.upper()}"
    assert 1e-6 < d[name] - lam <= 2 * d.sigma[name]


def test_the_lines_of_uncertain_terms_give_a_period_in_mm():
    """The lines naming the terms uncertain by what the terms leave or by the reversals'
    tails gave a period of 22.48 mm as "22483.82 ± 506.20 µm", where the table gives mm."""
    from types import SimpleNamespace

    from tcpmm.analysis.circle_tails import pair_text

    diag = SimpleNamespace(terms={"cyclic_period_X": (0.02248382, "m")})
    assert pair_text(diag, "cyclic_period_X", 0.02248382, 0.0005062, "±") == \
        "cyclic period X 22.48 ± 0.51 mm"


def test_a_cyclic_error_longer_than_the_scan_is_said_to_read_as_the_terms():
    """The scan runs to a third of the diameter (23.3 mm on R 35 mm). A pitch error of
    0.8 um at 60 mm, none else, is much like a scale error and a bow there and read a
    backlash and a scale mismatch that are not on the machine, while the cyclic error's
    n/a said only that a shorter one reads as the terms. It now says what a longer one
    reads as, and what brings it into the search."""
    from tcpmm.analysis.diagnostics import diagnose_pair
    from test_circle_diagnostics import R, W, circle

    err = {"cyc_x": (0.8e-6, 0.06, 0.5)}
    d = diagnose_pair(circle("ccw", err, 1), circle("cw", err, 2), R, (W, W))
    why = d.undetermined["cyclic_amplitude_X"]
    assert "periods from 23.3 down to" in why
    assert "A longer one, fewer than three of its periods along the travel" in why
    assert "a circle of a larger radius brings it into the search" in why


@pytest.mark.parametrize("period_mm, at_edge", [(24.0, True), (20.0, False)])
def test_a_cyclic_error_found_at_the_longest_period_searched_is_not_given_a_period(
        period_mm, at_edge):
    """A pitch error of 24 mm on R 35 mm lies just beyond the scan's longest period
    (23.3 mm): its power still rose there, and the scan gave 23.33 +- 0.24 mm as firm.
    Where it stands out at the band's end, its period and amplitude are not determined
    and say why; one inside the band keeps its period."""
    from tcpmm.analysis.diagnostics import diagnose_pair
    from test_circle_diagnostics import R, W, circle

    err = {"cyc_y": (0.6e-6, period_mm * 1e-3, 1.0)}
    d = diagnose_pair(circle("ccw", err, 1), circle("cw", err, 2), R, (W, W))
    if not at_edge:
        assert d["cyclic_period_Y"] == pytest.approx(period_mm * 1e-3, rel=0.02)
        return
    assert np.isnan(d["cyclic_period_Y"]) and np.isnan(d["cyclic_amplitude_Y"])
    why = d.undetermined["cyclic_period_Y"]
    assert "one stands out at the longest period searched, 23.3 mm" in why
    assert "a circle of a larger radius brings it into the search" in why


@pytest.mark.parametrize("seed", range(3))
def test_a_pitch_error_below_the_noise_is_found_and_leaves_the_backlash(seed):
    """A pitch error of 1.5 um at 5 mm on X beside 2 um of noise on each axis, with
    backlash, lateral play, a bow, squareness and scale and servo mismatches. It was
    refused for being under the RMS of what the fit leaves, which is the noise here, and
    left to the terms: backlash X read 6.3 um for 5 (the mean of 12 draws). Over some
    11 000 samples fitted the noise moves the amplitude by 0.05 um and the backlash by
    0.17 um (one standard deviation, over 12 draws): the tolerances are four of them."""
    from tcpmm.analysis.diagnostics import diagnose_pair
    from test_circle_diagnostics import W, circle

    err = {"b_x": 5e-6, "b_y": 2e-6, "tau_x": 1e-3, "eps_x": 80e-6, "p_y": 2e-6,
           "str_x": 2e-6, "alpha": 40e-6, "cyc_x": (1.5e-6, 5e-3, 0.7)}
    d = diagnose_pair(circle("ccw", err, 2 * seed + 1, noise=2e-6),
                      circle("cw", err, 2 * seed + 2, noise=2e-6), R, (W, W))
    assert d["cyclic_amplitude_X"] == pytest.approx(1.5e-6, abs=0.2e-6)
    assert d["cyclic_period_X"] == pytest.approx(5e-3, rel=0.02)
    assert d["backlash_X"] == pytest.approx(5e-6, abs=0.7e-6)
    assert np.isnan(d["cyclic_amplitude_Y"])  # none where the noise alone is
