"""Quickstart: the paper's circular test on the built-in machine, and a what-if.

Simulates the R35 mm, 5000 mm/min circle (CCW then CW) on the built-in machine and on a
copy whose TCP structure (column and headstock) is twice as stiff, and prints the
reversal spikes at the quadrant points A-D per sensor for both.

    python examples/quickstart.py [OUT_DIR]

writes ``circle.png`` and ``circle_stiffer.png`` into OUT_DIR (default ``out/quickstart``).
"""

import sys
from pathlib import Path

import tcpmm


def main(out_dir="out/quickstart"):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    machine = tcpmm.builtin_machine()
    y = machine.axes["Y"]
    stiffer = machine.with_axis("Y", y.replace(mechanics=y.mechanics.scaled(K_h=2.0)))
    command = tcpmm.paper_circle_command()
    tables = {}
    for name, m in (("circle", machine), ("circle_stiffer", stiffer)):
        result = tcpmm.analyse_circle(tcpmm.simulate(m, command), radius_m=0.035)
        result.plot(path=out / f"{name}.png")
        tables[name] = result.to_pandas()
        print(f"{name}: reversal spikes [um]")
        print(tables[name][["direction", "sensor", "spike_A_um", "spike_B_um", "spike_C_um",
                            "spike_D_um"]].round(2).to_string(index=False))
    return tables


if __name__ == "__main__":
    main(*sys.argv[1:])
