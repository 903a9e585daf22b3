"""Report sections on the machine: the model's parameters, and its identification."""

from __future__ import annotations

import json
import math
from pathlib import Path

from ..errors import InputError
from ..mechanics.statespace import plant
from ..servo.currentfilters import filters_text
from ..servo.sampled import sampled_spectral_radius
from ..uncertainty.driveranges import DRIVE
from .accuracy import verdict_html
from .html import esc, facts, figure, para, section, table

#: Mechanics parameter -> (description, display unit, factor from SI).
MECHANICS = {
    "J_m": ("motor inertia", "kg·m²", 1.0), "B_m": ("motor damping", "N·m·s/rad", 1.0),
    "J_L": ("screw inertia", "kg·m²", 1.0), "B_L": ("screw damping", "N·m·s/rad", 1.0),
    "K_L": ("screw torsional stiffness", "N·m/rad", 1.0), "lead": ("screw lead", "mm", 1e3),
    "M_t": ("table mass", "kg", 1.0), "C_t": ("nut damping", "N·s/m", 1.0),
    "K_t": ("nut axial stiffness", "N/µm", 1e-6), "M_b": ("bed mass", "kg", 1.0),
    "C_b": ("bed damping", "N·s/m", 1.0), "K_b": ("bed stiffness", "N/µm", 1e-6),
    "M_h": ("TCP structure mass", "kg", 1.0), "C_h": ("TCP structure damping", "N·s/m", 1.0),
    "K_h": ("TCP structure stiffness", "N/µm", 1e-6),
    "K_tc": ("motor torque constant", "N·m/A", 1.0), "load_force": ("load force", "N", 1.0),
}
#: Servo parameter -> (description, display unit, factor from SI).
SERVO = {
    "position_feedback": ("position feedback", "", None),
    "K_pp": ("position loop gain", "1/s", 1.0),
    "K_vp": ("velocity loop P gain", "A·s/rad", 1.0),
    "K_vi": ("velocity loop I gain", "A/rad", 1.0),
    "k_ff": ("velocity feedforward", "-", 1.0),
    "T_p": ("position loop period", "µs", 1e6), "T_v": ("velocity loop period", "µs", 1e6),
    "current_limit": ("current limit", "A", 1.0),
    "current_bandwidth_hz": ("current loop bandwidth", "Hz", 1.0),
    "delay_samples": ("computation delay", "samples of T_v", 1.0),
}


def _value(v, k):
    """A value in display units; text stays text, ``None`` is n/a [-]."""
    if v is None:
        return float("nan")
    if isinstance(v, str) or k is None:
        return str(v)
    return float(v) * k


def model_frame(machine):
    """One row per parameter, one column per axis, in display units [-]."""
    import pandas as pd

    rows = []
    for group, names, get in (("mechanics", MECHANICS, lambda a: a.mechanics),
                              ("servo", SERVO, lambda a: a.servo)):
        for p, (what, unit, k) in names.items():
            row = {"group": group, "parameter": p, "description": what, "unit": unit}
            row.update({ax: _value(getattr(get(a), p), k) for ax, a in machine.axes.items()})
            rows.append(row)
    row = {"group": "servo", "parameter": "filters", "unit": "",
           "description": "current-setpoint filters (the gains hold with them only)"}
    row.update({ax: filters_text(a.servo.filters) for ax, a in machine.axes.items()})
    rows.append(row)
    for p, what, unit, get in _friction_rows():
        row = {"group": "friction", "parameter": p, "description": what, "unit": unit}
        row.update({ax: get(a.friction) if a.friction is not None else float("nan")
                    for ax, a in machine.axes.items()})
        rows.append(row)
    dyn = {ax: _dynamics(a) for ax, a in machine.axes.items()}
    for i, (p, what, unit) in enumerate(DYNAMICS):
        row = {"group": "dynamics", "parameter": p, "description": what, "unit": unit}
        row.update({ax: d[i] for ax, d in dyn.items()})
        rows.append(row)
    return pd.DataFrame(rows)


#: Rows on the dynamics of each axis: name, description, unit.
DYNAMICS = (("modes", "natural frequencies of the mechanics", "Hz"),
            ("spectral_radius", "sampled servo loop spectral radius (stable up to 1)", "-"))


def _dynamics(axis) -> tuple:
    """Natural frequencies of the open mechanics, lowest first, as text [Hz], and the
    spectral radius of the sampled closed loop [-]."""
    import numpy as np

    ev = np.linalg.eigvals(plant(axis.mechanics).A)
    f = np.sort(np.abs(ev[ev.imag > 0])) / (2 * np.pi)
    return ", ".join(f"{x:.1f}" for x in f), sampled_spectral_radius(axis.mechanics, axis.servo)


def _friction_rows():
    """``(name, description, unit, getter)`` of the friction summary [-]."""
    def level(contact):
        return lambda f: (float("nan") if getattr(f, contact) is None else
                          0.5 * (getattr(f, contact).fc_pos + getattr(f, contact).fc_neg))

    return (("guideway_coulomb", "guideway Coulomb friction", "N", level("guideway")),
            ("screw_coulomb", "screw Coulomb friction (at the table)", "N", level("screw")),
            ("backlash", "lost motion of the nut", "µm", lambda f: f.backlash * 1e6))


def model_section(machine, source: str | None = None):
    """Machine and model summary: axes, masses, stiffnesses, servo gains, with units.

    Parameters
    ----------
    machine : Machine
        The model [SI].
    source : str, optional
        Where it came from (a file name), for the record [-].
    """
    frame = model_frame(machine)
    items = [("machine", machine.name), ("axes", ", ".join(machine.axes))]
    if source:
        items.append(("model file", Path(str(source)).name))
    body = facts(items)
    for s in machine.suspect:
        body += para(f"marked physically suspect: {s}", "warn")
    body += para("Parameters per axis in the units of the unit column; n/a: not in the "
                 "model (an axis without friction elements, an ideal current loop).")
    body += table(frame, "model.csv", digits=None)
    return section("model", "Machine and model", body)


def read_identification_folder(folder):
    """What ``tcpmm identify --report DIR`` wrote: the summary and the PNG figures.

    Parameters
    ----------
    folder : str or Path
        The report folder [-].

    Returns
    -------
    tuple
        ``(summary, images)``: the ``identification.json`` dictionary and
        ``{file stem: PNG bytes}`` of the Bode, sweep and lost-motion plots [-].
    """
    folder = Path(folder)
    js = folder / "identification.json"
    if not folder.is_dir():
        raise InputError("is not a folder; give the folder written by "
                         "tcpmm identify BUNDLE -o MODEL.yaml --report DIR", file=folder)
    if not js.is_file():
        raise InputError("has no identification.json; give the folder written by "
                         "tcpmm identify BUNDLE -o MODEL.yaml --report DIR", file=folder)
    try:
        summary = json.loads(js.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"is not a JSON file ({exc}); write it anew with tcpmm identify "
                         "--report DIR", file=js) from None
    if not isinstance(summary, dict) or not isinstance(summary.get("axes"), dict):
        raise InputError("has no 'axes'; write it anew with tcpmm identify --report DIR",
                         file=js, column="axes")
    images = {p.stem: p.read_bytes() for p in sorted(folder.glob("*.png"))}
    return summary, images


#: The parameters an open quantity of the verdict leaves open (:class:`tcpmm.model.OpenRange`).
OPEN_PARAMETERS = {"B_m": ("B_m",), "C_t": ("C_t",), "column": ("M_h", "K_h"),
                   "bed": ("M_b", "K_b"),
                   "mechanics": ("M_t", "M_b", "K_b", "M_h", "K_h"),
                   "damping": ("C_t", "C_b", "C_h"),
                   "time_base": ("J_m", "J_L", "M_t", "M_b", "M_h", "B_m", "B_L", "C_t",
                                 "C_b", "C_h"),
                   **{p: (p,) for p in DRIVE}}


def _friction_unit(name: str) -> str:
    """Unit of a fitted friction parameter (:func:`tcpmm.ident.friction.stribeck.fit_stribeck`'s
    names: forces ``Fc``, ``Fs``, Stribeck speed ``vs``, viscous ``Fv``) [-]."""
    return {"vs": "m/s", "Fv": "N s/m"}.get(name, "N" if name[:2] in ("Fc", "Fs") else "SI")


def _parameters_frame(axis: dict, opened=()):
    """Identified parameters of one axis with their standard deviations; a parameter the
    fit or the verdict leaves open (``opened``: its open quantities) is not determined,
    whatever its deviation (B_m read 'determined: yes' beside a verdict that gave it an
    open range) [-]."""
    import pandas as pd

    open_ps = {p for q in opened for p in OPEN_PARAMETERS.get(q, ())}
    rows = []
    for p, d in axis.get("parameters", {}).items():
        what, unit, k = MECHANICS.get(p, (p, "SI", 1.0))
        v = _value(d.get("value"), k)
        sd = _value(d.get("std"), k)
        rel = 100 * sd / abs(v) if isinstance(v, float) and v and math.isfinite(sd) else math.nan
        rows.append({"parameter": p, "description": what, "unit": unit, "value": v,
                     "std": sd, "std [%]": rel,
                     "determined": p not in axis.get("undetermined", []) and p not in open_ps})
    return pd.DataFrame(rows)


def _quality_frame(axis: dict):
    """Fit quality per transfer function of one axis [-]."""
    import pandas as pd

    return pd.DataFrame([{"transfer function": tf, "TF order": q.get("tf_order", ""),
                          "TF fit [%]": q.get("tf_fit_percent", math.nan),
                          "physical fit [%]": q.get("physical_fit_percent", math.nan),
                          "physical fit, log [%]": q.get("physical_log_fit_percent",
                                                         math.nan),
                          "modes [Hz]": ", ".join(f"{m:g}" for m in q.get("modes_hz", []))}
                         for tf, q in axis.get("fit", {}).items()])


def identification_section(summary: dict, images: dict | None = None):
    """Identification: measured against fitted Bode plots with coherence, and the
    parameters with units and standard deviations, per axis.

    Parameters
    ----------
    summary : dict
        ``Identification.to_dict()``, or the ``identification.json`` it wrote [-].
    images : dict, optional
        ``{file stem: PNG bytes}`` as :meth:`Identification.write_report` names them
        (``bode_X``, ``sweep_X``, ``lostmotion_X``) [-].
    """
    import pandas as pd

    images = images or {}
    body = para("Measured frequency responses (blue; bins of coherence below 0.5 left out, "
                "the coherence in grey) against the rational transfer-function fit (green) "
                "and the identified physical model (red). Fit percentages: 100 % is exact; "
                "below 0 the model misses the measurement by more than its own size. On the "
                "complex response a resonance a few bins off outweighs the rest of the band; "
                "the log fit judges the logarithm of the response, as the identification "
                "does, without the worst 1 % of bins.", "lead")
    for s in summary.get("suspect", []):
        body += para(f"physically suspect: {s}", "warn")
    for w in summary.get("warnings", []):  # what identify said on the way
        body += para(f"identify: {w}", "warn")
    if summary.get("verdict") is not None:
        body += verdict_html(summary["verdict"])
    for name, axis in summary["axes"].items():
        body += f"<h3>Axis {esc(name)}</h3>"
        if f"bode_{name}" in images:
            body += figure(images[f"bode_{name}"], f"Bode plots of axis {name}",
                           f"axis {name}: measured and identified frequency responses")
        body += table(_quality_frame(axis), f"fit_quality_{name}.csv", digits=1)
        opened = [r["quantity"] for r in (summary.get("verdict") or {}).get("axes", {})
                  .get(name, {}).get("open", [])]
        body += table(_parameters_frame(axis, opened), f"parameters_{name}.csv",
                      digits={"value": None, "std": None, "std [%]": 1},
                      caption="std: one standard deviation of the fit; a parameter the "
                              "data do not determine keeps its start value.")
        if axis.get("friction"):
            body += table(pd.DataFrame([{"friction": k, "unit": _friction_unit(k),
                                         "value": v["value"], "std": v["std"]}
                                        for k, v in axis["friction"].items()]),
                          f"friction_{name}.csv", digits={"value": None, "std": None},
                          caption="friction fitted to the friction runs, at the table")
        if f"lostmotion_{name}" in images:
            body += figure(images[f"lostmotion_{name}"], f"lost motion of axis {name}",
                           "nut deflection of the friction runs against speed", 620)
    return section("identification", "Identification", body)


def identification_result_section(identification):
    """:func:`identification_section` of an identification in memory, from the figures and
    the summary its :meth:`~tcpmm.ident.identification.Identification.write_report` writes.

    Parameters
    ----------
    identification : Identification
        :func:`tcpmm.ident.chain.identify_bundle` [-].
    """
    import tempfile

    from ..io.atomic import at_once

    # read back at once, not held back with the command's outputs
    with tempfile.TemporaryDirectory(prefix="tcpmm-report-") as tmp, at_once(tmp):
        identification.write_report(tmp)
        return identification_section(*read_identification_folder(tmp))
