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

    The samples of the program's G0 rapids (``command.blocks()``) are G1 blocks too, at
    the speed the command was planned to: a controller's own rapid would run them at its
    rapid speed and the program would no longer keep the compensated command's timing.
    A comment under the title says so, with the lines they are (:func:`rapid_note`).
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
    moved = np.zeros(pos.shape[1], dtype=bool)
    for k in range(1, pos.shape[1]):
        if np.max(np.abs(pos[:, k] - last)) <= near:
            lines.append(f"G4 P{command.period_s:g}")
        else:
            lines.append(f"G1 {words[k]} F{feed[k - 1]:.4f}")
            last, moved[k] = pos[:, k], True
    # the note goes under the title: the second sample's line is one further down
    note = rapid_note(command, moved, len(lines) - pos.shape[1] + 3)
    lines[1:1] = [note] if note else []
    lines.append("M30")
    return "\n".join(lines) + "\n"


#: The most runs of rapid lines :func:`rapid_note` lists one by one [-].
NOTE_RUNS = 12


def rapid_note(command, moved, first_line: int) -> str:
    """A comment saying which lines of the dense program are the program's G0 rapids,
    written as G1 at the planned speed; empty where the command has no rapid after its
    first sample (which the program's own G0 reaches) or no blocks (a command file) [-].

    Parameters
    ----------
    command : Command
        The command written, one line per sample [m].
    moved : ndarray of bool
        Per sample: written as a G1, not as a dwell (the hold after a program that ends
        on a rapid is no rapid written as G1) [-].
    first_line : int
        The line of the second sample in the program, 1 for the first line [-].
    """
    blocks = command.blocks()
    if blocks is None:
        return ""
    rapid = np.asarray(blocks[1][1:], dtype=bool) & moved[1:]
    edges = np.flatnonzero(np.diff(np.concatenate([[0], rapid.astype(int), [0]])))
    runs = [(first_line + a, first_line + b - 1) for a, b in zip(edges[::2], edges[1::2],
                                                                 strict=True)]
    if not runs:
        return ""
    shown = ", ".join(f"{a}" if a == b else f"{a}-{b}" for a, b in runs[:NOTE_RUNS])
    more = f" and {len(runs) - NOTE_RUNS} runs more" if len(runs) > NOTE_RUNS else ""
    return (f"(the program's G0 rapids are written as G1 at the speed the command was planned "
            f"to, so that it keeps the command's timing: lines {shown}{more})")
