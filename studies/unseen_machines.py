"""Validation on unseen machines: identify, predict and compare the circular test.

For ``N`` random machines derived from the built-in one, each with its X and Y axes
perturbed (mechanics, friction level, guideway/screw split, Stribeck or LuGre friction,
servo gains, velocity feedforward, sensor resolutions, optionally lost motion), the
script runs what a user would do on a real machine:

1. record the measurement bundle (servo-excitation sweep and constant-speed friction runs
   per axis) with :func:`tcpmm.machines.virtual.virtual_bundle`;
2. record the circular test (R35 mm, F5000 mm/min, CCW then CW) with
   :func:`tcpmm.machines.virtual.virtual_run`;
3. identify a model from the bundle alone with :func:`tcpmm.ident.pipeline.identify_bundle`;
4. predict the circle with the identified model and compare (the paper's Table 2):
   reversal spike heights at the quadrant points A-D and the contour error at the TCP,
   measured minus predicted.

The spike is the larger in magnitude of the rise and the fall of the radial error in the
20 deg after the point; where both are of similar size a small model error flips its
sign and the difference jumps by their sum. The largest rise/fall difference is printed
as well, to tell such flips from real errors.

The paper reports spike differences of 0.4-4.1 um; the target is to stay below that at
every quadrant. To attribute a failure, each machine is also predicted with hybrid
models that swap one part of the identified model for the true one:

``true model``
    The true machine simulated without measurement noise and TCP quantisation: the floor
    set by the measuring process and the analysis.
``id + true fric``
    Identified model with the true friction elements (and lost motion).
``id + true B_m,B_L,C_t``
    Identified model with the true linear damping to ground of motor, screw and table,
    which acts like viscous friction in steady motion and trades off against it.
``id + true fric,B,C_t``
    Both of the above: what is left is stiffness, inertia and the current loop.
``id + true Fs/Fc, vs``
    Identified model with the static-over-Coulomb ratio and Stribeck velocity of the
    true friction (Coulomb levels and split as identified).
``id + true split``
    Identified model with the identified friction total re-shared between guideway and
    screw in the true proportion: the effect of the split alone.
``id + true split, Fs/Fc, vs``
    Both of the above.
``id + true steady split``
    Identified model with the true split of the steady friction force: Coulomb and
    static levels shared between guideway and screw, and viscous force between motor
    side (``B_m, B_L``, screw) and table side (``C_t``, guideway), as a friction run that
    resolves the nut force could give them; Stribeck shape as identified.
``id + true other mech``
    Identified model with the true masses, inertias, stiffnesses and structural damping
    (all mechanics but ``B_m, B_L, C_t``).
``id + true mech``
    Identified friction on the true mechanics with the ideal current loop of the true
    machines: what is left is friction.
``id + ideal current loop``
    Identified model with the identified current-loop bandwidth removed.
``id, B,C_t <= run Fv``
    Identified model with its damping to ground capped by the viscous slope that the
    friction runs measure, the friction's viscous part being the remainder: uses no
    knowledge of the true machine, a candidate correction of the identification.
``true, Stribeck``
    The true machine with its LuGre friction replaced by the Stribeck friction of the
    same levels (only when an axis has LuGre): what a Stribeck model misses of the
    pre-sliding.

Scale factors are drawn log-uniformly in their ranges, shares, asymmetries, bandwidths
and gains uniformly, from a generator seeded by ``(seed, machine index)``, so a machine
can be re-run alone with ``--only``; ``--backlash`` draws one more number per axis, so
its machines differ from those of the same index without it.

Usage::

    python -m studies.unseen_machines [--n 6] [--seed 0] [--backlash] [--only 2 5]
                                       [--lugre-fraction 0.33] [--json FILE] [--keep DIR]
                                       [--presliding-um 0.5 | --fit-presliding]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from tcpmm.analysis.circular import analyse_circle
from tcpmm.analysis.compare import compare_circles
from tcpmm.ident.friction import PRESLIDING
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.machines.virtual import virtual_bundle, virtual_run
from tcpmm.mechanics.friction import LuGreFriction
from tcpmm.model import Axis, AxisFriction, Machine
from tcpmm.servo.params import ServoParams
from tcpmm.sim.simulate import simulate

from .unseen import (
    AXES,
    DIRECTIONS,
    LINEAR_DAMPING,
    PAPER_MAX,
    PAPER_MIN,
    QUADRANTS,
    RADIUS,
    SHARE_RANGE,
    as_stribeck,
    differences,
    draw_machine,
    friction_split,
    max_abs_spike,
    paper_circle_command,
    predicted_figures,
    resplit,
    tcp_figures,
    with_axes,
    without_backlash,
)

# ------------------------------------------------------------------------- evaluation


def friction_shape(fr: AxisFriction | None) -> dict:
    """Summed friction of both contacts: static over Coulomb level, Stribeck velocity
    (weighted by each contact's static excess), viscous coefficient.

    Parameters
    ----------
    fr : AxisFriction or None
        Friction of the axis [-].

    Returns
    -------
    dict
        ``fs_over_fc`` [-], ``vs`` [m/s], ``fv`` [N s/m] (nan without friction).
    """
    cs = [c for c in (fr.guideway, fr.screw) if c is not None] if fr is not None else []
    if not cs:
        return {"fs_over_fc": float("nan"), "vs": float("nan"), "fv": float("nan")}
    fc = sum(c.fc_pos + c.fc_neg for c in cs)
    fs = sum(c.fs_pos + c.fs_neg for c in cs)
    w = [max(c.fs_pos + c.fs_neg - c.fc_pos - c.fc_neg, 0.0) for c in cs]
    vs = (sum(wi * c.vs for wi, c in zip(w, cs, strict=True)) / sum(w) if sum(w) > 0
          else float(np.mean([c.vs for c in cs])))
    return {"fs_over_fc": fs / fc if fc > 0 else float("nan"), "vs": vs,
            "fv": sum(0.5 * (c.fv_pos + c.fv_neg) for c in cs)}


def with_stribeck_hump(fr: AxisFriction | None, target: AxisFriction | None):
    """``fr`` with its static levels and Stribeck velocity set to those of ``target``.

    Each contact keeps its Coulomb levels; its static levels become the Coulomb levels
    times the summed static-over-Coulomb ratio of ``target`` per direction, and its
    Stribeck velocity the weighted one of ``target`` [-].
    """
    if fr is None or target is None:
        return fr
    tcs = [c for c in (target.guideway, target.screw) if c is not None]
    r_pos = sum(c.fs_pos for c in tcs) / max(sum(c.fc_pos for c in tcs), 1e-12)
    r_neg = sum(c.fs_neg for c in tcs) / max(sum(c.fc_neg for c in tcs), 1e-12)
    vs = friction_shape(target)["vs"]

    def one(c):
        if c is None:
            return None
        return c.model_copy(update={"fs_pos": c.fc_pos * r_pos, "fs_neg": c.fc_neg * r_neg,
                                    "vs": vs})

    return fr.model_copy(update={"guideway": one(fr.guideway), "screw": one(fr.screw)})


def linear_damping(mech) -> float:
    """Damping to ground of motor, screw and table in table units [N s/m]."""
    return (mech.B_m + mech.B_L) / mech.R_L**2 + mech.C_t


def with_mechanics(axis: Axis, source: Axis, keys) -> Axis:
    """``axis`` with the mechanics parameters ``keys`` taken from ``source`` [-]."""
    m = source.mechanics
    return axis.replace(mechanics=axis.mechanics.replace(**{k: getattr(m, k) for k in keys}))


def viscous_from_run(axis: Axis, fv_run: float) -> Axis:
    """``axis`` with its damping to ground no larger than the friction runs' viscous slope.

    The constant-speed runs measure the whole viscous force, damping to ground of the
    mechanics (``B_m``, ``B_L``, ``C_t``) plus viscous friction. The damping is scaled
    down to that total where it exceeds it, and the friction's viscous coefficient is set
    to the remainder, shared between the contacts like their Coulomb levels.

    Parameters
    ----------
    axis : Axis
        Identified axis [SI].
    fv_run : float
        Viscous slope of the friction runs' Stribeck fit [N s/m].

    Returns
    -------
    Axis
        The modified axis [SI].
    """
    lin = linear_damping(axis.mechanics)
    k = min(1.0, fv_run / lin) if lin > 0 else 1.0
    mech = axis.mechanics.scaled(**{n: k for n in LINEAR_DAMPING})
    rest = max(fv_run - k * lin, 0.0)
    fr = axis.friction
    share, _ = friction_split(fr)
    share = 0.0 if math.isnan(share) else share

    def one(c, part):
        return None if c is None else c.model_copy(update={"fv_pos": rest * part,
                                                           "fv_neg": rest * part})

    fr = fr.model_copy(update={"guideway": one(fr.guideway, share),
                               "screw": one(fr.screw, 1 - share)})
    return axis.replace(mechanics=mech, friction=fr)


def with_true_steady_split(ident: Axis, true: Axis) -> Axis:
    """Identified axis with the true steady-motion split of friction and damping.

    The Coulomb and static levels are re-shared between guideway and screw in the true
    proportion; the viscous force is put where it acts on the true axis, the motor and
    screw side (``B_m``, ``B_L`` and the screw's viscous friction) into ``B_m, B_L``, the
    table side (``C_t`` and the guideway's viscous friction) into ``C_t``, and the
    friction keeps no viscous part.

    Parameters
    ----------
    ident, true : Axis
        Identified and true axis [SI].

    Returns
    -------
    Axis
        The modified identified axis [SI].
    """
    tf, tm, im = true.friction, true.mechanics, ident.mechanics

    def fv(c):
        return 0.0 if c is None else 0.5 * (c.fv_pos + c.fv_neg)

    def fc(c):
        return 0.0 if c is None else c.fc_pos + c.fc_neg

    share = fc(tf.guideway) / (fc(tf.guideway) + fc(tf.screw))
    fr = resplit(ident.friction, share)

    def no_fv(c):
        return None if c is None else c.model_copy(update={"fv_pos": 0.0, "fv_neg": 0.0})

    fr = fr.model_copy(update={"guideway": no_fv(fr.guideway), "screw": no_fv(fr.screw)})
    R2 = tm.R_L**2
    v_motor = (tm.B_m + tm.B_L) + fv(tf.screw) * R2  # [N m s/rad]
    k = v_motor / (im.B_m + im.B_L) if im.B_m + im.B_L > 0 else 1.0
    mech = im.replace(B_m=im.B_m * k, B_L=im.B_L * k, C_t=tm.C_t + fv(tf.guideway))
    return ident.replace(mechanics=mech, friction=fr)


def hybrid_models(true: Machine, ident: Machine, shares: dict, fv_run: dict) -> dict:
    """The attribution models (see the module docstring) [-]."""
    ta, ia = true.axes, ident.axes
    mech_all = [k for k in ta["X"].mechanics.model_dump() if k not in ("lead", "K_tc")]
    mech_rest = [k for k in mech_all if k not in LINEAR_DAMPING]

    def ideal_cl(a: Axis) -> Axis:
        return a.replace(servo=ServoParams.create(**{**a.servo.model_dump(),
                                                     "current_bandwidth_hz": None}))

    out = {
        "id + true fric": with_axes(ident, lambda n: ia[n].replace(friction=ta[n].friction)),
        "id + true B_m,B_L,C_t": with_axes(
            ident, lambda n: with_mechanics(ia[n], ta[n], LINEAR_DAMPING)),
        "id + true fric,B,C_t": with_axes(ident, lambda n: with_mechanics(
            ia[n], ta[n], LINEAR_DAMPING).replace(friction=ta[n].friction)),
        "id + true Fs/Fc, vs": with_axes(ident, lambda n: ia[n].replace(
            friction=with_stribeck_hump(ia[n].friction, ta[n].friction))),
        "id + true split": with_axes(
            ident, lambda n: ia[n].replace(friction=resplit(ia[n].friction, shares[n]))),
        "id + true split, Fs/Fc, vs": with_axes(ident, lambda n: ia[n].replace(
            friction=with_stribeck_hump(resplit(ia[n].friction, shares[n]), ta[n].friction))),
        "id + true steady split": with_axes(
            ident, lambda n: with_true_steady_split(ia[n], ta[n])),
        "id + true other mech": with_axes(
            ident, lambda n: with_mechanics(ia[n], ta[n], mech_rest)),
        "id + true mech": with_axes(
            ident, lambda n: ideal_cl(with_mechanics(ia[n], ta[n], mech_all))),
        "id + ideal current loop": with_axes(ident, lambda n: ideal_cl(ia[n])),
    }
    if all(fv_run.get(n) is not None for n in AXES):
        out["id, B,C_t <= run Fv"] = with_axes(
            ident, lambda n: viscous_from_run(ia[n], fv_run[n]))
    lugre = any(isinstance(getattr(ta[n].friction, c, None), LuGreFriction)
                for n in AXES for c in ("guideway", "screw"))
    if lugre:
        out["true, Stribeck"] = with_axes(true, lambda n: ta[n].replace(
            friction=ta[n].friction.model_copy(update={
                "guideway": as_stribeck(ta[n].friction.guideway),
                "screw": as_stribeck(ta[n].friction.screw)})))
    return out


def backlash_effect(true: Machine, cmd) -> float:
    """Largest change of the TCP path when the lost motion is set to zero [m]."""
    if not any(true.axes[n].friction.backlash > 0 for n in AXES):
        return float("nan")
    a, b = simulate(true, cmd), simulate(without_backlash(true), cmd)
    return float(max(np.max(np.abs(a.axes[n].tcp - b.axes[n].tcp)) for n in AXES))


def evaluate(true: Machine, cmd, workdir: Path, attribute: bool = True,
             presliding: float | None = PRESLIDING) -> dict:
    """Bundle, circle, identification, prediction and attribution of one machine.

    Parameters
    ----------
    true : Machine
        The true machine [SI].
    cmd : Command
        The circle command [m].
    workdir : Path
        Folder for the bundle [-].
    attribute : bool
        Also predict with the hybrid models [-].
    presliding : float or None
        Pre-sliding displacement given to the identified contacts, ``0`` for static
        friction (:mod:`tcpmm.ident.friction.presliding`), ``None`` to fit it to the
        friction runs [m].

    Returns
    -------
    dict
        Figures in SI and timings [s] [-].
    """
    t0 = time.perf_counter()
    virtual_bundle(true, workdir / "bundle", axes=AXES)
    measured = virtual_run(true, cmd)
    t1 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_bundle(read_bundle(workdir / "bundle"), presliding=presliding)
    t2 = time.perf_counter()
    rm = analyse_circle(measured, RADIUS)
    rp = analyse_circle(simulate(idn.machine, cmd), RADIUS)
    meas, pred = tcp_figures(rm), tcp_figures(rp)
    table2 = compare_circles(rm, rp).to_pandas()
    t3 = time.perf_counter()
    axes = {}
    shares = {}
    for n in AXES:
        ta, ia = true.axes[n], idn.machine.axes[n]
        s_true, f_true = friction_split(ta.friction)
        s_id, f_id = friction_split(ia.friction)
        shares[n] = s_true
        axes[n] = {
            "share_true": s_true, "share_id": s_id, "friction_true": f_true,
            "friction_id": f_id,
            "mechanics_true": ta.mechanics.model_dump(),
            "mechanics_id": ia.mechanics.model_dump(),
            "current_bandwidth_id_hz": ia.servo.current_bandwidth_hz,
            "shape_true": friction_shape(ta.friction), "shape_id": friction_shape(ia.friction),
            "linear_damping_true": linear_damping(ta.mechanics),
            "linear_damping_id": linear_damping(ia.mechanics),
            "backlash_id": getattr(ia.friction, "backlash", 0.0) if ia.friction else 0.0,
            "backlash_true": getattr(ta.friction, "backlash", 0.0) if ta.friction else 0.0,
            "split_source": getattr(getattr(idn.axes[n], "friction_split", None), "source",
                                    "prior"),
        }
    out = {
        "measured": meas, "predicted": pred, "difference": differences(meas, pred),
        "table2_tcp": table2[table2["sensor"] == "tcp"].to_dict(orient="records"),
        "axes": axes,
        "warnings": sorted({str(w.message).replace(str(workdir), "<work>").split(";")[0][:160]
                            for w in caught}),
        "time_s": {"virtual measurement": t1 - t0, "identification": t2 - t1,
                   "prediction": t3 - t2},
    }
    if attribute:
        variants = {"identified": out["difference"],
                    "true model": differences(meas, predicted_figures(true, cmd))}
        fv_run = {}
        for n, a in idn.axes.items():
            try:
                fv_run[n] = float(a.friction["Fv"])
            except (KeyError, TypeError, IndexError):
                fv_run[n] = None
        for name, model in hybrid_models(true, idn.machine, shares, fv_run).items():
            variants[name] = differences(meas, predicted_figures(model, cmd))
        out["attribution"] = variants
        out["backlash_effect"] = backlash_effect(true, cmd)
        out["time_s"]["attribution"] = time.perf_counter() - t3
    return out


# -------------------------------------------------------------------------- printing


def um(x: float) -> str:
    """A length [m] printed in um with two decimals."""
    return f"{x * 1e6:7.2f}"


def print_machine(index: int, desc: dict, res: dict) -> None:
    """Per-machine report: draw, identification, Table-2 spikes, attribution."""
    print(f"\n=== machine {index}: servo {desc['servo_mode']}, k_ff {desc['k_ff']}, "
          f"encoder {desc['sensors']['encoder_counts_per_rev']} counts/rev, scale "
          f"{desc['sensors']['scale_resolution'] * 1e6:g} um, TCP device "
          f"{desc['sensors']['tcp_resolution'] * 1e6:g} um, redraws {desc['redraws']}")
    for n in AXES:
        d = desc[n]
        print(f"  {n}: {d['friction_model']:8s} level x{d['friction_level']:.2f} "
              f"vs {d['vs_guideway'] * 1e3:.1f}/{d['vs_screw'] * 1e3:.1f} mm/s "
              f"Fs/Fc {d['fs_over_fc']:.2f} backlash {d['backlash'] * 1e6:.1f} um; "
              f"K_pp {d['K_pp']:.1f} 1/s, {d['servo']}")
    print("  axis  share true/id (source)   F(10 mm/s) true/id [N]   K_t id/true  M_t id/true"
          "  K_h id/true  J_tot id/true  f_cl id [Hz]  lost motion true/id [um]")
    for n in AXES:
        a = res["axes"][n]
        mt, mi = a["mechanics_true"], a["mechanics_id"]

        def ratio(k, mt=mt, mi=mi):
            return mi[k] / mt[k]

        def j_tot(m):
            return m["J_m"] + m["J_L"] + m["M_t"] * (m["lead"] / (2 * math.pi)) ** 2

        fcl = a["current_bandwidth_id_hz"]
        print(f"  {n}     {a['share_true']:.2f} / {a['share_id']:.2f} ({a['split_source']:5s})   "
              f"{a['friction_true']:7.1f} / {a['friction_id']:7.1f}       "
              f"{ratio('K_t'):6.2f}      {ratio('M_t'):6.2f}      {ratio('K_h'):6.2f}"
              f"       {j_tot(mi) / j_tot(mt):6.2f}      "
              f"{'-' if fcl is None else str(round(fcl)):>6}     "
              f"{a['backlash_true'] * 1e6:5.2f} / {a['backlash_id'] * 1e6:5.2f}")
    print("  axis  Fs/Fc true/id   vs true/id [mm/s]   friction fv true/id   "
          "B_m,B_L,C_t at table true/id [N s/m]")
    for n in AXES:
        a = res["axes"][n]
        st, si = a["shape_true"], a["shape_id"]
        print(f"  {n}     {st['fs_over_fc']:.2f} / {si['fs_over_fc']:.2f}      "
              f"{st['vs'] * 1e3:5.2f} / {si['vs'] * 1e3:5.2f}       {st['fv']:7.0f} / "
              f"{si['fv']:5.0f}       {a['linear_damping_true']:7.0f} / "
              f"{a['linear_damping_id']:7.0f}")
    print("  TCP spikes [um]     "
          + "".join(f"|       {q}: meas    pred    diff " for q in QUADRANTS))
    for d in DIRECTIONS:
        m, p, x = res["measured"][d], res["predicted"][d], res["difference"][d]
        cells = "".join(f"| {um(m['spikes'][q])} {um(p['spikes'][q])} {um(x['spikes'][q])} "
                        for q in QUADRANTS)
        print(f"  {d.upper():4s}                {cells}")
    print("  largest rise/fall difference [um] "
          + " | ".join(f"{d.upper()} " + " ".join(um(res["difference"][d]["lobes"][q])
                                                  for q in QUADRANTS) for d in DIRECTIONS))
    for d in DIRECTIONS:
        m, p, x = res["measured"][d], res["predicted"][d], res["difference"][d]
        print(f"  contour error {d.upper():3s} [um]: meas {um(m['contour_error'])}  pred "
              f"{um(p['contour_error'])}  diff {um(x['contour_error'])}")
    if "attribution" in res:
        print("  spike differences of the attribution models [um], "
              "CCW A B C D | CW A B C D | max")
        for name, diff in res["attribution"].items():
            vals = " | ".join(" ".join(um(diff[d]["spikes"][q]) for q in QUADRANTS)
                              for d in DIRECTIONS)
            print(f"    {name:28s} {vals} | {um(max_abs_spike(diff))}")
        be = res.get("backlash_effect", float("nan"))
        if not math.isnan(be):
            print(f"  lost motion: largest TCP change when it is removed from the true "
                  f"machine {be * 1e6:.3f} um")
    if res["warnings"]:
        print("  identification warnings: " + " / ".join(res["warnings"]))
    t = res["time_s"]
    print("  time: " + ", ".join(f"{k} {v:.1f} s" for k, v in t.items()))


def summary(results: dict) -> dict:
    """Max ``|spike difference|`` per quadrant and counts above the paper's bounds [-]."""
    ok = {i: r for i, r in results.items() if "error" not in r}
    per_q = {q: max((abs(r["difference"][d]["spikes"][q]) for r in ok.values()
                     for d in DIRECTIONS), default=float("nan")) for q in QUADRANTS}
    vals = [abs(r["difference"][d]["spikes"][q]) for r in ok.values() for d in DIRECTIONS
            for q in QUADRANTS]
    fails = {i: [f"{d.upper()} {q}" for d in DIRECTIONS for q in QUADRANTS
                 if abs(r["difference"][d]["spikes"][q]) > PAPER_MAX] for i, r in ok.items()}
    lobes = [r["difference"][d]["lobes"][q] for r in ok.values() for d in DIRECTIONS
             for q in QUADRANTS]
    ce = max((abs(r["difference"][d]["contour_error"]) for r in ok.values()
              for d in DIRECTIONS), default=float("nan"))
    att = {}
    for r in ok.values():
        for name, diff in r.get("attribution", {}).items():
            v = [abs(diff[d]["spikes"][q]) for d in DIRECTIONS for q in QUADRANTS]
            a = att.setdefault(name, {"max": 0.0, "n_above_4.1um": 0, "machines_above_4.1um": 0,
                                      "n_values": 0})
            a["max"] = max(a["max"], max(v))
            a["n_above_4.1um"] += sum(x > PAPER_MAX for x in v)
            a["machines_above_4.1um"] += any(x > PAPER_MAX for x in v)
            a["n_values"] += len(v)
    return {"max_abs_spike_difference": per_q, "n_values": len(vals),
            "attribution": att,
            "n_above_4.1um": sum(v > PAPER_MAX for v in vals),
            "n_above_0.4um": sum(v > PAPER_MIN for v in vals),
            "max_lobe_difference": max(lobes, default=float("nan")),
            "n_lobe_above_4.1um": sum(v > PAPER_MAX for v in lobes),
            "machines_failing_4.1um": {i: f for i, f in fails.items() if f},
            "max_abs_contour_error_difference": ce,
            "errors": {i: r["error"] for i, r in results.items() if "error" in r}}


def print_summary(s: dict, n: int) -> None:
    """Print the study summary."""
    print(f"\n=== summary over {n} machines (TCP, measured - predicted)")
    print("  max |spike difference| per quadrant [um]: " + "  ".join(
        f"{q} {v * 1e6:.2f}" for q, v in s["max_abs_spike_difference"].items()))
    print(f"  values above 4.1 um: {s['n_above_4.1um']} of {s['n_values']}; "
          f"above 0.4 um: {s['n_above_0.4um']} of {s['n_values']}")
    print(f"  largest rise/fall difference: {s['max_lobe_difference'] * 1e6:.2f} um, "
          f"above 4.1 um: {s['n_lobe_above_4.1um']} of {s['n_values']}")
    print(f"  max |contour error difference|: {s['max_abs_contour_error_difference'] * 1e6:.2f} um")
    if s["attribution"]:
        print("  attribution models: max |spike difference| [um], values and machines above "
              "4.1 um")
        for name, a in s["attribution"].items():
            print(f"    {name:28s} {a['max'] * 1e6:7.2f}   {a['n_above_4.1um']:3d} of "
                  f"{a['n_values']}   {a['machines_above_4.1um']:3d} machines")
    for i, f in s["machines_failing_4.1um"].items():
        print(f"  machine {i} above 4.1 um at: {', '.join(f)}")
    for i, e in s["errors"].items():
        print(f"  machine {i} failed: {e}")


def to_json(obj):
    """Plain JSON types (numpy scalars to floats) [-]."""
    if isinstance(obj, dict):
        return {str(k): to_json(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_json(v) for v in obj]
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def main(argv=None) -> int:
    """Command line entry point."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=6, help="number of machines")
    ap.add_argument("--seed", type=int, default=0, help="study seed")
    ap.add_argument("--only", type=int, nargs="+", help="run only these machine numbers")
    ap.add_argument("--backlash", action="store_true", help="draw a lost motion of 0-8 um")
    ap.add_argument("--lugre-fraction", type=float, default=1 / 3,
                    help="probability of LuGre friction per axis")
    ap.add_argument("--share", type=float, nargs=2, default=SHARE_RANGE, metavar=("LO", "HI"),
                    help="range of the guideway share of the friction drawn per axis")
    ap.add_argument("--no-attribution", action="store_true", help="skip the hybrid models")
    ap.add_argument("--presliding-um", type=float, default=PRESLIDING * 1e6,
                    help="pre-sliding displacement of the identified contacts [um]; 0: static")
    ap.add_argument("--fit-presliding", action="store_true",
                    help="fit the pre-sliding to the friction runs' reversals, as identify "
                         "does by default, instead of --presliding-um")
    ap.add_argument("--json", type=Path, help="write the numbers (SI) to this file")
    ap.add_argument("--keep", type=Path, help="keep the bundles in this folder")
    args = ap.parse_args(argv)
    presliding = None if args.fit_presliding else args.presliding_um * 1e-6

    cmd = paper_circle_command()
    indices = args.only if args.only else list(range(args.n))
    results, descs = {}, {}
    t_start = time.perf_counter()
    for i in indices:
        true, desc = draw_machine(args.seed, i, args.backlash, args.lugre_fraction,
                                   tuple(args.share))
        descs[i] = desc
        try:
            if args.keep:
                wd = args.keep / f"machine_{i}"
                wd.mkdir(parents=True, exist_ok=True)
                res = evaluate(true, cmd, wd, not args.no_attribution, presliding)
            else:
                with tempfile.TemporaryDirectory() as tmp:
                    res = evaluate(true, cmd, Path(tmp), not args.no_attribution, presliding)
        except Exception as exc:
            results[i] = {"error": f"{type(exc).__name__}: {exc}"}
            print(f"\n=== machine {i}: failed: {results[i]['error']}")
            continue
        results[i] = res
        print_machine(i, desc, res)
        sys.stdout.flush()
    s = summary(results)
    print_summary(s, len(indices))
    print(f"  total time {time.perf_counter() - t_start:.0f} s")
    if args.json:
        args.json.write_text(json.dumps(to_json({
            "seed": args.seed, "backlash": args.backlash, "lugre_fraction": args.lugre_fraction,
            "share_range": list(args.share),
            "presliding": presliding,
            "units": "SI (m, N, s); spikes signed, measured minus predicted",
            "machines": {i: {"draw": descs[i], **results[i]} for i in indices},
            "summary": s}), indent=1))
    return 1 if s["errors"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
