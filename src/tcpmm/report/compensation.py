"""The compensation section of a report: the TCP error before and after, the figures the
model predicts, and what the command was given per axis."""

from __future__ import annotations

from .html import figure, para, section, table

#: Figures of a compensation's scores shown, with their labels [-].
FIGURES = (("path", "contour_error_um", "contour error [µm]"),
           ("path", "contour_rms_um", "contour rms [µm]"),
           ("circle", "largest_spike_um", "largest reversal spike [µm]"),
           ("circle", "circular_deviation_um", "G [µm]"))


def _figures_frame(scores: dict):
    """Before, after and their ratio per predicted figure [µm, -]."""
    import pandas as pd

    rows = []
    for part, key, label in FIGURES:
        b = scores.get("before", {}).get(part, {}).get(key)
        a = scores.get("after", {}).get(part, {}).get(key)
        if b is None or a is None:
            continue
        rows.append({"figure": label, "before": b, "after": a,
                     "reduced by [x]": b / a if a > 0 else float("inf")})
    return pd.DataFrame(rows)


def _axes_frame(comp):
    """Per axis: the share of the correction applied, its size and the limits kept."""
    import pandas as pd

    d = comp.to_dict()
    shares = comp.robustness.get("factors", {})
    rows = []
    for a, c in d["correction"].items():
        b = d["bounds"].get(a, {})
        rows.append({"axis": a, "share applied": shares.get(a, 1.0),
                     "largest correction [µm]": c["applied_max_um"],
                     **{f"limit {k}": v for k, v in b.items()}})
    return pd.DataFrame(rows)


def compensation_section(comp, source=None):
    """The compensation: the model's predicted TCP error before and after (polar for a
    circle), the figures with their reduction, and per axis the share of the correction
    applied, its size and the limits it keeps.

    Parameters
    ----------
    comp : Compensation
        From :func:`tcpmm.compensate.compensate`, with its scores [-].
    source : str, optional
        The programmed command or program, for the record [-].
    """
    trusted = comp.to_dict().get("trusted_share")
    lead = ("The programmed command pre-compensated on the identified model: the model's "
            "TCP error before and after, as it predicts them"
            + (f" (from {source})" if source else "") + ".")
    if trusted is not None:
        lead += (f" The compensation improves the error on every machine drawn from the "
                 f"model's uncertainty on {trusted:.0%} of the samples (trusted).")
    body = para(lead, "lead") + figure(comp.plot(), "TCP error before and after")
    frame = _figures_frame(comp.scores)
    if len(frame):
        body += "<h3>Predicted figures</h3>" + table(frame, "compensation_figures.csv")
    body += ("<h3>Per axis</h3>" + table(_axes_frame(comp), "compensation_axes.csv"))
    return section("compensation", "Compensation", body)
