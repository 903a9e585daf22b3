"""A command's start-up without the cyclic collector's passes over its imports.

Importing numpy, pydantic, typer and the models builds some hundred thousand objects, none
of them garbage; the collector's default thresholds walk them again and again while they
are made (some 25 ms of a short command such as a simulation of the paper's circle, the
same again on every command). The first collection is held back until the command has
made :data:`START_THRESHOLD` objects the collector tracks; from it on, the interpreter's
own thresholds apply, so a long command collects as it always did.
"""

from __future__ import annotations

import gc
import operator
import sys

from ._stops import stop_not_ignored

#: Net allocations of tracked objects before the first collection [-]; a short command's
#: imports and run stay below it, the cyclic garbage it may hold back is bounded by it.
START_THRESHOLD = 200_000


def collect_late() -> None:
    """Raise the first generation's threshold to :data:`START_THRESHOLD` until the first
    collection, then restore the thresholds that were set."""
    thresholds = gc.get_threshold()
    if thresholds[0] == 0 or thresholds[0] >= START_THRESHOLD:
        return  # the collector is off, or already as lazy
    # a Ctrl-C that falls in the collection runs its handler in the callback, the first
    # code after it, where Python would ignore it: it is raised again, after the callback
    before = sys.unraisablehook
    sys.unraisablehook = ours = stop_not_ignored(before)

    def restore(phase: str, info: dict) -> None:
        if phase == "stop" and gc.get_threshold()[0] == START_THRESHOLD:
            gc.set_threshold(*thresholds)
            # replaced in its place by a function of C, not removed: removed while the
            # collector walks the list, it would make it skip the next callback; kept, a
            # Ctrl-C that falls in it on a later collection is "ignored" by Python
            gc.callbacks[gc.callbacks.index(restore)] = operator.is_
            if sys.unraisablehook is ours:  # a command's own hook stays
                sys.unraisablehook = before

    gc.callbacks.append(restore)
    gc.set_threshold(START_THRESHOLD, *thresholds[1:])
