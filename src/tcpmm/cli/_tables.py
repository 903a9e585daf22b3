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


def judged_rows(rows: list) -> list[dict]:
    """The rows of ``Comparison.judged_long`` as the terminal shows them: the raw spikes
    named raw, inside or not in words [-]."""
    return [{"dir": r["direction"], "figure": f"raw {r['figure']}"
             if r["figure"].startswith("spike") else r["figure"],
             "measured - predicted": r["measured_minus_predicted_um"],
             "90 % interval +-": r["half_width_90_um"],
             "inside": "-" if r["inside"] is None else "yes" if r["inside"] else "NO",
             "verdict": r["verdict"]} for r in rows]


def fixed(v: float, digits: int = 2) -> str:
    """``v`` to ``digits`` decimals, a value that rounds to zero without a sign (-0.00
    reads as a small negative value that is not there) [-]."""
    text = f"{v:.{digits}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def percent(share: float, decimals: int = 0, sep: str = "") -> str:
    """``share`` [-] in per cent with ``decimals``, more where they would round a share
    strictly between 0 and 1 to 0 % or 100 % ("99.8%", not "100%" beside the 0.2 % said
    not to be) [-]."""
    v = 100.0 * share
    while decimals < 4 and 0.0 < share < 1.0 and round(v, decimals) in (0.0, 100.0):
        decimals += 1
    return f"{v:.{decimals}f}{sep}%"


def _cell(v) -> str:
    """A number to two decimals (:func:`fixed`); one that does not exist (NaN) as a dash;
    yes or no [-]."""
    if isinstance(v, bool) or type(v).__name__ == "bool_":
        return "yes" if v else "no"
    if isinstance(v, float):
        return "-" if v != v else fixed(v)
    return str(v)


def print_table(table, console, title: str) -> None:
    """Print a result table (pandas) as a :func:`plain_table`, numbers to two decimals (a
    dash where there is none), so that nine columns fit in 80; on a terminal too narrow for
    it the columns after the leading names go into tables one under the other
    (:func:`column_parts`), so that no number and no word of a header is split.

    Parameters
    ----------
    table : pandas.DataFrame
        The table [-].
    console : rich.console.Console
        Where to print [-].
    title : str
        Title above it [-].
    """
    from pandas.api.types import is_numeric_dtype

    headers = [header(str(c)) for c in table.columns]
    rows = [[_cell(v) for v in row] for _, row in table.iterrows()]
    numeric = [is_numeric_dtype(table[c]) for c in table.columns]
    keys = next((i for i, n in enumerate(numeric) if n), len(numeric))
    parts = column_parts(headers, rows, numeric, keys, console.width)
    for n, (cols, widths) in enumerate(parts):
        t = plain_table([headers[i] for i in cols])
        for column, width in zip(t.columns, widths or (), strict=False):
            column.width = width
        for row in rows:
            t.add_row(*[row[i] for i in cols])
        print_plain(t, console, title if n == 0 else None)


#: Width between two columns of a :func:`plain_table`: a space of padding either side of
#: the blank rule [-].
GAP = 3


def _extent(cols, widths) -> int:
    """Width of a :func:`plain_table` of the columns ``cols`` at ``widths``, in
    characters [-]."""
    return sum(widths[i] for i in cols) + GAP * (len(cols) - 1)


def column_parts(headers, rows, numeric, keys: int, width: int) -> list[tuple]:
    """The columns of a table as parts that each fit ``width``, with their widths: the
    whole table where it fits unwrapped; else as few parts as fit, each holding the
    ``keys`` leading columns (the names of the rows) and a run of the others, cut where
    the fewest headers wrap, else as late as that allows (the first parts fullest), a
    part's widest columns narrowed first. A number is never split, nor a word of a header
    or a text; where even the names and one column do not fit, each column is a part of
    its own after the names, at its full width, wider than ``width``.

    Parameters
    ----------
    headers : list of str
        The columns' headers [-].
    rows : list of list of str
        The cells, row by row [-].
    numeric : list of bool
        Per column, whether its cells are numbers, which are kept whole [-].
    keys : int
        How many leading columns name the rows and go into every part [-].
    width : int
        Width to fit, in characters [-].

    Returns
    -------
    list of tuple
        Per part: the indices of its columns, and their widths in characters, or None
        where rich's own are kept [-].
    """
    from itertools import combinations

    from rich.cells import cell_len

    whole = list(range(len(headers)))
    hi, lo = [], []
    for i, (h, n) in enumerate(zip(headers, numeric, strict=True)):
        cells = [row[i] for row in rows]
        hi.append(max(map(cell_len, [h, *cells])))
        pieces = cells if n else [w for c in cells for w in c.split()]
        lo.append(max(map(cell_len, [*h.split(), *pieces, ""])))
    names, rest = whole[:keys], whole[keys:]
    if _extent(whole, hi) <= width or not rest:
        return [(whole, None)]
    k = _fewest_parts(names, rest, lo, width)
    if k is None:  # the narrowest form that keeps every number whole: the lines overflow
        return [([*names, i], [hi[j] for j in (*names, i)]) for i in rest]
    runs = [[rest[a:b] for a, b in zip((0, *cut), (*cut, len(rest)), strict=True)]
            for cut in combinations(range(1, len(rest)), k - 1)]
    runs = [r for r in runs if all(_extent(names + p, lo) <= width for p in r)]
    best = min(runs, key=lambda r: (sum(max(_extent(names + p, hi) - width, 0) for p in r),
                                    [-len(p) for p in r]))
    return [(names + p, _narrowed(names + p, lo, hi, width)) for p in best]


def _fewest_parts(names, rest, lo, width: int) -> int | None:
    """How many parts the columns ``rest``, each part after the columns ``names``, take at
    least at their narrowest widths ``lo`` in ``width`` (each part filled in turn); None
    where the names and one column do not fit [-]."""
    parts, run = 1, []
    for i in rest:
        if _extent([*names, i], lo) > width:
            return None
        if _extent([*names, *run, i], lo) > width:
            parts, run = parts + 1, []
        run.append(i)
    return parts


def _narrowed(cols, lo, hi, width: int) -> list[int]:
    """Widths of the columns ``cols``, each between ``lo`` and ``hi``, the widest narrowed
    first until they fit ``width``, in characters [-]."""
    w = [hi[i] for i in cols]
    for _ in range(_extent(range(len(cols)), w) - width):
        j = max((k for k in range(len(cols)) if w[k] > lo[cols[k]]), key=w.__getitem__)
        w[j] -= 1
    return w


def plain_table(headers, left=()):
    """An empty result table in the one style of every command: no vertical rules, the head
    ruled below, columns apart by spaces (a pipe cuts them with awk), right-justified but
    for those named in ``left``; a header is text, its "[dB]" no markup.

    Parameters
    ----------
    headers : iterable of str
        The columns' headers [-].
    left : iterable of str
        Headers of the columns justified left (names, labels) [-].

    Returns
    -------
    rich.table.Table
        The table to add rows to and print with :func:`print_plain` [-].
    """
    from rich import box
    from rich.table import Table
    from rich.text import Text

    t = Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False, padding=(0, 1))
    for h in headers:
        t.add_column(Text(h), justify="left" if h in left else "right", overflow="fold")
    return t


def print_plain(table, console, title: str | None = None, caption: str | None = None) -> None:
    """Print a :func:`plain_table` with its title on a line above and its caption on one
    below, never wrapped in a pipe or a log (rich centres and wraps its own to the table's
    width: a grep of a log for a figure in a caption would fail), no line ending in spaces
    (rich pads each row to the last column's width), and on a console that cannot write
    the rule of its head a rule of dashes [-]."""
    from rich.text import Text

    from ._app import on_screen
    from ._encoding import unicode_stream

    if not unicode_stream(console.file):
        table = _as_written(table, console.file)
    unwrapped = not on_screen(console)
    if title is not None:
        console.print(Text(title), soft_wrap=unwrapped)
    for part in ([table] if unwrapped else _fitted(table, console.width)):
        if console.options.ascii_only:  # rich's own stand-in is a box with vertical rules
            part.box = _ascii_head()
        # a part of the narrowest form is wider than the terminal: drawn at its width, not
        # folded to the terminal's, where its cells would come out blank
        wide = console.options.update_width(max(console.width, _width_of(console, part)))
        for segments in console.render_lines(part, wide, pad=False):
            line = Text()
            for s in segments:
                line.append(s.text, s.style)
            line.rstrip()
            console.print(line, soft_wrap=True)
    if caption is not None:
        console.print(Text(caption), soft_wrap=unwrapped)


def _width_of(console, table) -> int:
    """The width ``table`` takes unfolded, in characters [-]."""
    from rich.measure import Measurement

    unbounded = console.options.update_width(1_000_000)  # a measure is held to its width
    return Measurement.get(console, unbounded, table).maximum


def _fitted(table, width: int) -> list:
    """A :func:`plain_table` as tables one under the other that each fit a terminal of
    ``width`` (:func:`column_parts`; the leading columns justified left name the rows and
    go into each), so that rich does not fold a number across lines; the table itself
    where it fits [-]."""
    def plain(cell) -> str:
        return cell.plain if hasattr(cell, "plain") else str(cell)

    headers = [plain(c.header) for c in table.columns]
    rows = [list(r) for r in zip(*[[plain(x) for x in c.cells] for c in table.columns],
                                 strict=True)]
    numeric = [c.justify == "right" for c in table.columns]
    keys = next((i for i, n in enumerate(numeric) if n), len(numeric))
    parts = column_parts(headers, rows, numeric, keys, width)
    if len(parts) == 1 and parts[0][1] is None:
        return [table]
    out = []
    for cols, widths in parts:
        t = plain_table([headers[i] for i in cols],
                        left=[headers[i] for i in cols if not numeric[i]])
        for column, w in zip(t.columns, widths or (), strict=False):
            column.width = w
        for row in rows:
            t.add_row(*[row[i] for i in cols])
        out.append(t)
    return out


def _as_written(table, stream):
    """A :func:`plain_table` of the cells of ``table`` as ``stream`` writes them (µ as u
    where its encoding has no µ), so that rich measures what is written [-]."""
    from rich.text import Text

    from ._encoding import as_written

    def fit(cell):
        if isinstance(cell, Text):
            return Text(as_written(cell.plain, stream))
        return as_written(str(cell), stream)

    fitted = plain_table([fit(c.header).plain for c in table.columns])
    for new, old in zip(fitted.columns, table.columns, strict=True):
        new.justify, new.width = old.justify, old.width
    for row in zip(*(c.cells for c in table.columns), strict=True):
        fitted.add_row(*map(fit, row))
    return fitted


def _ascii_head():
    """The box of :func:`plain_table` in ASCII: its head ruled with dashes [-]."""
    from rich.box import Box

    return Box("    \n    \n -- \n    \n    \n    \n    \n    \n", ascii=True)
