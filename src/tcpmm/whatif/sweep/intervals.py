"""The spread of a draws design: per point of its grid, the figures of the machines drawn
from the model's uncertainty, as their median and 90 % interval, and their change from the
grid's first point, draw by draw.

::

    OUT_DIR/intervals.csv    a row per point of the grid (the parameters given): the draws,
                             those that ran away, saturated or failed, and per figure the
                             5 %, 50 % and 95 % quantiles over the others, of the figure and
                             of its change from the first point

A sweep's figures of the model as identified carry that model's uncertainty; a draws design
shows how far. Draw ``k`` is the same machine at every point of the grid, so the change
from one point to another is taken on each draw and is often firmer than either figure:
the uncertainty the points share cancels.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...io.atomic import write_table_atomic
from .store import FEED_RUN, TEXT_COLUMNS

INTERVALS_FILE = "intervals.csv"
#: Quantiles of the draws written per figure, and their column names' parts [-].
QUANTILES = ((0.05, "low"), (0.5, "median"), (0.95, "high"))
#: Draws per point below which a 90 % interval is no more than the draws' extremes [-].
FEW_DRAWS = 20
_NOT_PARAMETERS = {"index", "variant", "draw", "seed", FEED_RUN, *TEXT_COLUMNS}


def draw_intervals(summary):
    """Per point of the grid, the draws' quantiles of each figure and of its change from
    the first point.

    Parameters
    ----------
    summary : pandas.DataFrame
        The rows of a draws design (``summary.csv``) [file units].

    Returns
    -------
    pandas.DataFrame
        The grid's parameters; ``draws`` (rows of the point) and ``draws_faulty`` (those
        with a fault, an error or no figure, left out); per figure ``F_um`` the columns
        ``F_low_um``, ``F_median_um``, ``F_high_um`` (its 5 %, 50 % and 95 % quantiles)
        and ``F_change_low_um`` ... (of the figure minus the same draw's at the first
        point); NaN where no draw is left [um].
    """
    import pandas as pd

    figures = [c for c in summary.columns if c.endswith("_um")]
    params = [c for c in summary.columns if c not in _NOT_PARAMETERS and c not in figures]
    values = summary[figures].to_numpy(float) if figures else np.zeros((len(summary), 0))
    bad = ~np.isfinite(values).any(axis=1) if figures else np.zeros(len(summary), bool)
    for c in ("fault", "error"):
        if c in summary:
            text = summary[c]
            bad |= text.notna().to_numpy() & (text.astype(str).str.len().to_numpy() > 0)
    values = np.where(bad[:, None], np.nan, values)
    draw = summary["draw"].to_numpy() if "draw" in summary else np.arange(len(summary))
    points = (summary.groupby(params, sort=False, dropna=False).indices if params
              else {(): np.arange(len(summary))})
    first = None
    rows = []
    for key, idx in sorted(points.items(), key=lambda kv: kv[1].min()):  # the design's order
        by_draw = dict(zip(draw[idx], values[idx], strict=True))
        first = by_draw if first is None else first
        base = np.array([first.get(k, np.full(len(figures), np.nan)) for k in draw[idx]])
        key = key if isinstance(key, tuple) else (key,)
        row = {**dict(zip(params, key, strict=True)), "draws": idx.size,
               "draws_faulty": int(bad[idx].sum())}
        for j, c in enumerate(figures):
            name = c.removesuffix("_um")
            row.update(_quantiles(values[idx, j], name))
            row.update(_quantiles(values[idx, j] - base[:, j], f"{name}_change"))
        rows.append(row)
    return pd.DataFrame(rows)


def _quantiles(v: np.ndarray, name: str) -> dict:
    """``{name_low_um: ..., ...}``: the quantiles of the finite values, NaN for none [um]."""
    v = v[np.isfinite(v)]
    return {f"{name}_{suffix}_um": float(np.quantile(v, q)) if v.size else float("nan")
            for q, suffix in QUANTILES}


def write_intervals(out_dir, summary_path) -> Path:
    """:func:`draw_intervals` of the summary, written as ``intervals.csv`` [-]."""
    import pandas as pd

    summary = pd.read_csv(summary_path, keep_default_na=False, na_values=[""])
    path = Path(out_dir, INTERVALS_FILE)
    write_table_atomic(draw_intervals(summary), path, "%.10g")
    return path
