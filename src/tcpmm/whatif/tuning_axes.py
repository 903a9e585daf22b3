"""Which axes a tuning matches: the axes the path moves, or those the user names.

Contouring axes share their position gain (and the feedforward) so that their lags
match; an axis the path does not move has no lag on the path to match, and tuning it with
the others would let it pull their gains down for nothing. So only the contouring axes
are matched (:func:`tcpmm.servo.tune.tune_machine`); every other axis is tuned on its own
(:func:`tcpmm.servo.tunealone.tune_alone`), and the feedforward is chosen on the path for
the contouring axes it moves only.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..servo.tune import check_margins, tune_machine
from ..servo.tunealone import tune_alone
from .tuning_limit import held_words

#: An axis whose command spans less than this is not moved by the path: the end points of
#: a program's arcs and lines, rounded, move an axis it does not drive by far less [m].
MOVED_TOLERANCE_M = 1e-6


def moved_axes(machine, command) -> list:
    """The machine's axes the command moves by more than :data:`MOVED_TOLERANCE_M` in its
    feed moves: an axis a program moves only in G0 rapids (a Z retracting between the
    passes) contours nothing, as ``tcpmm contour`` leaves the rapids out.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    command : Command
        The path [m].

    Returns
    -------
    list of str
        Axis names in the machine's order [-].
    """
    pos = command.positions
    blocks = command.blocks()
    feed = None if blocks is None else (blocks[1][1:] == 0) & (blocks[1][:-1] == 0)
    if feed is None or not feed.any():  # no program's blocks, or all of it rapids
        return [n for n in machine.axes
                if n in pos and float(np.ptp(pos[n])) > MOVED_TOLERANCE_M]
    return [n for n in machine.axes
            if n in pos and float(np.abs(np.diff(pos[n]))[feed].sum()) > MOVED_TOLERANCE_M]


def left_out_note(matched: list, moved: list) -> list:
    """A note where the contouring axes named leave out an axis the path moves: its lag is
    not matched to theirs, and the path's shape changes with the difference [-]."""
    out = [n for n in moved if n not in matched]
    if not matched or not out:
        return []
    return [f"--axes leaves out {', '.join(out)}, which the path moves: "
            f"{'its' if len(out) == 1 else 'their'} position gain is not matched to "
            f"{', '.join(matched)}'s, and a path through axes of different gains is "
            "distorted (a circle becomes an ellipse); name every axis the path contours"]


def contouring_axes(machine, names) -> list:
    """The axes named, as ``"XY"`` or ``"X,Y"`` or a sequence, in the machine's order; an
    axis the machine lacks is an :class:`~tcpmm.errors.InputError`.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    names : str or sequence of str
        The contouring axes [-].

    Returns
    -------
    list of str
        Axis names [-].
    """
    if isinstance(names, str):
        names = names.split(",") if "," in names else list(names)
    want = {n.strip().upper() for n in names if n.strip()}
    lacks = sorted(want - set(machine.axes))
    if lacks or not want:
        raise InputError(f"contouring axes: the machine has no axis {', '.join(lacks)} (it "
                         f"has {', '.join(machine.axes)})" if lacks else
                         "contouring axes: none named")
    return [n for n in machine.axes if n in want]


def tune_axes(machine, gm_db: float, pm_deg: float, matched: list,
              jobs: int | None = 1) -> dict:
    """Proposals per axis: the ``matched`` axes share a position gain, every other axis is
    tuned on its own.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    gm_db : float
        Required gain margin of both loops [dB].
    pm_deg : float
        Required phase margin of both loops [deg].
    matched : list of str
        The contouring axes [-].
    jobs : int, optional
        Processes for the matched axes' own loops (:func:`~tcpmm.servo.tune.tune_machine`) [-].

    Returns
    -------
    dict of str to AxisTuning
        In the machine's order [-].
    """
    check_margins(gm_db, pm_deg)
    sub = machine.model_copy(update={"axes": {n: machine.axes[n] for n in matched}})
    out = tune_machine(sub, gm_db, pm_deg, jobs) if matched else {}
    for n, a in machine.axes.items():
        if n not in out:
            out[n] = tune_alone(a.mechanics, a.servo, gm_db, pm_deg)
    return {n: out[n] for n in machine.axes}


def axis_reasons(axes: dict, matched: list, moved: list, named: bool,
                 predicted: bool = True, judged: bool = True, dropped: dict | None = None,
                 path: bool = True
                 ) -> dict:
    """Per axis, one sentence: whether the path moves it, whether its position gain is
    matched, and what became of its position gain and feedforward [-].

    Parameters
    ----------
    axes : dict of str to AxisTuning
        The proposals, feedforward included [-].
    matched, moved : list of str
        The contouring axes, and the axes the path moves [-].
    named : bool
        Whether the user named the contouring axes (``--axes``) [-].
    predicted : bool
        Whether the proposal's path is a prediction the feedforward could be chosen on [-].
    judged : bool
        Whether the path tells the feedforward fractions apart (a straight line does not:
        :data:`tcpmm.whatif.tuning.FEEDFORWARD_RESOLUTION_UM`) [-].
    dropped : dict, optional
        The feedforward fractions left out of the choice, with their path figures: a
        fraction lowered because the current limit left out the larger ones says so [-].
    path : bool
        Whether a path was predicted at all (a one-axis machine has no circle to run) [-].

    Returns
    -------
    dict of str to str
    """
    out = {}
    for n, t in axes.items():
        words = ["no path predicted" if not path else
                 "moved by the path" if n in moved else "not moved by the path"]
        if named and (n in matched) != (n in moved):
            words[0] += ", named by --axes" if n in matched else ", not named by --axes"
        b, a = t.before, t.after
        kpp = "K_pp kept" if a.K_pp == b.K_pp else \
            f"K_pp {'lowered' if a.K_pp < b.K_pp else 'raised'} to {a.K_pp:.4g} 1/s"
        if not t.met:  # that its settings are kept, and why, is its own note's to say
            words.append("its margins are not met")
        elif n in matched and len(matched) > 1:
            words.append(f"{kpp}, matched over {', '.join(matched)}")
        elif n in matched:
            words.append(f"{kpp}, no other axis to match")
        else:
            own = "" if a.K_pp == b.K_pp else " to meet its own margins"
            which = "" if named or not matched else ", which the path moves"
            words.append(f"{kpp}{own}; not matched to {', '.join(matched) or 'any axis'}"
                         + which)
        why = _kept_why(n in moved, n in matched, path and predicted, judged, path)
        if why:
            words.append(f"k_ff kept ({why})")
        elif t.met:
            words.append(f"k_ff {'kept' if a.k_ff == b.k_ff else f'{b.k_ff:g} -> {a.k_ff:g}'}"
                         ", chosen on the path"
                         + (held_words(dropped or {}, a.k_ff) if a.k_ff < b.k_ff else ""))
        out[n] = f"{n}: " + "; ".join(words)
    return out


def _kept_why(moved: bool, matched: bool, predicted: bool, judged: bool, path: bool) -> str:
    """Why an axis's feedforward is kept unchosen, or ``""`` where the path chooses it [-]."""
    return ("no path predicted to choose it on" if not path else
            "the path does not move it" if not moved else
            "it is not matched" if not matched else
            "the path is no prediction to choose it on" if not predicted else
            "the path does not judge it" if not judged else "")
