"""Benchmark: read, parse and interpolate a 100 000-block program of short G1 segments.

The program is an Archimedean spiral in XY (radius 5 mm to 50 mm, blocks about 0.1 mm
long) at F3000. Prints the time to read and parse it, the time to interpolate it
(target: below 10 s), and their ratio.

Run: ``.venv/bin/python benchmarks/interpolate.py [--blocks N]``
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import numpy as np

from tcpmm.path import InterpolatorSettings, interpolate, parse_gcode, read_program

TARGET_S = 10.0


def spiral_program(blocks: int, feed_mm_per_min: float = 3000.0) -> str:
    """G-code of a spiral made of ``blocks`` G1 blocks [-]."""
    step_mm = 0.1
    r0, r1 = 5.0, 50.0
    # r = r0 + b*phi; the length r0*Phi + b*Phi^2/2 must be blocks*step_mm
    total_angle = 2.0 * blocks * step_mm / (r0 + r1)
    b = (r1 - r0) / total_angle
    r = r0
    phi = 0.0
    xs = np.empty(blocks)
    ys = np.empty(blocks)
    for k in range(blocks):
        phi += step_mm / r
        r = r0 + b * phi
        xs[k] = r * math.cos(phi)
        ys[k] = r * math.sin(phi)
    lines = [
        "%",
        "(spiral of short G1 blocks)",
        "G21 G17 G90",
        f"G1 X{r0:.4f} Y0 F{feed_mm_per_min:g}",
    ]
    lines += [f"X{x:.4f} Y{y:.4f}" for x, y in zip(xs, ys, strict=True)]
    lines += ["M30", "%"]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=100_000)
    args = ap.parse_args()
    settings = InterpolatorSettings(
        path_accel_m_per_s2=2.0,
        axis_accel_m_per_s2={"X": 3.0, "Y": 3.0},
        filter_kind="bell",
        filter_time_s=0.016,
    )
    # compile (numba cache) outside the timing
    interpolate(parse_gcode("G1 X1 F100\nG1 Y1\n"), settings)

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "spiral.nc"
        path.write_text(spiral_program(args.blocks))
        t0 = time.perf_counter()
        segments = parse_gcode(read_program(path), path)
        t1 = time.perf_counter()
        command = interpolate(segments, settings)
        t2 = time.perf_counter()
    parse_s, interp_s = t1 - t0, t2 - t1
    print(f"blocks:               {len(segments)}")
    print(f"samples:              {command.time_s.size} ({command.time_s[-1]:.1f} s of motion)")
    print(f"read + parse:         {parse_s:.2f} s")
    print(f"interpolate:          {interp_s:.2f} s (target < {TARGET_S:.0f} s)")
    print(f"interpolate / parse:  {interp_s / parse_s:.2f}")
    if interp_s > TARGET_S:
        raise SystemExit(f"interpolation took {interp_s:.1f} s, more than {TARGET_S:.0f} s")


if __name__ == "__main__":
    main()
