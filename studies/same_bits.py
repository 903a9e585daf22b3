"""The same answer on every CPU: the command line's outputs on the reference machines of an
independent simulator, and a digest of each, to compare between machines.

For each of ``../shared/data/bench_{c,d,e,h,r05,r17}``, as a user runs it:
``tcpmm identify bundle -o model.yaml``, then for each measured circle (R 35 mm, F5000 and
F10000, CCW and CW) ``tcpmm simulate model.yaml --command circle_*_cmd.csv -o pred.csv`` and
``tcpmm compare circle_*_meas.csv pred.csv --radius 35 --model model.yaml --json``. Each
command runs in a process of its own with one BLAS thread and one job. Prints the SHA-256 of
every model, prediction and comparison written, and one digest over them all: run it on
two machines and compare the last line.

Run: ``.venv/bin/python -m studies.same_bits OUT [--data DIR] [--machines c,d,...]``
"""

from __future__ import annotations

import argparse
import hashlib
import os
import subprocess
import sys
from pathlib import Path

from . import DATA

MACHINES = ("c", "d", "e", "h", "r05", "r17")
CASES = ("ccw", "cw", "ccw_fast", "cw_fast")
_TCPMM = "import sys; from tcpmm.cli import run; sys.argv[0] = 'tcpmm'; sys.exit(run())"


def tcpmm(*args, stdout=None) -> None:
    """``tcpmm args`` in a process of its own, one thread and one job; its output to
    ``stdout`` (a path) where given [-]."""
    env = {**os.environ, "TCPMM_JOBS": "1", "OMP_NUM_THREADS": "1",
           "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
    out = subprocess.run([sys.executable, "-c", _TCPMM, *map(str, args)], env=env,
                         capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"tcpmm {' '.join(map(str, args))} failed:\n{out.stderr}")
    if stdout is not None:
        Path(stdout).write_text(out.stdout, encoding="utf-8")


def outputs(letter: str, data: Path, out: Path) -> list[Path]:
    """Identify machine ``letter`` and predict and compare its circles into ``out``; the
    files written [-]."""
    folder = data / f"bench_{letter}"
    model = out / f"model_{letter}.yaml"
    tcpmm("identify", folder / "bundle", "-o", model)
    files = [model]
    for case in CASES:
        pred, cmp_ = out / f"pred_{letter}_{case}.csv", out / f"cmp_{letter}_{case}.json"
        tcpmm("simulate", model, "--command", folder / f"circle_{case}_cmd.csv", "-o", pred)
        tcpmm("compare", folder / f"circle_{case}_meas.csv", pred, "--radius", "35",
              "--model", model, "--json", stdout=cmp_)
        files += [pred, cmp_]
    return files


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out", type=Path, help="folder for the outputs")
    p.add_argument("--data", type=Path, default=DATA)
    p.add_argument("--machines", default=",".join(MACHINES))
    args = p.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    total = hashlib.sha256()
    for letter in args.machines.split(","):
        for f in outputs(letter, args.data, args.out):
            digest = hashlib.sha256(f.read_bytes()).hexdigest()
            total.update(f"{f.name} {digest}\n".encode())
            print(f"{digest[:16]}  {f.name}", flush=True)
    print(f"all: {total.hexdigest()}")


if __name__ == "__main__":
    main()
