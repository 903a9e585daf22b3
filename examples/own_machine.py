"""Your own machine, end to end: measure, identify, predict, compare.

On a real machine you record the measurement bundle (docs/measure.md) and a circular
test with a TCP device. Here a virtual machine stands in for it: the built-in machine
with a heavier table on X plays the machine you do not know. The script

1. records its bundle (servo-excitation sweep and friction runs per axis),
2. identifies a model from the bundle alone (``tcpmm identify``),
3. records the circular test on the machine and predicts it with the identified model,
4. compares them as the paper's Table 2 does (measured - predicted, TCP).

    python examples/own_machine.py [OUT_DIR]

writes ``bundle/``, ``identified_model.yaml`` and ``table2.png`` into OUT_DIR (default
``out/own_machine``).
"""

import sys
from pathlib import Path

import tcpmm


def main(out_dir="out/own_machine"):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    builtin = tcpmm.builtin_machine()
    x = builtin.axes["X"]
    machine = builtin.with_axis("X", x.replace(mechanics=x.mechanics.scaled(M_t=1.3)))

    bundle = tcpmm.virtual_bundle(machine, out / "bundle")                    # 1. measure
    identification = tcpmm.identify(bundle)                                 # 2. identify
    model = identification.machine
    tcpmm.save_model(model, out / "identified_model.yaml")
    print("table mass of X [kg]: true", round(machine.axes["X"].mechanics.M_t, 1),
          "identified", round(model.axes["X"].mechanics.M_t, 1))

    command = tcpmm.paper_circle_command()
    measured = tcpmm.virtual_run(machine, command)                           # 3. predict
    predicted = tcpmm.simulate(model, command)
    table2 = tcpmm.compare(measured, predicted, radius_m=0.035)              # 4. compare
    table2.plot(path=out / "table2.png")
    rows = table2.to_pandas()
    print(rows[rows["sensor"] == "tcp"].round(2).to_string(index=False))
    return table2


if __name__ == "__main__":
    main(*sys.argv[1:])
