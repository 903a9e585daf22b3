"""Bad input to the flat public API (``tcpmm.*``) is an :class:`InputError` that names the
argument, the value and the fix, never an error from inside or a silent wrong result; and
every result's ``to_dict`` is JSON as ``--json`` prints it."""

import json
import math
import warnings

import pytest

import tcpmm
from tcpmm.model import AxisUncertainty


@pytest.fixture(scope="module")
def small_circle():
    """A 10 mm circle that starts at quadrant point A: its spike A is undefined."""
    return tcpmm.circle_command(0.01, 0.05)


def test_a_spread_dict_is_json_with_a_missing_spike_null(vmc, small_circle):
    m = vmc.model_copy(update={"axes": {
        n: a.replace(uncertainty=AxisUncertainty()) for n, a in vmc.axes.items()}})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = tcpmm.circle_spread(m, small_circle, 0.01, n=1, floors=None).to_dict()
    json.dumps(d, allow_nan=False)
    assert d["spikes"][0]["point"] == "A" and d["spikes"][0]["spike_um"] is None


def test_json_ready_turns_what_is_not_finite_into_none():
    from tcpmm.result import json_ready

    assert json_ready({"a": [1.0, math.nan, (math.inf, "x")], "b": 2}) == {
        "a": [1.0, None, [None, "x"]], "b": 2}


def test_a_compensation_dict_is_json_with_a_missing_spike_null(vmc, small_circle):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = tcpmm.compensate(vmc, small_circle, draws=0, radius_m=0.01).to_dict()
    json.dumps(d, allow_nan=False)
    assert d["scores"]["before"]["circle"]["passes"][0]["spikes_um"]["A"] is None
