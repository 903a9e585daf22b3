"""Draw the pictures of the documentation: the paper's circular test on the built-in
machine, as ``make demo`` draws it (``circle.png``).

    .venv/bin/python docs/img/make_images.py
"""

from pathlib import Path

import tcpmm
from tcpmm.plot.circle import plot_circle

HERE = Path(__file__).resolve().parent


def main():
    run = tcpmm.simulate(tcpmm.builtin_machine(), tcpmm.paper_circle_command())
    result = tcpmm.analyse_circle(run, radius_m=0.035)
    fig = plot_circle(result, title="Circle R35 mm, F5000 mm/min, built-in machine")
    fig.savefig(HERE / "circle.png", dpi=60, bbox_inches="tight")


if __name__ == "__main__":
    main()
