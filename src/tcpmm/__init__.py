"""tcpmm: a virtual machine tool.

A mechatronic model of the tool center point (TCP-MM) of CNC feed axes: five-inertia
mechanics inside a cascade servo loop, identified from servo excitation and driven by the
interpolated position command of an NC program.

The public API, by step of the work (each name is imported on first use, so that
``import tcpmm`` stays cheap)::

    model      load_model, save_model, builtin_machine
    measure    design_excitation, read_bundle, virtual_bundle, virtual_run
    identify   identify, read_frf, fit_frf, read_tf_fragment
    predict    program_to_command, circle_command, paper_circle_command, read_command,
               simulate
    analyse    read_run, analyse_circle, circle_diagnostics, compare, contour_error
    accuracy   prediction_verdict, CircleTest, ProgramTest
    what-if    circle_spread, run_sweep, tune_servos
    correct    compensate

Results share one protocol: ``.to_pandas()`` (a table in file units), ``.to_dict()``
(what ``--json`` prints) and ``.plot(ax=None, path=None)``, which returns the matplotlib
figure (and saves it too when ``path`` is given).

Example::

    import tcpmm
    run = tcpmm.simulate(tcpmm.builtin_machine(), tcpmm.paper_circle_command())
    tcpmm.analyse_circle(run, radius_m=0.035).plot(path="circle.png")
"""

import sys as _sys
import types as _types

from ._blas_kernels import pin_blas_kernels as _pin_blas_kernels
from ._numba_cache import ensure_cache_dir as _ensure_cache_dir

_pin_blas_kernels()  # before anything loads numpy: the same sums on every CPU
_ensure_cache_dir()

__version__ = "0.1.0"

#: Public name -> "module:attribute" it is imported from on first use.
_API = {
    "load_model": "tcpmm.api:load_model",
    "save_model": "tcpmm.api:save_model",
    "builtin_machine": "tcpmm.machines.builtin:builtin_machine",
    "design_excitation": "tcpmm.ident.excitation:design_excitation",
    "read_bundle": "tcpmm.io.bundle:read_bundle",
    "virtual_bundle": "tcpmm.machines.virtual:virtual_bundle",
    "virtual_run": "tcpmm.machines.virtual:virtual_run",
    "identify": "tcpmm.api:identify",
    "read_frf": "tcpmm.io.frffile:read_frf",
    "fit_frf": "tcpmm.ident.lti.frffit:fit_frf",
    "read_tf_fragment": "tcpmm.io.tffragment:read_tf_fragment",
    "program_to_command": "tcpmm.path.program:program_to_command",
    "circle_command": "tcpmm.path.circle:circle_command",
    "paper_circle_command": "tcpmm.machines.paper:paper_circle_command",
    "read_command": "tcpmm.path.commandfile:read_command_csv",
    "as_command": "tcpmm.api:as_command",
    "simulate": "tcpmm.api:simulate",
    "read_run": "tcpmm.io.runfile:read_run",
    "analyse_circle": "tcpmm.analysis.circular:analyse_circle",
    "circle_diagnostics": "tcpmm.analysis.diagnostics:circle_diagnostics",
    "compare": "tcpmm.api:compare",
    "contour_error": "tcpmm.analysis.contour:contour_error",
    "prediction_verdict": "tcpmm.uncertainty:prediction_verdict",
    "CircleTest": "tcpmm.uncertainty:CircleTest",
    "ProgramTest": "tcpmm.uncertainty:ProgramTest",
    "circle_spread": "tcpmm.whatif.spread:circle_spread",
    "run_sweep": "tcpmm.whatif.sweep.run:run_sweep",
    "tune_servos": "tcpmm.whatif.tuning:tune_and_predict",
    "compensate": "tcpmm.api:compensate",
}

__all__ = ["__version__", *_API]


def __getattr__(name: str):
    """Import a public name on first use [-]."""
    target = _API.get(name)
    if target is None:
        raise AttributeError(f"module 'tcpmm' has no attribute {name!r}")
    import importlib

    module, attr = target.split(":")
    value = getattr(importlib.import_module(module), attr)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_API))


class _Package(_types.ModuleType):
    """The package module. A public name that is also a subpackage's (``compensate``)
    stays the public function when the subpackage is imported, which would otherwise set
    the package attribute to the module; the subpackage stays importable by its path
    (``from tcpmm.compensate.scores import judge``)."""

    def __setattr__(self, name, value):
        if name in _API and isinstance(value, _types.ModuleType):
            return
        super().__setattr__(name, value)


_sys.modules[__name__].__class__ = _Package
