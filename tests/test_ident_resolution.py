"""A record that moves in steps finer than the sensor machine.yaml declares: the model
quantises its sensors as declared, so an encoder declared with 4096 counts for one of a
million turned the velocity loop into noise and every circle into "no prediction: holds
its current at the limit, check the load force, the gains and the current limit", which
sent the user to the wrong file."""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from tcpmm.errors import InputWarning
from tcpmm.ident.gates.columns import _warn_finer_steps, check_record_units
from tcpmm.io.bundle import read_bundle

DATA = Path(__file__).resolve().parents[2] / "shared" / "data"


def _record(counts: int, scale_step_m: float, n: int = 20_000):
    """A record of an axis travelling slowly (a few counts a sample) with noise of a
    count, quantised to ``counts`` per turn and to ``scale_step_m`` [SI]."""
    rng = np.random.default_rng(1)
    turns = np.linspace(0.0, 0.02, n) + rng.normal(0.0, 1.0 / counts, n)
    q = 2.0 * math.pi / counts
    angle = np.round(turns * 2.0 * math.pi / q) * q
    scale = np.round(turns * 0.02 / scale_step_m) * scale_step_m
    return SimpleNamespace(motor_angle_rad=angle, scale_m=scale, source="X/sweep.csv")


def _sensors(counts: int, scale_um: float):
    return SimpleNamespace(encoder_resolution_rad=2.0 * math.pi / counts,
                           scale_resolution_m=scale_um * 1e-6)


def test_a_record_finer_than_the_declared_sensors_is_said_and_a_matching_one_is_not():
    rec = _record(1_048_576, 0.05e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _warn_finer_steps(rec, _sensors(1_048_576, 0.05))
        _warn_finer_steps(rec, _sensors(4 * 1_048_576, 0.01))  # declared finer: no contradiction
    with pytest.warns(InputWarning, match="X/sweep.csv: motor_angle_rad moves in steps of "
                                          r"5.99e-06 rad.*encoder_counts_per_rev"):
        _warn_finer_steps(rec, _sensors(4096, 0.05))
    with pytest.warns(InputWarning, match="scale_mm moves in steps of 5e-08 m.*"
                                          "scale_resolution_um"):
        _warn_finer_steps(rec, _sensors(1_048_576, 1.0))


@pytest.mark.skipif(not DATA.is_dir(), reason="the shared data sets are not beside the project")
@pytest.mark.parametrize("bench", ["c", "d", "e", "h", "r05", "r17"])
def test_the_benches_records_move_in_the_steps_they_declare(bench):
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        check_record_units(read_bundle(DATA / f"bench_{bench}" / "bundle"))
