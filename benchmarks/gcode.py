"""G-code parse speed: ``parse_gcode`` per block on a 100 000-block spiral of
``G1 X.. Y..`` lines (``--arcs``: of ``G3 X.. Y.. I.. J..`` arcs), against the reference
path (every line through the tokeniser and the interpreter) measured in the same run.
``runs`` is the parse as the streaming commands (``path``, ``simulate --gcode``) make it:
the same lexer and interpreter, the blocks kept as runs of arrays
(:class:`tcpmm.path.runs.LineRun`, :class:`~tcpmm.path.runs.ArcRun`) that the interpolator
takes as they are, where ``parse_gcode`` makes each block a Python object (most of its
time on arcs); the runs are checked to hold the same segments.

They run in turn, ``--rounds`` times, so that a change of machine load hits them
all alike; min and median over the rounds. The target is 2 us a block. Not a test:
``python benchmarks/gcode.py [--blocks N] [--rounds N] [--arcs] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings

from tcpmm.errors import InputWarning
from tcpmm.io.text import file_lines
from tcpmm.path import gcode_stream, parse_gcode
from tcpmm.path.gcode_fast import collector_paused
from tcpmm.path.runs import as_lines

TARGET_US = 2.0


def spiral_program(blocks: int) -> str:
    """A spiral of ``blocks`` G1 blocks about 0.01 mm long, as issue #52 timed it [-]."""
    lines = ["G21 G90 G64 P0.01", "G1 X0 Y0 F3000"]
    for i in range(1, blocks + 1):
        r, phi = 5 + 0.1 * i * 0.002, i * 0.002
        lines.append(f"G1 X{r * math.cos(phi):.4f} Y{r * math.sin(phi):.4f}")
    return "\n".join([*lines, "M30"]) + "\n"


def arc_program(blocks: int) -> str:
    """The spiral of :func:`spiral_program` as G3 arcs about its centre, each centre
    given by I and J from the arc's start [-]."""
    lines, x, y = ["G21 G90", "G1 X5 Y0 F3000"], 5.0, 0.0
    for i in range(1, blocks + 1):
        r, phi = 5 + 0.1 * i * 0.002, i * 0.002
        nx, ny = float(f"{r * math.cos(phi):.4f}"), float(f"{r * math.sin(phi):.4f}")
        lines.append(f"G3 X{nx:.4f} Y{ny:.4f} I{-x:.4f} J{-y:.4f}")
        x, y = nx, ny
    return "\n".join([*lines, "M30"]) + "\n"


def reference(text: str):
    """The program through the tokeniser and interpreter only [-]."""
    with collector_paused():  # as parse_gcode, so that the ratio is the fast path's
        it = gcode_stream.run_program(text, None, (0.0, 0.0, 0.0), fast=False)
    it.emit_warnings()
    return it.segments


def as_runs(text: str):
    """The program lexed and interpreted into runs, as :func:`tcpmm.path.stream` reads a
    chunk [-]."""
    with collector_paused():
        (it,) = gcode_stream.interpret_chunks([file_lines(text)], None,
                                              (0.0, 0.0, 0.0), runs=True)
    it.emit_warnings()
    return it.segments


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100_000, help="G1 blocks [-]")
    ap.add_argument("--rounds", type=int, default=5, help="timed rounds [-]")
    ap.add_argument("--arcs", action="store_true", help="G3 arcs instead of G1 blocks")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    a = ap.parse_args(argv)
    text = (arc_program if a.arcs else spiral_program)(a.blocks)
    tools = {"fast": parse_gcode, "runs": as_runs, "reference": reference}
    times = {k: [] for k in tools}
    outs = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InputWarning)  # the G1 X0 Y0 at the start
        for _ in range(a.rounds):
            for name, f in tools.items():
                t0 = time.perf_counter()
                outs[name] = f(text)
                times[name].append(time.perf_counter() - t0)
    if outs["fast"] != outs["reference"] or as_lines(outs["runs"]) != outs["fast"]:
        raise SystemExit("the fast path, the runs and the reference gave different segments")
    lines = text.count("\n")
    us = {k: sorted(v) for k, v in times.items()}
    res = {"blocks": a.blocks, "arcs": a.arcs, "rounds": a.rounds,
           "fast_us_per_block": us["fast"][0] / lines * 1e6,
           "fast_us_per_block_median": us["fast"][len(us["fast"]) // 2] / lines * 1e6,
           "runs_us_per_block": us["runs"][0] / lines * 1e6,
           "runs_us_per_block_median": us["runs"][len(us["runs"]) // 2] / lines * 1e6,
           "reference_us_per_block": us["reference"][0] / lines * 1e6,
           "reference_us_per_block_median":
               us["reference"][len(us["reference"]) // 2] / lines * 1e6}
    res["speedup"] = res["reference_us_per_block"] / res["fast_us_per_block"]
    if a.json:
        print(json.dumps(res, indent=1))
    else:
        print(f"blocks:     {a.blocks} ({a.rounds} rounds, min / median)")
        print(f"fast:       {res['fast_us_per_block']:.2f} / "
              f"{res['fast_us_per_block_median']:.2f} us a block (target {TARGET_US:g})")
        print(f"runs:       {res['runs_us_per_block']:.2f} / "
              f"{res['runs_us_per_block_median']:.2f} us a block")
        print(f"reference:  {res['reference_us_per_block']:.2f} / "
              f"{res['reference_us_per_block_median']:.2f} us a block")
        print(f"speed-up:   {res['speedup']:.2f}")
    return res


if __name__ == "__main__":
    main()
