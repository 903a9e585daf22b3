"""A verdict's cause as the console and the page say it: the quantity in words, the key
kept for ``--json``."""

import re
from types import SimpleNamespace

import pytest

from tcpmm.report.accuracy import verdict_html
from tcpmm.uncertainty.verdict import FigureVerdict
from tcpmm.uncertainty.verdict_text import QUANTITY_WORDS

#: a snake_case key, which no sentence a user reads holds
KEY = re.compile(r"\b[a-z][a-z0-9]*(?:_[a-z0-9]+)+\b")


@pytest.mark.parametrize("quantity", sorted(QUANTITY_WORDS))
@pytest.mark.parametrize("opened", [False, True])
def test_identifys_verdict_lines_name_the_cause_in_words(quantity, opened, capsys):
    """identify printed "verdict R35 F5000 G (CW): 43.31 um, uncertain +- 7.56 um (axis Y
    guideway_share)", the JSON key where its report reads "guideway share of the
    friction"."""
    from tcpmm.cli.ident import _print_verdict

    cause = f"axis Y {quantity}" + (", open" if opened else "")
    fig = FigureVerdict("R35 F5000", "cw", "G", 43.31e-6, 7.56e-6, 1e-6, "uncertain",
                        cause, "friction runs with a finer scale")
    _print_verdict(SimpleNamespace(axes={}, figures=[fig], worst=lambda: {"R35 F5000 G": fig}),
                   "")
    [line] = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("verdict")]
    assert f"(axis Y {QUANTITY_WORDS[quantity]}" in line, line
    assert not KEY.search(line), line
    assert ("which the data leave open" in line) == opened
    assert fig.to_dict()["cause"] == cause  # the machine interface keeps its key
    page = verdict_html({"tests": ["R35 F5000"], "axes": {}, "figures": [fig.to_dict()]})
    assert QUANTITY_WORDS[quantity] in page and not KEY.search(re.sub(r"<[^>]+>", " ", page))
