"""A take-up width read from noise as a fraction of the search's step, whose interval holds
a step: the spikes after the terms read with it, at the first samples after the reversal,
hold much of the backlash (tests/test_circle_diagnostics.py's circles are sampled too
coarsely for it; these are as a ballbar logs them, 1 kHz at F10000 on R 35 mm)."""

import numpy as np

from conftest import run_cli

R_MM, FEED, RATE, START, SWEEP, DWELL = 35.0, 10000.0, 1000.0, 45.0, 450.0, 0.2


def _pair_file(path, direction, backlash_x_um, lag_y_s, noise_um, seed):
    """A circle run: the command, and the tool with a backlash of X (a step where X's
    velocity turns) and Y lagging its command, with noise on both axes [mm]."""
    s = 1.0 if direction == "ccw" else -1.0
    w = FEED / 60.0 / R_MM
    span = np.radians(SWEEP) / w
    t = np.arange(0.0, span + 2 * DWELL, 1.0 / RATE)

    def at(tt):
        th = np.radians(START) + s * w * np.clip(tt - DWELL, 0.0, span)
        return R_MM * np.cos(th), R_MM * np.sin(th)

    x_c, y_c = at(t)
    x, y = x_c.copy(), at(t - lag_y_s)[1]
    vx = np.gradient(x, t)
    sign = np.sign(np.where(np.abs(vx) > 1e-9, vx, 0.0))
    held = np.maximum.accumulate(np.where(sign != 0, np.arange(t.size), 0))
    sx = sign[held]
    rng = np.random.default_rng(seed)
    x = x - backlash_x_um * 1e-3 / 2 * sx + noise_um * 1e-3 * rng.normal(0, 1, t.size)
    y = y + noise_um * 1e-3 * rng.normal(0, 1, t.size)
    zero = np.zeros_like(t)
    rows = np.column_stack([t, x_c, y_c, zero, x, y, zero])
    np.savetxt(path, rows, delimiter=",", fmt="%.10g", comments="",
               header="time_s,x_cmd_mm,y_cmd_mm,z_cmd_mm,x_tcp_mm,y_tcp_mm,z_tcp_mm")
    return path


def test_a_width_a_step_may_be_leaves_no_spike_claimed(tmp_path, capsys):
    """A backlash of 5 um on X as a step, Y lagging 2 ms, 0.2 um of noise and no spike:
    the take-up width read 0.05 ± 0.09 um (the search's step 0.19), and the spike at C
    CCW, the first sample after X reverses, 3.66 ± 0.66 um, ranked among the error
    sources; read with a step, which the width's interval holds, it is 0.5 um. Its ±95%
    now holds the move to the step, and no spike is ranked."""
    ccw = _pair_file(tmp_path / "ccw.csv", "ccw", 5.0, 2e-3, 0.2, 204)
    cw = _pair_file(tmp_path / "cw.csv", "cw", 5.0, 2e-3, 0.2, 204)
    code, out, _ = run_cli(capsys, "circle", ccw, cw, "--radius", 35)
    assert code == 0
    line = next(x for x in out.splitlines() if x.startswith("spike C after the pair's terms"))
    value, pm = (float(v) for v in line.split()[6:9:2])
    assert abs(value) <= pm, line
    assert "not ranked: reversal spikes: none of the 8 spikes" in out
