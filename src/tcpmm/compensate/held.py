"""Axes a program holds still that the model lacks: a G18 program's Y, which the
interpreter writes, on a machine of X and Z. The correction is learned without them and
they are put back where the program held them."""

from __future__ import annotations

import numpy as np

from ..path.command import Command


def without_held(machine, *commands) -> tuple:
    """The commands without the axes the model lacks and they hold still (a G18 program's
    Y, which the interpreter writes, on an X-Z machine), and those axes' positions; an
    axis the model lacks that moves is refused where the correction is learned [-, m]."""
    first = commands[0]
    held = {a: float(first.positions[a][0]) for a in first.axes if a not in machine.axes
            and all(np.ptp(c.positions[a]) == 0.0 for c in commands)}
    if not held:
        return commands, held
    return tuple(Command(c.time_s, {a: p for a, p in c.positions.items() if a not in held},
                         dict(c.meta)) for c in commands), held


def with_held(command, held: dict):
    """``command`` with the axes :func:`without_held` took out, where they were [m]."""
    if not held:
        return command
    n = command.time_s.size
    return Command(command.time_s, {**command.positions,
                                    **{a: np.full(n, v) for a, v in held.items()}},
                   dict(command.meta))
