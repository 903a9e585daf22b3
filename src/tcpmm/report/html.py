"""HTML building blocks of the report: page, section, table with its CSV, embedded figure.

Everything a page needs is inside it: the style sheet, the figures as PNG ``data:`` URIs and
each table's CSV as a ``data:`` download link, so the file opens with no network.
"""

from __future__ import annotations

import base64
import functools
import html
import io
import math
import re
from datetime import UTC, datetime
from pathlib import Path

from .. import __version__
from ..plot import pyplot

MINUS, DASH = "\u2212", "\u2014"

#: The page's style sheet: system fonts only, printable, no external resource.
CSS = """
:root { --ink: #1d2733; --muted: #5b6b7b; --line: #d5dce4; --band: #f3f6f9;
        --accent: #1f5fa8; --warn: #9a5b00; }
* { box-sizing: border-box; }
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, Helvetica, Arial,
       sans-serif; color: var(--ink); margin: 0; background: #fff; line-height: 1.45; }
header { background: var(--accent); color: #fff; padding: 18px 32px 14px; }
header h1 { margin: 0 0 4px; font-size: 24px; font-weight: 600; }
header p { margin: 0; opacity: 0.9; font-size: 13px; }
main { max-width: 1180px; margin: 0 auto; padding: 8px 32px 40px; }
nav { margin: 14px 0 4px; font-size: 14px; display: flex; flex-wrap: wrap; gap: 4px 18px; }
nav a { color: var(--accent); text-decoration: none; }
section { border-top: 2px solid var(--line); margin-top: 26px; padding-top: 6px; }
h1, h2, h3, p, dd, nav a { overflow-wrap: anywhere; }  /* a file name of no spaces */
td, th { overflow-wrap: break-word; }  /* anywhere would squeeze a column to letters */
h2 { font-size: 20px; margin: 10px 0 6px; color: var(--accent); }
h3 { font-size: 15px; margin: 18px 0 6px; }
p.note, p.lead { color: var(--muted); font-size: 13px; margin: 4px 0 8px; max-width: 900px; }
p.warn { color: var(--warn); font-size: 13px; margin: 4px 0; }
p.pass, p.fail, p.open { font-size: 20px; font-weight: 600; margin: 8px 0; padding: 8px 14px;
                         border-left: 6px solid; max-width: 900px; }
p.pass { color: #1e6b33; border-color: #2e8b47; background: #eef8f0; }
p.fail { color: #9b1c1c; border-color: #c53030; background: #fcefef; }
p.open { color: var(--ink); border-color: var(--accent); background: var(--band); }
table { border-collapse: collapse; font-size: 13px; margin: 6px 0 2px;
        font-variant-numeric: tabular-nums; }
th, td { border-bottom: 1px solid var(--line); padding: 3px 10px; }
th { background: var(--band); text-align: left; font-weight: 600; white-space: nowrap; }
td.num { text-align: right; white-space: nowrap; }
td.na { color: var(--muted); text-align: right; }
tr:hover td { background: #fafcfe; }
.tablebox { overflow-x: auto; max-width: 100%; }
a.csv { font-size: 12px; color: var(--accent); text-decoration: none; }
a.csv::before { content: "\\2913  "; }
figure { margin: 10px 0 4px; }
figure img { max-width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { color: var(--muted); font-size: 12px; }
dl.facts { display: grid; grid-template-columns: max-content auto; gap: 2px 14px;
           font-size: 13px; margin: 6px 0; }
dl.facts dt { color: var(--muted); }
dl.facts dd { margin: 0; }
footer { color: var(--muted); font-size: 12px; margin-top: 30px; }
@media print { header { background: none; color: var(--ink); } nav { display: none; }
               section { break-inside: avoid-page; }
               main { max-width: none; padding: 0 4px; }
               .tablebox { overflow: visible; }
               table { width: 100%; font-size: 7.5pt; }
               th, td { padding: 1px 3px; }
               th { white-space: normal; } }
"""


def esc(text) -> str:
    """``text`` escaped for HTML [-]."""
    return html.escape(str(text), quote=True)


def data_uri(data: bytes, mime: str) -> str:
    """A ``data:`` URI holding ``data`` [-]."""
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


def figure_png(fig, dpi: int = 110) -> bytes:
    """A matplotlib figure as PNG bytes; the figure is closed [-]."""
    buf = io.BytesIO()
    try:
        fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    finally:
        pyplot().close(fig)
    return buf.getvalue()


def figure(image, alt: str, caption: str | None = None, width_px: int | None = None) -> str:
    """An embedded figure from a matplotlib figure or PNG bytes, at most ``width_px`` wide
    on the page (default: its own width, up to the page's) [-]."""
    png = image if isinstance(image, bytes) else figure_png(image)
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    style = f' style="max-width: min(100%, {width_px}px)"' if width_px else ""
    return (f'<figure><img alt="{esc(alt)}"{style} src="{data_uri(png, "image/png")}">'
            f"{cap}</figure>")


def number(v: float, digits: int | None = None) -> str:
    """``v`` with ``digits`` decimals, or four significant digits without an exponent
    from 0.001 to 10^6 when ``digits`` is None; never a negative zero; n/a for NaN [-]."""
    if v != v:
        return "n/a"
    if digits is not None:
        text = f"{v:.{digits}f}"
    elif v == 0 or not 1e-3 <= abs(v) < 1e6:
        mantissa, _, exponent = f"{v:.3e}".partition("e")
        text = f"{mantissa.rstrip('0').rstrip('.')}e{exponent}" if v else "0"
    else:
        text = f"{v:.{max(0, 3 - math.floor(math.log10(abs(v))))}f}"
        text = text.rstrip("0").rstrip(".") if "." in text else text
    return text.lstrip("-") if float(text) == 0 else text


def _cell(value, digits) -> str:
    """One table cell: numbers right-aligned (an integer as one), NaN as n/a [-]."""
    if isinstance(value, bool):
        return f'<td>{"yes" if value else "no"}</td>'
    if isinstance(value, int):  # a count or a rank: no decimals
        return f'<td class="num">{esc(str(value).replace("-", MINUS))}</td>'
    if isinstance(value, float):
        v = float(value)
        if math.isnan(v):
            return '<td class="na">n/a</td>'
        return f'<td class="num">{esc(number(v, digits).replace("-", MINUS))}</td>'
    return f"<td>{esc(value)}</td>"


def table(frame, csv_name: str, digits: dict | int | None = 2, caption: str | None = None) -> str:
    """A table and the link that downloads it as CSV.

    Parameters
    ----------
    frame : pandas.DataFrame
        The table; column names carry their units, e.g. ``spike A [µm]`` [-].
    csv_name : str
        File name the CSV downloads as [-].
    digits : int or dict or None
        Decimals of the numbers (``None``: four significant digits), one for all columns
        or per column name (a column not named: two decimals) [-].
    caption : str, optional
        Line under the table [-].
    """
    import numpy as np

    per = digits if isinstance(digits, dict) else {}
    # the download holds the words shown
    frame = frame.map(lambda v: in_words(v) if isinstance(v, str) else v)
    head = "".join(f"<th>{esc(c)}</th>" for c in frame.columns)
    rows = []
    for rec in frame.itertuples(index=False):
        cells = []
        for c, v in zip(frame.columns, rec, strict=True):
            v = v.item() if isinstance(v, np.generic) else v
            cells.append(_cell(v, per.get(c, 2) if isinstance(digits, dict) else digits))
        rows.append("<tr>" + "".join(cells) + "</tr>")
    csv = frame.to_csv(index=False, lineterminator="\n").encode("utf-8")
    link = (f'<a class="csv" download="{esc(csv_name)}" '
            f'href="{data_uri(csv, "text/csv;charset=utf-8")}">{esc(csv_name)}</a>')
    cap = f'<p class="note">{esc(caption)}</p>' if caption else ""
    return (f'<div class="tablebox"><table data-csv="{esc(csv_name)}"><thead><tr>{head}</tr>'
            f'</thead><tbody>{"".join(rows)}</tbody></table></div>{link}{cap}')


def facts(items) -> str:
    """A two-column list of ``(name, value)`` [-]."""
    body = "".join(f"<dt>{esc(k)}</dt><dd>{esc(in_words(str(v)))}</dd>" for k, v in items)
    return f'<dl class="facts">{body}</dl>'


#: The unit micrometre as the command line writes it in messages (``um``, ASCII for any
#: terminal), not a part of a name (``--tolerance-um``, ``radial_max_um``)
_UM = re.compile(r"(?<![-\w])um\b")


#: What the command line's messages say in its own terms, and the page in its words: a
#: pointer to ``--json``, which a report has not (its circle table holds the raw spikes),
#: and the keys of the quantities identification may leave open (:func:`_quantities`)
_WORDS = ((" (the raw e - b are in --json)", " (the raw spikes, e \u2212 b, are in the "
                                               "circle's table)"),
          (" (the move is in --json, tail_shift)", ""))


@functools.cache
def _quantities():
    """The keys of the quantities identification may leave open, and the pattern of a
    message naming one of an axis ("axis X guideway_share, open"); the model table's
    column of the model file's keys keeps them [-]."""
    from ..uncertainty.verdict_text import QUANTITY_WORDS  # its package brings the simulator

    return QUANTITY_WORDS, re.compile(r"(\baxis \w+,? )(" + "|".join(QUANTITY_WORDS)
                                      + r")\b")


def in_words(text: str) -> str:
    """``text``, a message of the command line, as the page says it: micrometres ``µm``
    (the command line writes ``um``), no pointer to ``--json`` and no key of a quantity
    where the docs have words for it [-]."""
    for console, page_words in _WORDS:
        text = text.replace(console, page_words)
    words, pattern = _quantities()
    return pattern.sub(lambda m: m.group(1) + words[m.group(2)], _UM.sub("µm", text))


def para(text: str, kind: str = "note") -> str:
    """A paragraph of class ``kind`` (note, lead, warn; pass, fail or open for a
    verdict), in the page's words (:func:`in_words`) [-]."""
    return f'<p class="{kind}">{esc(in_words(text))}</p>'


def section(key: str, title: str, body: str) -> tuple[str, str, str]:
    """A report section: ``(key, title, html)``; ``key`` is its anchor and its
    ``data-section`` [-]."""
    return key, title, (f'<section id="{esc(key)}" data-section="{esc(key.split("-")[0])}">'
                        f"<h2>{esc(title)}</h2>{body}</section>")


def distinct_names(files) -> dict[str, str]:
    """Per file (by its path as text), its name with as many of its folders as tell it
    from the other files of that name: ``mon/run.csv`` and ``tue/run.csv``; the name
    alone where no other shares it [-]."""
    paths = {str(f): Path(str(f)).absolute().parts for f in files}
    out = {}
    for key, parts in paths.items():
        others = {p for p in paths.values() if p != parts}
        n = 1
        while n < len(parts) and any(o[-n:] == parts[-n:] for o in others):
            n += 1
        out[key] = "/".join(parts[-n:])
    return out


def page(title: str, sections, inputs=()) -> str:
    """The whole report page.

    Parameters
    ----------
    title : str
        Page title [-].
    sections : list of tuple
        ``(key, title, html)`` from :func:`section`, in the order shown [-].
    inputs : list of tuple
        ``(what, file)`` named in the header, or ``(what, file, shown)`` for a file
        staged to be moved to ``shown`` [-].
    """
    stamp = datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC")
    toc = "".join(f'<a href="#{esc(k)}">{esc(t)}</a>' for k, t, _ in sections)
    shown = distinct_names(f for _, f, *_ in inputs)
    given = "; ".join(f"{w}: {shown[str(f)]}" for w, f, *_ in inputs)
    sub = f"tcpmm {__version__}, {stamp}" + (f" {DASH} {given}" if given else "")
    body = "".join(h for _, _, h in sections) + _inputs(inputs)
    return ("<!DOCTYPE html>\n"
            f'<html lang="en"><head><meta charset="utf-8"><title>{esc(title)}</title>'
            '<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<style>{CSS}</style></head><body><header><h1>{esc(title)}</h1>"
            f"<p>{esc(sub)}</p></header><main><nav>{toc}</nav>{body}"
            "<footer>SI inside the model; lengths here in mm and µm, as each column says. "
            "Tables download as CSV from the link under each.</footer></main></body></html>\n")


def _inputs(inputs) -> str:
    """The files the report was made from, each with its full path and the time it was
    last written (a measurement's date where the recorder wrote it then), to tell one
    machine's and one day's report from another's [-]."""
    items = []
    for what, f, *shown in inputs:  # shown: where a file being staged will be
        p = Path(str(f))
        try:
            when = datetime.fromtimestamp(p.stat().st_mtime, UTC).strftime(
                "%Y-%m-%d %H:%M UTC")
        except OSError:  # a built-in machine, or a file gone since
            items.append((what, str(f)))
            continue
        items.append((what, f"{shown[0] if shown else p.resolve()} (written {when})"))
    return (f'<div class="inputs" id="inputs"><h3>Inputs</h3>{facts(items)}</div>'
            if items else "")
