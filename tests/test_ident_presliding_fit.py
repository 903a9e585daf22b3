"""Pre-sliding distance and bristle damping fitted to the reversals of friction runs."""

import math

import numpy as np
import pytest

from tcpmm.ident.friction import with_presliding
from tcpmm.ident.friction.preslidingfit import fit_presliding
from tcpmm.io.records import FrictionRecord
from tcpmm.machines.builtin import builtin_machine
from tcpmm.machines.virtual import virtual_friction

SLOW = (0.0005, 0.002)  # plateau speeds [m/s]
#: Turning round gently, as a position loop does that stops on a point and goes back: the
#: contacts pass their pre-sliding in tens of milliseconds, not in one sample [m/s^2].
GENTLE = 0.005


@pytest.fixture(scope="module")
def axis_with_bristles():
    """The built-in X axis, its contacts given 3 um of pre-sliding and damping ratio 0.5,
    with an encoder of 2^20 counts (10 nm at the table), as drives of such axes have."""
    a = builtin_machine().axes["X"]
    a = a.replace(sensors=a.sensors.model_copy(update={"encoder_counts_per_rev": 2**20}))
    return a.replace(friction=with_presliding(a.friction, a.mechanics, 3e-6, 0.5))


@pytest.fixture(scope="module")
def runs(axis_with_bristles):
    return virtual_friction(axis_with_bristles, SLOW, plateau_s=0.4, accel_m_per_s2=GENTLE)


def test_distance_and_damping_of_a_known_axis_are_recovered(axis_with_bristles, runs):
    a = axis_with_bristles
    fit = fit_presliding(runs, a.mechanics, a.friction)
    assert fit.determined, fit.reason
    assert fit.reversals == 3  # two plateau speeds, each there and back
    # encoder quantisation and the smoothing of the path leave a few per cent
    assert fit.presliding == pytest.approx(3e-6, rel=0.08)
    assert abs(fit.presliding - 3e-6) < 3 * fit.presliding_std
    assert fit.damping_ratio == pytest.approx(0.5, abs=0.15)
    assert fit.rms_force < 1.5 * fit.noise_force


def test_the_distance_follows_the_truth(runs, axis_with_bristles):
    """A longer pre-sliding in the record gives a longer fitted one (not a prior)."""
    a = axis_with_bristles
    longer = a.replace(friction=with_presliding(a.friction, a.mechanics, 8e-6, 0.5))
    runs = virtual_friction(longer, SLOW, plateau_s=0.4, accel_m_per_s2=GENTLE)
    fit = fit_presliding(runs, a.mechanics, a.friction)
    assert fit.determined and fit.presliding == pytest.approx(8e-6, rel=0.08)


def test_reversals_in_one_sample_determine_nothing(axis_with_bristles):
    """At 1 m/s^2 the contacts pass their pre-sliding within a few samples: the fit says
    the distance is open instead of returning one."""
    a = axis_with_bristles
    fit = fit_presliding(virtual_friction(a, SLOW, plateau_s=0.4, accel_m_per_s2=1.0),
                         a.mechanics, a.friction)
    assert not fit.determined and "do not follow" in fit.reason


def test_a_coarse_encoder_determines_nothing(axis_with_bristles):
    """1 um per count at the table cannot resolve 3 um of pre-sliding."""
    a = axis_with_bristles
    coarse = a.replace(sensors=a.sensors.model_copy(update={"encoder_counts_per_rev": 10000}))
    fit = fit_presliding(virtual_friction(coarse, SLOW, plateau_s=0.4, accel_m_per_s2=GENTLE),
                         a.mechanics, a.friction)
    assert not fit.determined and "too coarse" in fit.reason


def test_lost_motion_is_left_to_the_prior(runs, axis_with_bristles):
    """2 um of play against 3 um of pre-sliding: the reversal model, which leaves the
    play out, cannot be trusted."""
    a = axis_with_bristles
    fit = fit_presliding(runs, a.mechanics, a.friction.model_copy(update={"backlash": 2e-6}))
    assert not fit.determined and "lost motion" in fit.reason


def test_a_negligible_lost_motion_keeps_the_fit(runs, axis_with_bristles):
    """A hundredth of a micrometre of play, as a friction split may leave where there
    is none, does not throw away what the reversals say."""
    a = axis_with_bristles
    plain = fit_presliding(runs, a.mechanics, a.friction)
    fit = fit_presliding(runs, a.mechanics, a.friction.model_copy(update={"backlash": 1e-8}))
    assert fit.determined and plain.determined
    assert fit.presliding == pytest.approx(plain.presliding, rel=0.02)


def test_runs_without_slow_reversals_determine_nothing(axis_with_bristles):
    a = axis_with_bristles
    t = np.arange(0, 2.0, 1e-3)
    angle = 0.05 * t / (a.mechanics.lead / (2 * math.pi))  # one way at 50 mm/s
    rec = FrictionRecord.from_arrays(t, np.full_like(t, 1.0), angle, 0.05 * t)
    fit = fit_presliding(rec, a.mechanics, a.friction)
    assert not fit.determined and fit.reversals == 0 and "reversal" in fit.reason
    assert fit.to_dict()["determined"] is False


def test_play_operator_known_answer():
    from tcpmm.sim.pathforce import play_operator

    s = np.array([0.0, 1.0, 0.8, 1.1, 3.0, 2.0, 1.2, 1.5])
    assert play_operator(s, 1.0) == pytest.approx([0.0, 0.5, 0.5, 0.6, 2.5, 2.5, 1.7, 1.7])
    assert play_operator(s, 0.0).tolist() == s.tolist()


def test_noise_on_a_creeping_path_ratchets_a_contact_unless_it_passes_the_play():
    """A position loop brings a friction run to its turning point creeping (micrometres
    per second, as the drives of machines C-E do): there 5 nm of sensor noise turns the
    contact's path back and forth at every sample. Each step back relaxes the bristles
    twice as fast as a step forward loads them, so the force sinks by a sixth in 0.3 s
    and a fit takes the softer bristles for a longer pre-sliding (C: 7.9 um where the
    contacts have 5.3 and 2.3). Through a play of six noise deviations the force holds."""
    from tcpmm.mechanics.friction import LuGreFriction, friction_params_array
    from tcpmm.sim.pathforce import contact_force_along_path, play_operator

    c = LuGreFriction(fc_pos=100.0, fc_neg=100.0, fs_pos=130.0, fs_neg=130.0, vs=1.5e-3,
                      sigma0=130.0 / 3e-6)
    p, h = friction_params_array(c), 1e-3
    s = np.r_[0.0, np.cumsum(np.r_[np.full(20, 5e-4), np.full(300, 4e-6)]) * h]
    noisy = s + np.random.default_rng(0).normal(0.0, 5e-9, s.size)
    clean = contact_force_along_path(s, h, p)[-50:].mean()
    assert contact_force_along_path(noisy, h, p)[-50:].mean() < 0.9 * clean
    held = contact_force_along_path(play_operator(noisy, 30e-9), h, p)[-50:].mean()
    assert held == pytest.approx(clean, rel=1e-3)


def test_the_range_holds_the_fit_and_the_truth(axis_with_bristles, runs):
    """The range spans the fit's two standard deviations and the refits with the noise
    play halved and doubled; on a record whose contacts have one distance it holds it."""
    a = axis_with_bristles
    fit = fit_presliding(runs, a.mechanics, a.friction)
    lo, hi = fit.presliding_range
    spread = math.exp(2.0 * fit.presliding_std / fit.presliding)
    assert lo <= fit.presliding / spread * 1.01 and hi >= fit.presliding * spread * 0.99
    assert lo < 3e-6 < hi
    assert fit.to_dict()["presliding_range_m"] == [lo, hi]


def test_the_play_is_the_width_whose_fit_explains_the_force_best():
    """``_over_band`` fits at every width of the grid, refines about the lowest cost by a
    parabola in the logarithm of the width, and spans the range over the chosen fit and its
    neighbours, each widened by two standard deviations (here 0.1 in the log). Known
    answer: a cost with its minimum at 2**0.7 widths, the distance 1 um times the width."""
    from types import SimpleNamespace

    from tcpmm.ident.friction.preslidingfit import BAND_GRID, _over_band

    tried = []

    def fit_at(k):
        tried.append(k)
        r = SimpleNamespace(cost=(math.log2(k) - 0.7) ** 2 + 1.0, x=[math.log(1e-6 * k)])
        return r, 0.1, 0.01

    (r, _, _), (lo, hi) = _over_band(fit_at)
    assert tried[:len(BAND_GRID)] == list(BAND_GRID) and len(tried) == len(BAND_GRID) + 1
    assert math.exp(r.x[0]) == pytest.approx(1e-6 * 2**0.7, rel=1e-12)
    # the lowest cost on the grid is at 2 widths: the neighbours are 1 and 4
    assert lo == pytest.approx(1e-6 * math.exp(-0.2)) and hi == pytest.approx(4e-6 * math.exp(0.2))
    # a minimum at the edge of the grid is kept as it is
    (r, _, _), _ = _over_band(lambda k: (SimpleNamespace(cost=k, x=[math.log(k)]), 0.1, 0.0))
    assert math.exp(r.x[0]) == pytest.approx(BAND_GRID[0])
