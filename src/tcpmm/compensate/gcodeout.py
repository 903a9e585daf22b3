"""The compensated command as an NC program: one G1 block per interpolator period."""

from __future__ import annotations

import numpy as np

from ..io.atomic import write_text_atomic


def dense_program(command, title: str = "compensated command") -> str:
    """G-code text: absolute G1 moves in mm, one per sample, each at the feed that covers
    its step in one period [-].

    Parameters
    ----------
    command : Command
        The command to write [m].
    title : str
        Comment at the head of the program [-].
    """
    axes = [a for a in command.axes if a in ("X", "Y", "Z")]
    pos = np.array([command.positions[a] for a in axes]) * 1e3  # mm
    step = np.linalg.norm(np.diff(pos, axis=1), axis=0)
    feed = step / command.period_s * 60.0  # mm/min
    first = " ".join(f"{a}{p:.6f}" for a, p in zip(axes, pos[:, 0], strict=True))
    lines = [f"({title}: {pos.shape[1]} samples at {command.period_s:g} s)",
             "G90 G17 G21 G61", f"G0 {first}"]
    for k in range(1, pos.shape[1]):
        if step[k - 1] <= 0.0:
            lines.append(f"G4 P{command.period_s:g}")
            continue
        words = " ".join(f"{a}{p:.6f}" for a, p in zip(axes, pos[:, k], strict=True))
        lines.append(f"G1 {words} F{feed[k - 1]:.4f}")
    lines.append("M30")
    return "\n".join(lines) + "\n"


def write_dense_program(command, path) -> None:
    """Write :func:`dense_program` atomically [-]."""
    write_text_atomic(path, dense_program(command))
