"""Console tables of results that stay whole at 80 columns, with units in the headers."""

from __future__ import annotations

#: Short headers of the usual result columns; any other ``*_um`` column is named
#: ``<name> [µm]``.
HEADERS = {
    "direction": "dir", "contour_error_um": "contour [µm]", "circular_deviation_um": "G [µm]",
    "radial_rms_um": "rms [µm]", "radial_max_um": "max [µm]",
}


def header(column: str) -> str:
    """Console header of a result column, with its unit [-]."""
    if column in HEADERS:
        return HEADERS[column]
    if column.startswith("spike_") and column.endswith("_um"):
        return f"{column[6:-3] or 'spike'} [µm]"
    if column.endswith("_um"):
        return f"{column[:-3].replace('_', ' ')} [µm]"
    return column.replace("_", " ")


def raw_spike_named(figure: str) -> str:
    """A verdict's figure as a user reads it: ``"R35 spike A"`` is the raw ``e - b`` at A,
    which ``tcpmm circle`` does not lead with (it leads with the spike after the fitted
    terms) [-]."""
    for q in "ABCD":
        figure = figure.replace(f"spike {q}", f"raw spike {q} (e - b)")
    return figure


def judged_rows(rows: list) -> list[dict]:
    """The rows of ``Comparison.judged_long`` as the terminal shows them: the raw spikes
    named raw, inside or not in words [-]."""
    return [{"dir": r["direction"], "figure": f"raw {r['figure']}"
             if r["figure"].startswith("spike") else r["figure"],
             "measured - predicted": r["measured_minus_predicted_um"],
             "90 % interval +-": r["half_width_90_um"],
             "inside": "yes" if r["inside"] else "NO", "verdict": r["verdict"]} for r in rows]


def fixed(v: float, digits: int = 2) -> str:
    """``v`` to ``digits`` decimals, a value that rounds to zero without a sign (-0.00
    reads as a small negative value that is not there) [-]."""
    text = f"{v:.{digits}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def _cell(v) -> str:
    """A number to two decimals (:func:`fixed`); one that does not exist (NaN) as a dash;
    yes or no [-]."""
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return "yes" if v else "no"
    if isinstance(v, float):
        return "-" if v != v else fixed(v)
    return str(v)


def print_table(table, console, title: str) -> None:
    """Print a result table (pandas) as a rich table without vertical rules, numbers to
    two decimals (a dash where there is none), so that nine columns fit in 80.

    Parameters
    ----------
    table : pandas.DataFrame
        The table [-].
    console : rich.console.Console
        Where to print [-].
    title : str
        Title above it [-].
    """
    from rich import box
    from rich.markup import escape
    from rich.table import Table

    # the title is text: rich took its "[um]" for a style and printed it without
    t = Table(title=escape(title), box=box.SIMPLE_HEAD, pad_edge=False, padding=(0, 1))
    for c in table.columns:
        t.add_column(header(str(c)), justify="right", overflow="fold")
    for _, row in table.iterrows():
        t.add_row(*[_cell(v) for v in row])
    console.print(t)
