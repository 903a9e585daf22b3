"""The command group: its commands listed in the order of the work, and its help never
wrapped where standard output is not a terminal."""

from __future__ import annotations

import sys

from typer.core import TyperGroup

#: The width the help is laid out at where standard output is no terminal: no line of
#: it wraps [characters].
UNWRAPPED = 1_000_000


class Workflow(TyperGroup):
    """Lists the commands in the order of the work (measure, identify, predict, analyse),
    whatever module registered them; commands not named here follow in their own order."""

    ORDER = ("demo", "machine", "excite", "identify", "frf", "bode", "path", "simulate",
             "circle", "contour", "compare", "spread", "sweep", "tune", "report")

    def make_context(self, info_name, args, parent=None, **extra):
        """The help is not wrapped when standard output is not a terminal (click's
        default of 80 columns split its sentences in a file, and cut the commands'
        summaries short with "..."); the commands' contexts inherit the widths."""
        if parent is None and not _stdout_is_terminal():
            extra.setdefault("terminal_width", UNWRAPPED)
            extra.setdefault("max_content_width", UNWRAPPED)
        return super().make_context(info_name, args, parent=parent, **extra)

    def list_commands(self, ctx):
        names = super().list_commands(ctx)
        rank = {n: i for i, n in enumerate(self.ORDER)}
        return sorted(names, key=lambda n: rank.get(n, len(rank)))


def _stdout_is_terminal() -> bool:
    try:
        return sys.stdout is not None and sys.stdout.isatty()
    except (AttributeError, ValueError):  # a replaced or closed stream
        return False
