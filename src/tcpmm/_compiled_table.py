"""The functions :mod:`tcpmm._compiled` builds ahead of time, the sources they are compiled
from and the kinds of their arguments and results (this file is one of the sources: an
edit of a kind makes a new module)."""

from __future__ import annotations

#: Sources the functions are compiled from (relative to the package): an edit makes a
#: new key.
KERNEL_SOURCES = ("sim/kernel.py", "sim/servoparts.py", "sim/linearstep.py",
                  "sim/frictionstep.py", "sim/contact.py", "sim/frictionlaw.py",
                  "sim/layout.py", "sim/expm.py",
                  "mechanics/friction.py", "path/lookahead.py", "path/profile.py",
                  "path/sampling.py", "path/geometry.py", "path/gcode_scan.py",
                  "path/gcode_arcscan.py", "path/blendtrig.py",
                  "path/nearest.py", "path/ties.py", "sim/cornerfigs.py", "sim/cornerchords.py",
                  "sim/cornerfeed.py",
                  "sim/pathforce.py", "sim/hessenberg.py", "_compiled_table.py")
#: :func:`tcpmm.sim.kernel.run_axis`'s arguments, in order (those of
#: :meth:`tcpmm.sim.inputs.KernelInputs.as_args`).
_KERNEL_KINDS = ("f2", "f2", "f1", "f1", "f1", "f1", "f1", "i1", "f2", "f2", "f2", "f1", "f1",
                 "f1", "f2", "f2", "f2", "f1")
#: :mod:`tcpmm.sim.cornerfigs`' arguments and results.
_SHAPE_KINDS = ("f1", "f1", "f1", "u1", "i1", "f", "f", "i", "f")
_FEED_KINDS = ("f1", "f3", "f2", "i2", "i", "f1", "f1", "f2", "f2", "f2", "f2", "i1")
_FEED_RESULT = ("i2", "f1", "f1", "f1", "u1", "i1", "f2")
#: :func:`tcpmm.path.nearest.search_blocks`' results.
_BLOCKS_KINDS = ("f2", "f2", "f1", "f1", "f1", "f2", "f2", "f2", "f1", "f1", "f1")
#: The functions built into the module: name -> (module of tcpmm, numba's entry point,
#: the function compiled, argument kinds, result kinds). Kinds: ``f1``, ``f2``, ``i1``,
#: ``u1`` C-contiguous float64, int64 or uint8 arrays of 1 or 2 dimensions; ``f``, ``i`` a
#: float64 or int64 number; a tuple for a tuple.
FUNCTIONS = {
    "run_axis": ("sim.kernel", "run_axis", "_run_axis", _KERNEL_KINDS, "f1"),
    "expm": ("sim.expm", "expm", "expm", ("f2",), "f2"),
    "lookahead": ("path.lookahead", "lookahead", "lookahead", ("f1", "f1", "f1", "f"), "f1"),
    "backward": ("path.lookahead", "backward", "backward", ("f1", "f1", "f1", "f"), "f1"),
    "segment_profiles": ("path.profile", "segment_profiles", "segment_profiles",
                         ("f1", "f1", "f1", "f1", "f"), "f2"),
    "timeline": ("path.sampling", "timeline", "timeline",
                 ("i1", "f1", "f1", "f1", "f", "i"), ("i1", "f1", "f1", "i")),
    "sample": ("path.sampling", "sample", "sample",
               ("i1", "f1", "f1", "f1", "f1", "f2", "i", "f"), ("i1", "f1")),
    "scan_lines": ("path.gcode_scan", "scan_lines", "scan_lines", ("u1",), ("i2", "f2")),
    "run_plain": ("path.gcode_scan", "run_plain", "run_plain", ("i2", "f2", "i", "f1"),
                  ("i", "f2", "f1", "i1")),
    "arc_ends": ("path.gcode_arcscan", "arc_ends", "arc_ends", ("i2", "f2", "f1"),
                 ("i", "f2", "f2", "i1", "f1", "f2")),
    "arc_centres": ("path.gcode_arcscan", "arc_centres", "arc_centres",
                    ("i2", "f2", "f1", "f2", "f2", "i1", "f2", "f1"), "i"),
    "nearest_segments": ("path.nearest", "nearest_segments", "nearest_segments",
                         ("f2", "f2", "f2", "f1", "f2", "f1", "f1", "i1", "i1", "i", "f1", "f1"),
                         ("f1", "i1")),
    "search_blocks": ("path.nearest", "search_blocks", "search_blocks", ("f2", "f1"),
                      _BLOCKS_KINDS),
    "nearest_segments_in": ("path.nearest", "nearest_segments_in", "nearest_segments_in",
                            ("f2", "f2", "f2", "f1", "f2", "f1", "f1", "i1", "i1", "i", "f1",
                             "f1", *_BLOCKS_KINDS), ("f1", "i1")),
    "corner_shapes": ("sim.cornerfigs", "corner_shapes", "corner_shapes", _SHAPE_KINDS, "f2"),
    "corner_figures": ("sim.cornerfigs", "corner_figures", "corner_figures",
                       ("f2", "f1", *_SHAPE_KINDS[:5], "i"), "f2"),
    "feed_many": ("sim.cornerfeed", "feed_many", "feed_many", _FEED_KINDS, _FEED_RESULT),
    "first_bend": ("sim.cornerfigs", "first_bend", "first_bend", ("f2", "f1", "i", "f1", "f", "f"),
                   "i"),
    "corner_frames": ("sim.cornerfigs", "corner_frames", "corner_frames",
                      ("f2", "f1", "f1", "i1", "f1", "f"), "f2"),
    "corner_figures_many": ("sim.cornerfigs", "corner_figures_many", "corner_figures_many",
                            ("f2", "i1", "f2", *_SHAPE_KINDS[:4], "i2", "i1"), "f2"),
    "first_bends": ("sim.cornerfigs", "first_bends", "first_bends",
                    ("f2", "f1", "i1", "f2", "f1", "f"), "i1"),
    "chord_strays": ("sim.cornerchords", "chord_strays", "chord_strays",
                     ("f2", "f1", "i1", "f", "f"), "f2"),
    "contact_force_along_path": ("sim.pathforce", "contact_force_along_path",
                                 "contact_force_along_path", ("f1", "f", "f1"), "f1"),
    "play_operator": ("sim.pathforce", "play_operator", "play_operator", ("f1", "f"), "f1"),
    "sliding_friction": ("sim.frictionlaw", "sliding_friction", "sliding_friction",
                         ("f", "f1"), "f"),
    "corner_turns": ("path.blendtrig", "corner_turns", "corner_turns",
                     ("f2", "f2", "f2", "f2", "f1", "f"), ("u1", "f1", "f1")),
    "blend_reach": ("path.blendtrig", "blend_reach", "blend_reach", ("f1", "f1"), "f1"),
    "hessenberg_response": ("sim.hessenberg", "hessenberg_response", "hessenberg_response",
                            ("f2", "f1", "f1", "f1", "f1"), ("f1", "f1")),
}
