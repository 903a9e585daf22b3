"""The steps of an axis whose command holds still, taken from a cycle of its states.

Under a command that holds one position (an axis the program does not move: Z under a
program in the XY plane) the velocity-loop step is one and the same map of the axis's
state, a map the kernel computes to the bit. Once the state at a record comes back to the
bits it had at an earlier record, with the counters of the loops (in the state) the same,
every step after repeats those between, record for record: an axis at rest comes back
after one record, an axis that hunts about its position under its friction and the
quantisation of its encoder after its limit cycle (the Z axis of ``builtin:vmc``, about
two seconds). :class:`HeldCommand` runs the kernel a record at a time until its state
comes back and then copies the cycle's records and state instead of computing them:
the same records and state as the kernel's, to the bit. Where none comes back within
:data:`MAX_RECORDS` records, the rest of the held command runs through the kernel as
before.
"""

from __future__ import annotations

import numpy as np

from . import layout as L

#: Records run one at a time while looking for a cycle of a held command's states, the
#: most before the kernel runs the rest in one call: a call a record costs some
#: microseconds, some hundred times a record's steps [-].
MAX_RECORDS = 6000


def held(cmd: np.ndarray, vcmd: np.ndarray) -> bytes | None:
    """The bits of a command and command velocity that hold still over a piece (the same
    bits at every sample: ``-0.0`` is not ``0.0``, as the records tell them apart), or
    ``None`` where they do not [-]."""
    if cmd.size == 0:
        return None
    c, v = cmd.view(np.int64), vcmd.view(np.int64)
    if (c != c[0]).any() or (v != v[0]).any():
        return None
    return cmd[:1].tobytes() + vcmd[:1].tobytes()


class HeldCommand:
    """The records of an axis under a held command, from a cycle of its states once one
    is found (module docstring).

    Parameters
    ----------
    rec_every : int
        Velocity-loop steps a record [-].
    """

    def __init__(self, rec_every: int):
        self.rec_every = rec_every
        self.reset(None)

    def reset(self, bits: bytes | None) -> None:
        """Forget the states seen: the command now holds ``bits`` (``None``: it moves) [-]."""
        self.bits = bits
        self.looked = 0  # records looked at under this command
        self._restart()

    def _restart(self) -> None:
        """Forget the states seen, not how many [-]."""
        self.seen: dict = {}  # a state's bits -> its index in ``states``
        self.states: list = []  # (plant state, carried state) at each record looked at
        self.recs: list = []  # the record of each of those steps
        self.start = 0  # the step of ``states[0]``
        self.cycle: tuple | None = None  # (index of its first state, records, their count)

    def run(self, bits: bytes, steps, first: int, stop: int, x, state) -> np.ndarray:
        """The records of steps ``first`` to ``stop - 1`` under the held command ``bits``.

        Parameters
        ----------
        bits : bytes
            The command's bits (:func:`held`) [-].
        steps : callable
            ``steps(a, b)``: the kernel's records of steps ``a`` to ``b - 1`` from the
            axis's present state, which it advances [SI].
        first, stop : int
            The steps [-].
        x, state : callable, ndarray
            ``x()`` the axis's plant state, ``x(new)`` sets it; the carried state the
            kernel reads and writes (:mod:`tcpmm.sim.layout`) [SI].

        Returns
        -------
        ndarray (8, n)
            The records [SI].
        """
        if bits != self.bits:
            self.reset(bits)
        re, out, k = self.rec_every, [], first
        if state[L.S_SET] == 0.0 or k % re:  # from rest, or between two records
            k = min(stop, (k // re + 1) * re)
            out.append(steps(first, k))
        while k < stop and (self.cycle is not None or self.looked < MAX_RECORDS):
            if self.cycle is None and not self._look(k, x(), state):
                out.append(steps(k, min(stop, k + re)))
                self.recs.append(out[-1][:, 0])
                k = min(stop, k + re)
                continue
            k = self._copied(k, stop, x, state, out)
            break
        if k < stop:
            out.append(steps(k, stop))
        return out[0] if len(out) == 1 else np.concatenate(out, axis=1)

    def _look(self, k: int, x, state) -> bool:
        """Whether the state at record step ``k`` is one seen before (and so closes a
        cycle); else kept [-]."""
        if self.states and k != self.start + len(self.states) * self.rec_every:
            self._restart()  # not the steps that follow those kept
        self.looked += 1
        if not self.states:
            self.start = k
        kept = state.copy()
        kept[L.S_STEP] = kept[L.S_CMD0] = 0.0  # the step counts on; the piece's first sample
        key = x.tobytes() + kept.tobytes()
        first = self.seen.get(key)
        if first is None:
            self.seen[key] = len(self.states)
            self.states.append((x.copy(), kept))
            return False
        n = len(self.states) - first
        self.cycle = (first, np.stack(self.recs[first:], axis=1), n)
        self.start += first * self.rec_every  # the cycle's first record, at phase 0
        self.states = self.states[first:]
        self.seen, self.recs = {}, []
        return True

    def _copied(self, k: int, stop: int, x, state, out: list) -> int:
        """The cycle's records from record step ``k`` (on the cycle) to the last record
        step before ``stop`` into ``out``, the axis's state set to the cycle's there; that
        step [-]."""
        _, recs, n = self.cycle
        whole = (stop - k) // self.rec_every
        phase = (k - self.start) // self.rec_every
        out.append(_repeated(recs, phase % n, whole))
        end = k + whole * self.rec_every
        xs, kept = self.states[(phase + whole) % n]
        x(xs.copy())
        cmd0 = state[L.S_CMD0]
        state[:] = kept
        state[L.S_STEP], state[L.S_CMD0] = end, cmd0
        return end


def _repeated(recs: np.ndarray, phase: int, count: int) -> np.ndarray:
    """``count`` columns of the cycle ``recs`` from its column ``phase`` on, round and
    round: copied in blocks that double, not gathered a column at a time [SI]."""
    n = recs.shape[1]
    out = np.empty((recs.shape[0], count))
    head = min(n - phase, count)
    out[:, :head] = recs[:, phase:phase + head]
    done = head
    if done < count:
        done = min(n, count)
        out[:, head:done] = recs[:, :done - head]
    while done < count:  # ``done`` is a whole number of cycles from here on
        m = min(done, count - done)
        out[:, done:done + m] = out[:, :m]
        done += m
    return out
