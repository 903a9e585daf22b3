"""A CCW and a CW circle of one run are diagnosed once: the headline spikes after the
pair's terms and the diagnostics the table, the report and ``tcpmm circle`` print read the
same fit, with the warnings and the error it gives each time it is read."""

import warnings

import numpy as np
import pytest

import tcpmm.analysis.diagnostics as diagnostics
from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.diagnostics import circle_diagnostics
from tcpmm.errors import InputError, InputWarning
from test_circle import R, circle_path, make_run, polar_perturb


@pytest.fixture
def pair_run():
    p = np.vstack([circle_path("ccw"), circle_path("cw")])
    return make_run(p, polar_perturb(p, (0, 0), lambda a: 3e-6 + 2e-6 * np.cos(2 * a)))


@pytest.fixture
def calls(monkeypatch):
    """The arguments of every call of ``diagnose_pair`` [-]."""
    seen = []
    fit = diagnostics.diagnose_pair

    def counted(*args, **kw):
        seen.append(args)
        return fit(*args, **kw)

    monkeypatch.setattr(diagnostics, "diagnose_pair", counted)
    return seen


def test_the_spikes_and_the_diagnostics_of_a_pair_are_one_fit(pair_run, calls):
    res = analyse_circle(pair_run, R)
    sc = {p.direction: p.sensors["tcp"] for p in res.passes}
    spikes = {d: s.spikes_after_terms() for d, s in sc.items()}
    diag = circle_diagnostics(res, sensor="tcp")
    assert len(calls) == 1
    assert circle_diagnostics(res, sensor="tcp") is diag and len(calls) == 1
    for d, s in spikes.items():
        assert repr(s) == repr({q: diag.terms[f"spike_{q}_{d}"][0] for q in "ABCD"})
    # as it was fitted alone, to the bit (repr: NaN as NaN)
    alone = diagnostics.diagnose_pair(*calls[0][:2], R, calls[0][3], ("X", "Y"), "tcp")
    assert repr(alone) == repr(diag)


def test_a_pair_of_two_runs_or_of_another_plane_is_fitted_for_itself(pair_run, calls):
    res = analyse_circle(pair_run, R)
    circle_diagnostics(res, sensor="tcp")
    circle_diagnostics(res, sensor="tcp", axes=("X", "Z"))  # named for a plane of its own
    circle_diagnostics(res, analyse_circle(pair_run, R), sensor="tcp")
    assert len(calls) == 3


def test_what_the_fit_warns_of_and_its_error_are_told_to_every_reader(pair_run, monkeypatch):
    def refused(*args, **kw):
        warnings.warn(InputWarning("the pair reads odd"), stacklevel=2)
        raise InputError("the pair cannot be fitted")

    monkeypatch.setattr(diagnostics, "diagnose_pair", refused)
    res = analyse_circle(pair_run, R)
    sc = next(p.sensors["tcp"] for p in res.passes if p.direction == "ccw")
    with warnings.catch_warnings(record=True) as quiet:
        warnings.simplefilter("always")
        assert not sc.after_pair  # the headline spikes fall back to the circle's own terms
    assert not [w for w in quiet if "odd" in str(w.message)]
    for _ in range(2):
        with pytest.warns(InputWarning, match="reads odd"), \
                pytest.raises(InputError, match="cannot be fitted"):
            circle_diagnostics(res, sensor="tcp")
