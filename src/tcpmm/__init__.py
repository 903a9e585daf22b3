"""tcpmm: a virtual machine tool.

A mechatronic model of the tool center point (TCP-MM) of CNC feed axes: five-inertia
mechanics inside a cascade servo loop, identified from servo excitation and driven by the
interpolated position command of an NC program.
"""

from ._numba_cache import ensure_cache_dir as _ensure_cache_dir

_ensure_cache_dir()

__version__ = "0.1.0"
