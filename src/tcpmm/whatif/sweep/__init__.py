"""Sweeps: a model and program run over variants of named parameters.

A design (:mod:`~tcpmm.whatif.sweep.design`: ``grid``, ``lhs`` or ``draws``) lists
variants of named parameters (:mod:`~tcpmm.whatif.sweep.space`); each variant is simulated
and analysed as an independent task (:func:`~tcpmm.whatif.sweep.task.evaluate_variant`),
here, on the local cores or on a Dask cluster (:func:`~tcpmm.whatif.sweep.run.run_sweep`),
and its row is written to the results folder as it arrives
(:mod:`~tcpmm.whatif.sweep.store`); a draws design also gets each figure's interval per
point of its grid (:mod:`~tcpmm.whatif.sweep.intervals`). A rerun of the same sweep runs
only the variants whose rows are missing.
"""

from .cluster import local_cluster
from .design import (
    DESIGNS,
    ParamSpec,
    Variant,
    draws_design,
    grid_design,
    latin_hypercube,
    lhs_design,
    make_design,
    parse_param,
)
from .intervals import draw_intervals
from .metrics import circle_metrics, path_distance, path_metrics
from .run import SweepResult, run_sweep
from .space import apply_parameters, canonical_name, parameter_names
from .store import read_results
from .task import CircleProgram, GcodeProgram, evaluate_variant, metric_names

__all__ = [
    "DESIGNS",
    "CircleProgram",
    "GcodeProgram",
    "ParamSpec",
    "SweepResult",
    "Variant",
    "apply_parameters",
    "canonical_name",
    "circle_metrics",
    "draw_intervals",
    "draws_design",
    "evaluate_variant",
    "grid_design",
    "latin_hypercube",
    "lhs_design",
    "local_cluster",
    "make_design",
    "metric_names",
    "parameter_names",
    "parse_param",
    "path_distance",
    "path_metrics",
    "read_results",
    "run_sweep",
]
