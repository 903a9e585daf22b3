"""Property tests of the sweep.csv reader: round trip and located errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError
from tcpmm.io.bundle import SWEEP_COLUMNS, read_sweep_csv

SETTINGS = settings(
    max_examples=25,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)


@st.composite
def sweep_tables(draw):
    n = draw(st.integers(64, 200))
    fs = draw(st.sampled_from([100.0, 1000.0, 2048.0, 8000.0, 51200.0]))
    t0 = draw(st.floats(-10, 10, allow_nan=False))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    cols = {"time_s": t0 + np.arange(n) / fs}
    for name in SWEEP_COLUMNS[1:]:
        cols[name] = rng.normal(0, draw(st.sampled_from([1e-6, 1.0, 1e4])), n)
    if draw(st.booleans()):
        cols["tcp_mm"] = rng.normal(0, 1e-3, n)
    order = draw(st.permutations(list(cols)))
    return {k: cols[k] for k in order}, fs


def _write(path, cols):
    pd.DataFrame(cols).to_csv(path, index=False, float_format="%.15g")
    return path


@SETTINGS
@given(table=sweep_tables())
def test_round_trip_any_column_order(tmp_path, table):
    cols, fs = table
    rec = read_sweep_csv(_write(tmp_path / "s.csv", cols))
    assert rec.n_samples == cols["time_s"].size
    assert rec.fs_hz == pytest.approx(fs, rel=1e-9)
    np.testing.assert_allclose(rec.excitation_A, cols["excitation_A"], rtol=1e-13)
    np.testing.assert_allclose(rec.scale_m, cols["scale_mm"] * 1e-3, rtol=1e-13)
    if "tcp_mm" in cols:
        np.testing.assert_allclose(rec.tcp_m, cols["tcp_mm"] * 1e-3, rtol=1e-13)
    else:
        assert rec.tcp_m is None


@SETTINGS
@given(table=sweep_tables(), data=st.data())
def test_bad_value_is_located(tmp_path, table, data):
    cols, _ = table
    n = cols["time_s"].size
    name = data.draw(st.sampled_from(list(cols)))
    row = data.draw(st.integers(0, n - 1))
    bad = data.draw(st.sampled_from([np.nan, np.inf, -np.inf]))
    cols = {k: v.copy() for k, v in cols.items()}
    cols[name][row] = bad
    with pytest.raises(InputError) as exc:
        read_sweep_csv(_write(tmp_path / "s.csv", cols))
    assert exc.value.line == row + 2
    assert exc.value.column == name


@SETTINGS
@given(table=sweep_tables(), data=st.data())
def test_time_glitch_is_located(tmp_path, table, data):
    cols, fs = table
    n = cols["time_s"].size
    row = data.draw(st.integers(1, n - 2))
    shift = data.draw(st.sampled_from([0.2, 0.5, 3.0, -1.5]))
    cols = {k: v.copy() for k, v in cols.items()}
    cols["time_s"][row] += shift / fs
    with pytest.raises(InputError) as exc:
        read_sweep_csv(_write(tmp_path / "s.csv", cols))
    assert exc.value.column == "time_s"
    if shift > 1:
        # a sample pushed later than its successor: reported as an ordering problem at
        # the successor, whose time no longer increases
        assert "does not increase" in exc.value.message
        assert exc.value.line == row + 3
    else:
        assert exc.value.line == row + 2
