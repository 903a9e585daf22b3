"""The report's section on the spread of a prediction: the reversal spikes over machines
drawn from what identification left uncertain, with the verdict on each figure."""

from __future__ import annotations

import json
from pathlib import Path

from ..errors import InputError
from ..plot.spread import plot_spread_rows
from ..whatif.spread import DRAWS_NOTE
from .html import figure, para, section, table


def spread_section(spread):
    """The reversal spikes of a prediction over machines drawn from what identification
    left uncertain.

    Parameters
    ----------
    spread : SpikeSpread or dict
        :func:`tcpmm.whatif.spread.circle_spread`, or its ``to_dict()`` (``tcpmm spread --json``)
        [-].
    """
    import pandas as pd

    data = spread.to_dict() if hasattr(spread, "to_dict") else spread
    body = para(f"{data['draws']} machines drawn from the identified uncertainty, "
                f"{data['sensor']} sensor. A quadrant point is "
                "settled when nine in ten draws give the spike the nominal sign, and held "
                f"when nine in ten lie within {data['tolerance_um']:g} µm of it (the "
                "verdicts' word firm is another test, of 1 µm). "
                f"{DRAWS_NOTE}: the same spike has an interval of each.", "lead")
    if hasattr(spread, "plot"):
        fig, what = spread.plot(), "draws (dots) and their range (bar)"
    else:
        fig = plot_spread_rows(data["spikes"], data["sensor"], data["tolerance_um"] * 1e-6,
                               data["draws"])
        what = "the range of the draws (bar)"
    body += figure(fig, "spread of the reversal spikes",
                   f"nominal spike (circle), {what}; ticks: rise and fall after the "
                   "reversal", 900)
    frame = pd.DataFrame(data["spikes"])
    if "draws_agree" in frame:  # its deprecated name, "firm", is the same column
        frame = frame.drop(columns="firm").rename(columns={"draws_agree": "firm"})
    frame = frame.rename(columns={
        "spike_um": "spike [µm]", "rise_um": "rise [µm]", "fall_um": "fall [µm]",
        "low_um": "lowest [µm]", "high_um": "highest [µm]",
        "same_sign": "same sign [%]", "within": "within tolerance [%]",
        "firm": f"held within {data['tolerance_um']:g} µm"})
    frame["direction"] = frame["direction"].str.upper()
    for c in ("same sign [%]", "within tolerance [%]"):
        frame[c] = 100.0 * frame[c]
    said = _verdicts(data.get("verdict"))
    if said:
        frame["verdict"] = [said.get((r["direction"], f"spike {r['point']}"), "")
                            for r in data["spikes"]]
    body += table(frame, "spread.csv", digits={"same sign [%]": 0, "within tolerance [%]": 0})
    bad = [f"{r['direction'].upper()} {r['point']}" for r in data["spikes"]
           if not (r["settled"] and r.get("draws_agree", r["firm"]))]
    if bad:
        body += para(f"Not settled or not held: {', '.join(bad)}; a measured spike there "
                     "can differ from the prediction by more than the tolerance.", "warn")
    return section("spread", "Spread of the prediction", body + _other_verdicts(data, said))


def _verdicts(verdict) -> dict:
    """Per ``(direction, figure)`` the verdict as the command line words it: firm with its
    interval, uncertain with it and its cause, undetermined with its cause; empty for a
    spread without verdicts [-]."""
    from ..uncertainty.verdict import verdict_words  # its module brings the simulator

    return {(f["direction"], f["figure"]): verdict_words(
        f["verdict"], f.get("half_width_um"), f["cause"], "±", "µm")
        for f in (verdict or {}).get("figures", [])}


def _other_verdicts(data: dict, said: dict) -> str:
    """The verdicts on the figures other than the spikes (contour error, G), and what would
    settle those not firm, as lines under the table [-]."""
    lines = [f"{d.upper()} {fig}: {text}" for (d, fig), text in said.items()
             if not fig.startswith("spike")]
    settle = sorted({f["settle"] for f in data.get("verdict", {}).get("figures", [])
                     if f["verdict"] != "firm" and f.get("settle")})
    out = "".join(para(line) for line in lines)
    if settle:
        out += para("To settle what is not firm: " + "; ".join(settle) + ".", "warn")
    return out


#: Keys of a spread row the section reads: numbers, then the rest.
SPREAD_NUMBERS = ("spike_um", "rise_um", "fall_um", "low_um", "high_um", "same_sign", "within")
SPREAD_ROW = ("direction", "point", *SPREAD_NUMBERS, "settled", "firm")


def read_spread_json(path) -> dict:
    """A spread as ``tcpmm spread --json`` prints it (``SpikeSpread.to_dict()``), checked.

    Parameters
    ----------
    path : str or Path
        The JSON file [-].
    """
    path = Path(path)
    fix = "write it with tcpmm spread MODEL.yaml ... --json > SPREAD.json"
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"is not a JSON file ({exc}); {fix}", file=path) from None
    if not isinstance(data, dict):
        raise InputError(f"holds no spread; {fix}", file=path)
    for key in ("draws", "sensor", "tolerance_um", "spikes"):
        if key not in data:
            raise InputError(f"has no '{key}', so it is not a spread; {fix}", file=path,
                             column=key)
    if not (_number(data["draws"]) and data["draws"] == int(data["draws"]) >= 1):
        raise InputError(f"'draws' must be a whole number of 1 or more; {fix}", file=path,
                         column="draws")
    if not (_number(data["tolerance_um"]) and data["tolerance_um"] > 0):
        raise InputError(f"'tolerance_um' must be a positive number; {fix}", file=path,
                         column="tolerance_um")
    rows = data["spikes"]
    if not (isinstance(rows, list) and rows and len(rows) % 4 == 0
            and all(isinstance(r, dict) for r in rows)):
        raise InputError(f"'spikes' must be rows for the quadrant points A-D of each circle; "
                         f"{fix}", file=path, column="spikes")
    for i, r in enumerate(rows):
        lack = [k for k in SPREAD_ROW if k not in r]
        bad = [k for k in SPREAD_NUMBERS if k in r and not (_number(r[k]) or r[k] is None)]
        if lack or bad:
            what = f"lacks {', '.join(lack)}" if lack else f"has no number in {', '.join(bad)}"
            raise InputError(f"row {i + 1} of 'spikes' {what}; {fix}", file=path,
                             column="spikes")
        r.update({k: float("nan") for k in SPREAD_NUMBERS if r[k] is None})
    return data


def _number(v) -> bool:
    """Whether a JSON value is a number (not a boolean) [-]."""
    return isinstance(v, int | float) and not isinstance(v, bool)
