"""The compensated command as an NC program: one G1 block per interpolator period."""

from __future__ import annotations

import numpy as np

from ..path.gcode_words import ZERO_MOVE_M


def dense_program(command, title: str = "compensated command", settle_s: float = 0.0) -> str:
    """G-code text: absolute G1 moves in mm, one per sample, each at the feed that covers
    its step in one period, in continuous-path mode (G64: under G61 each block would
    come to rest); a sample that rounds to within :data:`~tcpmm.path.gcode_words.ZERO_MOVE_M`
    on every axis of where the tool was last sent is a dwell of one period (a reader skips
    such a G1 as a move of zero length, as controllers do, and the program would lose that
    period; a step of the last written digit, 1 nm, is one) [-].

    Parameters
    ----------
    command : Command
        The command to write [m].
    title : str
        Comment at the head of the program [-].
    settle_s : float
        Dwell after the rapid to the first sample: the compensated command starts from
        rest there, and a machine still settling from the rapid starts off its path [s].
    """
    axes = [a for a in command.axes if a in ("X", "Y", "Z")]
    # rounded as written, and -0 made 0: "-0.000000" and "0.000000" are one place
    pos = np.round(np.array([command.positions[a] for a in axes]) * 1e3, 6) + 0.0  # mm
    step = np.linalg.norm(np.diff(pos, axis=1), axis=0)
    feed = step / command.period_s * 60.0  # mm/min
    words = [" ".join(f"{a}{p:.6f}" for a, p in zip(axes, pos[:, k], strict=True))
             for k in range(pos.shape[1])]
    lines = [f"({title}: {pos.shape[1]} samples at {command.period_s:g} s)",
             "G90 G17 G21 G64", f"G0 {words[0]}"]
    if settle_s > 0:
        lines.append(f"G4 P{settle_s:g}")
    # the reader's test on the text's millimetres, with room for their conversion to m
    near, last = ZERO_MOVE_M * 1e3 * (1 + 1e-6), pos[:, 0]
    for k in range(1, pos.shape[1]):
        if np.max(np.abs(pos[:, k] - last)) <= near:
            lines.append(f"G4 P{command.period_s:g}")
        else:
            lines.append(f"G1 {words[k]} F{feed[k - 1]:.4f}")
            last = pos[:, k]
    lines.append("M30")
    return "\n".join(lines) + "\n"

