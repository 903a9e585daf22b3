"""What an identified axis's model takes from where: per parameter, the FRF fit, the
friction runs or a value set, and whether the data determine it; the parameter table
:meth:`tcpmm.ident.identification.Identification.parameters_table` gives."""

from __future__ import annotations

import numpy as np

from .physical.greybox import FITTED


def model_parameters(a):
    """One axis's parameter table (:meth:`Identification.parameters_table`): the model's
    value and deviation, where they come from (``from``) and whether the data determine
    them (:func:`model_status`), the physical fit's own beside them [-]."""
    df = a.physical.to_pandas().rename(columns={"value": "fit_value", "std": "fit_std",
                                                "determined": "fit_determined"})
    model = a.axis.mechanics.model_dump()
    sd = a.axis.uncertainty.mechanics if a.axis.uncertainty is not None else {}
    status = model_status(a)
    df.insert(1, "value", [model[p] for p in df["parameter"]])
    df.insert(2, "std", [sd.get(p, float("nan")) for p in df["parameter"]])
    df["rel_std_percent"] = 100.0 * df["std"] / df["value"].where(df["value"] != 0.0)
    df["from"] = [status[p][0] for p in df["parameter"]]
    df["determined"] = [status[p][1] for p in df["parameter"]]
    return df


def model_status(a) -> dict:
    """Per fitted parameter of an axis, ``(from, determined)``: whether the model's value
    is the FRF fit's (``"FRF fit"``), the friction runs' (``"friction runs"``: the nut's
    stiffness, the steady viscous force, with their own deviation) or set without one
    (``"set"``: the motor bearing's damping taken as negligible); and whether the data
    determine it. The FRF fit's guess of a parameter the runs then give is no guess in
    the model (a screw damping 'not determined' beside its 0.9 % deviation), and a value
    set is determined by nothing [-]."""
    model = a.axis.mechanics.model_dump()
    fit = a.physical.mechanics.model_dump()
    sd = a.axis.uncertainty.mechanics if a.axis.uncertainty is not None else {}
    out = {}
    for p in FITTED:
        if model[p] == fit[p]:
            out[p] = ("FRF fit", p not in a.physical.undetermined)
        elif np.isfinite(sd.get(p, np.nan)):
            out[p] = ("friction runs", True)
        else:
            out[p] = ("set", False)
    return out


def model_undetermined(a) -> list:
    """The parameters of an axis's model the data do not determine: the FRF fit's that
    the model keeps (the current loop's too), and those set (:func:`model_status`) [-]."""
    status = model_status(a)
    kept = [p for p in a.physical.undetermined if p not in status or status[p][1] is False]
    return kept + [p for p, (_, ok) in status.items() if not ok and p not in kept]
