"""Peak memory of a long run: ``tcpmm simulate`` of the paper's circles 13 times (105 s,
3 axes with friction on the built-in machine, about 106 000 command samples), written to
CSV and to Parquet.

Each command runs in a process of its own, started by a small parent that reads the
child's maximum resident set (``getrusage(RUSAGE_CHILDREN).ru_maxrss``) once it has ended:
what ``/usr/bin/time -v`` reports. The target is 350 MB. Not a test:
``python benchmarks/memory.py [--repeat N] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TARGET_MB = 350.0
#: Runs the command given as its arguments and prints the child's peak memory [kB].
_PEAK = ("import resource, subprocess, sys; "
         "rc = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL).returncode; "
         "print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")


def long_program(repeat: int, path: Path) -> Path:
    """The example circle program with its CCW and CW circles ``repeat`` times [-]."""
    lines = (ROOT / "examples" / "circle_r35_f5000.nc").read_text().splitlines()
    start = next(i for i, ln in enumerate(lines) if ln.startswith("G0 X0 Y0"))
    head = lines[:start + 1]
    body = [ln for ln in lines[start + 1:] if ln.strip() not in ("M30", "%")]
    path.write_text("\n".join(head + body * repeat + ["M30", "%"]) + "\n")
    return path


def peak_mb(cmd: list[str]) -> float:
    """Peak resident memory of ``cmd`` run in a process of its own [MB]."""
    out = subprocess.run([sys.executable, "-c", _PEAK, *cmd], capture_output=True, text=True,
                         check=True).stdout.split()
    if out[0] != "0":
        raise SystemExit(f"{' '.join(cmd)} failed with exit code {out[0]}")
    return int(out[1]) / 1024.0


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=13, help="circle pairs in the program")
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = p.parse_args(argv)
    tcpmm = str(Path(sys.executable).with_name("tcpmm"))
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        prog = long_program(args.repeat, tmp / "long.nc")
        subprocess.run([tcpmm, "path", str(prog), "-o", str(tmp / "cmd.csv")], check=True,
                       capture_output=True)
        figures = {"target_mb": TARGET_MB, "circle_pairs": args.repeat}
        for fmt in ("csv", "parquet"):
            figures[f"peak_mb_{fmt}"] = round(peak_mb(
                [tcpmm, "simulate", "builtin:vmc", "--command", str(tmp / "cmd.csv"),
                 "-o", str(tmp / f"run.{fmt}")]), 1)
    if args.json:
        print(json.dumps(figures))
        return
    for fmt in ("csv", "parquet"):
        mb = figures[f"peak_mb_{fmt}"]
        print(f"tcpmm simulate -o run.{fmt}: peak {mb:.0f} MB "
              f"({'within' if mb <= TARGET_MB else 'above'} {TARGET_MB:.0f} MB)")


if __name__ == "__main__":
    main()
