"""Channel skew and TCP gain: the delays identification reads between a sweep's channels,
and the TCP device's gain, on the reference machines of an independent simulator as
recorded (every channel in step, the TCP read in full) and with one channel of X's sweep
shifted by whole samples, as a recorder whose channels are not sampled together writes it,
or the TCP column scaled by 0.9.

Per machine and axis: the delay of the scale against the motor encoder (``G_T``) and of the
TCP against the scale (``G_tcp``), each with its standard uncertainty, in samples of the
sweep (100 us); ``*`` a skew (:mod:`tcpmm.ident.physical.skew`); the channel
identification names, with the shift it says puts it back; and the measured ``G_tcp`` over
the model's below the first mode (:func:`tcpmm.ident.gates.masses.tcp_gain`).

Run: ``.venv/bin/python -m studies.channel_skew [--data DIR]``; with
``--population SEED COUNT [--backlash]`` the machines of :mod:`studies.unseen` instead.
"""

from __future__ import annotations

import argparse
import dataclasses
import tempfile
import warnings
from pathlib import Path

import numpy as np

from tcpmm.ident.gates.masses import TCP_MODE_MARGIN, first_mode_hz, tcp_gain
from tcpmm.ident.options import MIN_COHERENCE
from tcpmm.ident.physical.skew import skewed_channels
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle

from . import DATA

MACHINES = ("c", "d", "e", "h", "r05", "r17")
#: ``(machine, column of X's sweep, samples late or, a float, the factor it is scaled by)``
SHIFTED = [("c", "tcp_m", 1), ("d", "tcp_m", 1), ("d", "tcp_m", 2), ("d", "tcp_m", 3),
           ("d", "scale_m", 1), ("d", "motor_angle_rad", 1), ("r17", "tcp_m", 1),
           ("r17", "tcp_m", 2), ("r17", "tcp_m", 3), ("r17", "scale_m", 1),
           ("r17", "motor_angle_rad", 1), ("d", "tcp_m", 0.9), ("r17", "tcp_m", 0.9)]


def shifted(bundle, column: str, n):
    """``bundle`` with X's sweep column ``column`` ``n`` samples late (an int), or scaled
    by ``n`` (a float) [-]."""
    x = bundle.axes["X"]
    v = getattr(x.sweep, column)
    moved = n * v if isinstance(n, float) else np.r_[np.full(n, v[0]), v[:-n]]
    late = dataclasses.replace(x.sweep, **{column: moved})
    return dataclasses.replace(bundle, axes={**bundle.axes,
                                             "X": dataclasses.replace(x, sweep=late)})


def rows(label: str, bundle) -> list[str]:
    """One table row per axis of ``bundle`` identified [-]."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        idn = identify_bundle(bundle, verdict=False, accept_suspect=True)
    out = []
    for name, a in idn.axes.items():
        read = {k.frf: f"{k.samples:+.2f} +- {k.std_s / k.sample_s:.2f}"
                       f"{' *' if k.skewed else ''}{' nj' if k.not_judged else ''}"
                for k in a.channel_skews}
        named = "; ".join(f"{k.channel} {k.samples:+.2f} ({k.remedy()})"
                          for k in skewed_channels(a.channel_skews)) or "-"
        gain = tcp_gain(a.frfs["G_tcp"], lambda f, a=a: a.fitted_response("G_tcp", f),
                        MIN_COHERENCE, first_mode_hz(a.axis.mechanics) / TCP_MODE_MARGIN,
                        bundle.axes[name].sweep.excitation_A)
        out.append(f"| {label} | {name} | {read.get('G_T', '-')} | {read.get('G_tcp', '-')} "
                   f"| {named} | {'-' if gain is None else f'{gain.gain:.4f}'} |")
    return out


def population(seed: int, count: int, backlash: bool) -> None:
    """The rows of ``count`` machines of :mod:`studies.unseen` drawn with ``seed``, every
    channel in step; a delay not judged (the sweep crossed the play) is marked ``nj`` [-]."""
    from tcpmm.machines.virtual import virtual_bundle

    from .unseen import draw_machine

    for index in range(count):
        truth, _ = draw_machine(seed, index, backlash=backlash)
        with tempfile.TemporaryDirectory() as tmp:
            virtual_bundle(truth, Path(tmp) / "bundle", seed=index)
            print("\n".join(rows(f"seed {seed} machine {index}",
                                 read_bundle(Path(tmp) / "bundle"))), flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(DATA), help="folder holding bench_*/bundle")
    ap.add_argument("--population", type=int, nargs=2, metavar=("SEED", "COUNT"),
                    help="machines of studies.unseen instead of the reference machines")
    ap.add_argument("--backlash", action="store_true", help="the population with play")
    args = ap.parse_args(argv)
    print("| bundle | axis | scale against motor [samples] | TCP against scale [samples] "
          "| channel named | TCP gain |")
    print("|---|---|---|---|---|---|")
    if args.population:
        population(*args.population, args.backlash)
        return
    for m in MACHINES:
        print("\n".join(rows(f"{m.upper()} as recorded",
                             read_bundle(f"{args.data}/bench_{m}/bundle"))), flush=True)
    for m, column, n in SHIFTED:
        b = shifted(read_bundle(f"{args.data}/bench_{m}/bundle"), column, n)
        label = (f"{m.upper()}, X's {column} x {n}" if isinstance(n, float)
                 else f"{m.upper()}, X's {column} {n} late")
        print("\n".join(rows(label, b)), flush=True)


if __name__ == "__main__":
    main()
