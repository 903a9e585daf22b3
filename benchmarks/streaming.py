"""Streaming end to end: an NC program of N blocks (0.1 mm G1 blocks of a spiral at
F3000; with ``--program spiral-g64`` the same under ``G64 P0.01``; with ``zigzag`` a CAM
finishing pattern, passes of 2 mm in 0.1 mm blocks 0.05 mm apart under ``G64 P0.01``, a
corner every 21 blocks (``zigzag-long``: passes of 50 mm 0.5 mm apart); with ``arcs``
the spiral as G3 arcs of I and J) through
``tcpmm simulate --gcode ... -o RUN.parquet`` (read, interpolated and simulated a chunk
of blocks at a time, written a row group at a time)
and ``tcpmm contour RUN.parquet --chunk-rows ...`` (the contour error summary, read in
chunks).

Each command runs in a process of its own, started by a small parent that reads the
child's maximum resident set (``getrusage(RUSAGE_CHILDREN).ru_maxrss``) and its wall
time. Targets of issue #52: 1 M blocks in 6 s, 10 M blocks in 60 s under 2 GB. Not a
test: ``python benchmarks/streaming.py [--blocks N] [--program P] [--chunk-blocks N]
[--json]``.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: Runs the command given as its arguments; prints its exit code and peak memory [kB].
_PEAK = ("import resource, subprocess, sys; "
         "rc = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL).returncode; "
         "print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
_TCPMM = ("import sys; from tcpmm.cli import run; sys.exit(run())",)


def _write_program(path: Path, head: str, blocks) -> Path:
    """``head``, the lines ``blocks`` gives and ``M30``, written 100 000 lines at a time [-]."""
    with open(path, "w") as f:
        f.write(head)
        rows = []
        for row in blocks:
            rows.append(row)
            if len(rows) == 100_000:
                f.writelines(rows)
                rows.clear()
        f.writelines(rows)
        f.write("M30\n")
    return path


def spiral_program(blocks: int, path: Path, head: str = "G21 G90 G17") -> Path:
    """A spiral of ``blocks`` G1 blocks 0.1 mm long at F3000, from a radius of 20 mm
    outwards by 0.01 mm a turn [-]."""
    def rows():
        r, phi = 20.0, 0.0
        for _ in range(blocks):
            phi += 0.1 / r
            r = 20.0 + 0.01 * phi / (2 * math.pi)
            yield f"G1 X{r * math.cos(phi):.4f} Y{r * math.sin(phi):.4f}\n"

    return _write_program(path, f"{head}\nG1 X20 Y0 F3000\n", rows())


def zigzag_program(blocks: int, path: Path, per: int = 20, step_mm: float = 0.05) -> Path:
    """A CAM finishing pattern of ``blocks`` G1 blocks under ``G64 P0.01`` at F3000:
    passes of ``per`` blocks of 0.1 mm along X (2 mm), a ``step_mm`` step in Y between
    them [-]."""
    def rows():
        x, y, dx = 0.0, 0.0, 0.1
        for k in range(blocks):
            if k % (per + 1) == per:
                y += step_mm
                dx = -dx
                yield f"G1 Y{y:.4f}\n"
            else:
                x += dx
                yield f"G1 X{x:.4f}\n"

    return _write_program(path, "G21 G90 G17 G64 P0.01\nG1 X0 Y0 F3000\n", rows())


def arc_program(blocks: int, path: Path) -> Path:
    """The spiral of :func:`spiral_program` as ``blocks`` G3 arcs 0.1 mm long, each about
    the centre of the spiral, its centre given by I and J from its start (a CAM program
    that fits its curves with arcs) [-]."""
    def rows():
        x, y, r, phi = 20.0, 0.0, 20.0, 0.0
        for _ in range(blocks):
            phi += 0.1 / r
            r = 20.0 + 0.01 * phi / (2 * math.pi)
            nx, ny = float(f"{r * math.cos(phi):.4f}"), float(f"{r * math.sin(phi):.4f}")
            yield f"G3 X{nx:.4f} Y{ny:.4f} I{-x:.4f} J{-y:.4f}\n"
            x, y = nx, ny

    return _write_program(path, "G21 G90 G17\nG1 X20 Y0 F3000\n", rows())


#: The programs the benchmark makes, by name.
PROGRAMS = {"spiral": spiral_program,
            "spiral-g64": lambda n, path: spiral_program(n, path, "G21 G90 G17 G64 P0.01"),
            "zigzag": zigzag_program, "arcs": arc_program,
            "zigzag-long": lambda n, path: zigzag_program(n, path, 500, 0.5)}


def timed(args: list[str]) -> tuple[float, float]:
    """Wall time [s] and peak resident memory [MB] of ``tcpmm args`` in a process of its
    own."""
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", _PEAK, sys.executable, "-c", *_TCPMM,
                          *args], capture_output=True, text=True, check=True).stdout.split()
    wall = time.perf_counter() - t0
    if out[0] != "0":
        raise SystemExit(f"tcpmm {' '.join(args)} failed with exit code {out[0]}")
    return wall, int(out[1]) / 1024.0


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--blocks", type=int, default=1_000_000,
                   help="blocks of the program (10000000 for the 10 M target)")
    p.add_argument("--program", choices=sorted(PROGRAMS), default="spiral",
                   help="the program made (module docstring)")
    p.add_argument("--chunk-blocks", type=int, default=100_000, help="blocks a chunk")
    p.add_argument("--chunk-rows", type=int, default=200_000, help="run rows a chunk")
    p.add_argument("--no-contour", action="store_true",
                   help="time the simulation alone (the contour error takes longest)")
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    a = p.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        prog = PROGRAMS[a.program](a.blocks, Path(tmp) / "program.nc")
        run = Path(tmp) / "run.parquet"
        sim = timed(["simulate", "builtin:vmc", "--gcode", str(prog), "-o", str(run),
                     "--chunk-blocks", str(a.chunk_blocks)])
        size_mb = run.stat().st_size / 1e6
        con = (0.0, 0.0) if a.no_contour else timed(
            ["contour", str(run), "--plane", "XY", "--chunk-rows", str(a.chunk_rows)])
    res = {"program": a.program, "blocks": a.blocks, "simulate_s": sim[0],
           "simulate_peak_mb": sim[1], "contour_s": con[0], "contour_peak_mb": con[1],
           "total_s": sim[0] + con[0], "peak_mb": max(sim[1], con[1]), "run_file_mb": size_mb}
    if a.json:
        print(json.dumps(res))
        return
    print(f"{a.program}, {a.blocks} blocks: simulate {sim[0]:.1f} s, {sim[1]:.0f} MB; contour "
          f"{con[0]:.1f} s, {con[1]:.0f} MB; total {res['total_s']:.1f} s, peak "
          f"{res['peak_mb']:.0f} MB (run file {size_mb:.0f} MB)")


if __name__ == "__main__":
    main()
