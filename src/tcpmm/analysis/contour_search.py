"""The compiled search for each sample's nearest command segment
(:func:`tcpmm.path.nearest.nearest_segments`), in threads where the paths are long."""

from __future__ import annotations

import itertools
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .._threads import usable_cores

#: points of all paths together from which the paths are searched in threads: below, a
#: thread's start costs more than it saves [-]
_THREADED = 20_000


def searched(qs: dict, p, seg, ln2, tdir, sag, seglen, lo, hi, signed: bool, t_q,
             t_p) -> dict:
    """:func:`tcpmm.path.nearest.nearest_segments` of each path of ``qs`` (from the module
    compiled ahead of time, which spares the command numba's start); where the paths are
    long and there are cores, in threads, each path cut into as many runs of points as
    there are cores so that the threads finish together (the compiled search lets go of
    the interpreter lock, and each point's result is the same whatever run it is in)
    [m], [-]."""
    from .. import _compiled

    # the blocks and boxes of the command, once for every path and run of points
    blocks = _compiled.search_blocks(p, sag)

    def search(q, i0, i1):
        return _compiled.nearest_segments_in(q[i0:i1], p, seg, ln2, tdir, sag, seglen,
                                             lo[i0:i1], hi[i0:i1], int(signed), t_q[i0:i1],
                                             t_p, *blocks)

    cores = usable_cores()
    if cores < 2 or sum(q.shape[0] for q in qs.values()) < _THREADED:
        return {k: search(q, 0, q.shape[0]) for k, q in qs.items()}
    with ThreadPoolExecutor(cores) as pool:
        found = {k: [pool.submit(search, q, *r) for r in _parts(q.shape[0], cores)]
                 for k, q in qs.items()}
        parts = {k: [f.result() for f in fs] for k, fs in found.items()}
    return {k: tuple(np.concatenate(c) for c in zip(*ps, strict=True))
            for k, ps in parts.items()}


def _parts(n: int, parts: int) -> list:
    """``parts`` runs ``(i0, i1)`` of ``n`` points as near equal as may be [-]."""
    cut = [n * i // parts for i in range(parts + 1)]
    return list(itertools.pairwise(cut))
