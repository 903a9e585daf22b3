"""Every scale ring's label of the circle plot can be read: none lies under a trace drawn
in the panel, also where a trace runs on its ring all the way round (a sensor reading the
nominal circle, a trace of constant radial error)."""

import matplotlib
import numpy as np
import pytest

from tcpmm.analysis.circular import analyse_circle
from test_circle import R, circle_path, make_run, polar_perturb

matplotlib.use("Agg")


def _covered(fig):
    """``{label: [(share, above), ...]}`` over every panel, one pair per line drawn
    (traces and the nominal circle): the share of the label's length the line runs along
    inside its box, in the display's pixels (0 where it does not enter the box, small where
    it crosses it, about 1 where it runs along it), and whether the label is drawn over
    it."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    out = {}
    for ax in fig.axes:
        labels = [t for t in ax.texts if isinstance(t, matplotlib.text.Annotation)
                  and t.get_text().endswith("µm")]
        lines = [ln for ln in ax.lines if ln.get_linestyle() in ("-", ":", "--")]
        for t in labels:
            rot = t.get_rotation()
            t.set_rotation(0.0)
            box = t.get_window_extent(renderer)
            t.set_rotation(rot)
            c, a = ax.transData.transform(t.xy), np.radians(rot)
            turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            for ln in lines:
                u, v = ((ax.transData.transform(ln.get_xydata()) - c) @ turn).T
                inside = (np.abs(u) < 0.5 * box.width) & (np.abs(v) < 0.5 * box.height)
                run = np.ptp(u[inside]) / box.width if inside.any() else 0.0
                out.setdefault(t.get_text(), []).append(
                    (float(run), t.get_zorder() > ln.get_zorder()))
    return out


@pytest.mark.parametrize("error_um", [0.0, 20.0, -20.0])
def test_a_trace_on_a_ring_all_the_way_round_leaves_its_label_readable(error_um):
    """A TCP trace of constant radial error runs on its ring (0 µm: the nominal circle)
    all the way round, so wherever the label stands along that ring it lay under the
    trace; a 2-lobed error of the scale beside it makes the rings. That label is drawn over
    the traces; the others, which a trace at most crosses, stay under them (a white box
    over a crossing trace reads as a gap in the path). The nominal circle, dashed, runs
    along the 0 µm label always: the label lies over it, as a map's contour label breaks
    its line."""
    p = circle_path()
    err = (lambda a: error_um * 1e-6 + 0.0 * a) if error_um else (lambda a: 0.0 * a)
    wavy = polar_perturb(p, (0.0, 0.0), lambda a: 20e-6 * np.cos(2 * a))
    run = make_run(p, polar_perturb(p, (0.0, 0.0), err))
    run.axes["X"].scale, run.axes["Y"].scale = wavy[:, 0], wavy[:, 1]
    fig = analyse_circle(run, R).plot()
    covered = _covered(fig)
    ring = f"{error_um:+g} µm" if error_um else "0 µm"
    assert ring in covered, covered
    assert all(share < 0.5 or above for lines in covered.values() for share, above in lines)
    sensors_above = {t for t, lines in covered.items() if all(above for _, above in lines)}
    assert sensors_above == {ring}, covered
