"""Channel skew: the delays identification reads between a sweep's channels, on the
reference machines of an independent simulator as recorded (every channel in step) and with
one channel of X's sweep shifted by whole samples, as a recorder whose channels are not
sampled together writes it.

Per machine and axis: the delay of the scale against the motor encoder (``G_T``) and of the
TCP against the scale (``G_tcp``), each with its standard uncertainty, in samples of the
sweep (100 us); ``*`` a skew (:mod:`tcpmm.ident.physical.skew`); and the channel
identification names, with the shift it says puts it back.

Run: ``.venv/bin/python -m studies.channel_skew [--data DIR]``
"""

from __future__ import annotations

import argparse
import dataclasses
import warnings

import numpy as np

from tcpmm.ident.physical.skew import skewed_channels
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle

from . import DATA

MACHINES = ("c", "d", "e", "h", "r05", "r17")
#: ``(machine, column of X's sweep, samples late)``
SHIFTED = [("c", "tcp_m", 1), ("d", "tcp_m", 1), ("d", "tcp_m", 2), ("d", "tcp_m", 3),
           ("d", "scale_m", 1), ("d", "motor_angle_rad", 1), ("r17", "tcp_m", 1),
           ("r17", "tcp_m", 2), ("r17", "tcp_m", 3), ("r17", "scale_m", 1),
           ("r17", "motor_angle_rad", 1)]


def shifted(bundle, column: str, n: int):
    """``bundle`` with X's sweep column ``column`` ``n`` samples late [-]."""
    x = bundle.axes["X"]
    v = getattr(x.sweep, column)
    late = dataclasses.replace(x.sweep, **{column: np.r_[np.full(n, v[0]), v[:-n]]})
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
                       f"{' *' if k.skewed else ''}" for k in a.channel_skews}
        named = "; ".join(f"{k.channel} {k.samples:+.2f} ({k.remedy()})"
                          for k in skewed_channels(a.channel_skews)) or "-"
        out.append(f"| {label} | {name} | {read.get('G_T', '-')} | {read.get('G_tcp', '-')} "
                   f"| {named} |")
    return out


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default=str(DATA), help="folder holding bench_*/bundle")
    args = ap.parse_args(argv)
    print("| bundle | axis | scale against motor [samples] | TCP against scale [samples] "
          "| channel named |")
    print("|---|---|---|---|---|")
    for m in MACHINES:
        print("\n".join(rows(f"{m.upper()} as recorded",
                             read_bundle(f"{args.data}/bench_{m}/bundle"))), flush=True)
    for m, column, n in SHIFTED:
        b = shifted(read_bundle(f"{args.data}/bench_{m}/bundle"), column, n)
        label = f"{m.upper()}, X's {column} {n} late"
        print("\n".join(rows(label, b)), flush=True)


if __name__ == "__main__":
    main()
