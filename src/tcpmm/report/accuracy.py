"""The verdict on the predicted figures as the report shows it: per axis what the data leave
open and what would settle it, per figure its 90 % interval against its target."""

from __future__ import annotations

from ..analysis.compare import raw_spike_named
from .html import esc, para, table

_TEXT = {"firm": "firm", "uncertain": "uncertain", "undetermined": "undetermined"}


def verdict_html(verdict: dict) -> str:
    """HTML of a verdict (``Verdict.to_dict()``, as ``identification.json`` holds it).

    Parameters
    ----------
    verdict : dict
        ``{"firm", "tests", "axes", "figures"}`` [-].
    """
    import pandas as pd

    tests = ", ".join(verdict.get("tests", [])) or "none (one axis)"
    lead = ("Every predicted figure below is firm: within its target (the larger of 1 um "
            "and 1 % for spikes and G, of 0.5 um and 1 % for the contour error) at 90 %."
            if verdict.get("firm") else
            "Not every predicted figure is firm: the table gives each one's 90 % interval, "
            "what drives it and the measurement that would settle it.")
    body = f"<h3>Verdict on the predicted figures ({esc(tests)})</h3>" + para(lead, "lead")
    from ..uncertainty.figures import REFERENCE_WORDS
    from ..uncertainty.verdict_text import cause_text

    body += para(f"The circles of this verdict: {REFERENCE_WORDS}. A circle that starts from "
                 "rest, is fed in with its join in the turn analysed, or is pulled in by a "
                 "controller's filter reads its own figures; tcpmm spread gives the verdict "
                 "on such a circle.")
    for name, a in verdict.get("axes", {}).items():
        for r in a.get("open", []):
            body += para(f"axis {name}, {r['quantity']} open ({_range(r)}): {r['cause']}; "
                         f"to settle: {r['settle']}", "warn")
    # the raw e - b, as the command line names it: the circle's table leads with others
    rows = [{"circle": f["test"], "pass": f["direction"],
             "figure": raw_spike_named(f["figure"], "−"),
             "predicted [µm]": _or_nan(f["nominal_um"]),
             "± 90 % [µm]": _or_nan(f["half_width_um"]),
             "target [µm]": f["target_um"], "verdict": _TEXT[f["verdict"]],
             "cause": cause_text(f["cause"]), "to settle": f["settle"]}
            for f in verdict.get("figures", [])]
    if rows:
        body += table(pd.DataFrame(rows), "verdict.csv", digits=2)
    return body


def _or_nan(x) -> float:
    """``x``, NaN (shown n/a) for none: a figure that is no prediction has no interval."""
    return float("nan") if x is None else x


#: The unit an open quantity's range is shown in, and the factor from SI to it
#: (:class:`tcpmm.model.OpenRange`) [-].
RANGE_UNITS = {"backlash": ("µm", 1e6), "presliding": ("µm", 1e6), "C_t": ("N s/m", 1.0),
               "B_m": ("N m s/rad", 1.0), "column": ("N/µm", 1e-6),
               "bed": ("N/µm", 1e-6),
               "guideway_share": ("", 1.0), "mechanics": ("times", 1.0),
               "damping": ("times", 1.0), "time_base": ("times", 1.0),
               "J_m": ("kg m²", 1.0), "J_L": ("kg m²", 1.0), "B_L": ("N m s/rad", 1.0),
               "K_L": ("N m/rad", 1.0), "K_t": ("N/µm", 1e-6), "M_t": ("kg", 1.0)}


def _range(r: dict) -> str:
    """An open quantity's range in its unit, ``low to high unit`` [-]."""
    unit, k = RANGE_UNITS.get(r["quantity"], ("", 1.0))
    return f"{r['low'] * k:.3g} to {r['high'] * k:.3g}" + (f" {unit}" if unit else "")
