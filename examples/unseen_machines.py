"""Validation on unseen machines: identify, predict and compare the circular test.

For ``N`` random machines derived from the built-in one, each with its X and Y axes
perturbed (mechanics, friction level, guideway/screw split, Stribeck or LuGre friction,
servo gains, velocity feedforward, sensor resolutions, optionally lost motion), the
script runs what a user would do on a real machine:

1. record the measurement bundle (servo-excitation sweep and constant-speed friction runs
   per axis) with :func:`tcpmm.virtual.virtual_bundle`;
2. record the circular test (R35 mm, F5000 mm/min, CCW then CW) with
   :func:`tcpmm.virtual.virtual_run`;
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

    python examples/unseen_machines.py [--n 6] [--seed 0] [--backlash] [--only 2 5]
                                       [--lugre-fraction 0.33] [--presliding-um 0.5]
                                       [--json FILE] [--keep DIR]
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

from tcpmm.analysis.circular import QUADRANTS, analyse_circle
from tcpmm.analysis.compare import compare_circles, lobe_difference
from tcpmm.builtin import builtin_machine
from tcpmm.demo import RADIUS_MM, paper_circle_command
from tcpmm.ident.friction import PRESLIDING
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle
from tcpmm.mechanics.friction import LuGreFriction, StribeckFriction, friction_params_array
from tcpmm.model import Axis, AxisFriction, Machine, Sensors
from tcpmm.servo.closedloop import is_stable
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import sampled_spectral_radius
from tcpmm.sim.friction import sliding_friction
from tcpmm.simulate import simulate
from tcpmm.units import mm_to_m
from tcpmm.virtual import virtual_bundle, virtual_run

AXES = ("X", "Y")
DIRECTIONS = ("ccw", "cw")
#: Spike-difference bounds of the paper's Table 2 [m].
PAPER_MAX = 4.1e-6
PAPER_MIN = 0.4e-6
#: Table velocity at which the guideway share of friction is evaluated [m/s].
V_SHARE = 0.01
RADIUS = mm_to_m(RADIUS_MM)

MASSES = ("J_m", "J_L", "M_t", "M_b", "M_h")
STIFFNESSES = ("K_L", "K_t", "K_b", "K_h")
DAMPINGS = ("B_m", "B_L", "C_t", "C_b", "C_h")
ENCODER_COUNTS = (8192, 10000, 65536, 1048576)
#: Scale and TCP-device resolutions [m].
SCALE_RESOLUTIONS = (5e-8, 1e-7, 5e-7, 1e-6)
TCP_RESOLUTIONS = (1e-8, 7.8e-8, 1e-7)
K_FF = (0.0, 0.5, 0.9)
#: Screen factor of the stability check: the sampled loop's spectral radius must be below.
MAX_SPECTRAL_RADIUS = 0.9995
MAX_DRAWS = 50
#: Mechanics parameters that act like viscous friction in steady motion.
LINEAR_DAMPING = ("B_m", "B_L", "C_t")


# ----------------------------------------------------------------------------- drawing


def log_uniform(rng, lo, hi):
    """A factor drawn log-uniformly in ``[lo, hi]`` [-]."""
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def scale_friction(f, k):
    """A friction element with its levels and viscous coefficients multiplied by ``k``.

    Parameters
    ----------
    f : StribeckFriction or LuGreFriction or None
        The element [-].
    k : float
        Factor, >= 0 [-].

    Returns
    -------
    StribeckFriction or LuGreFriction or None
        The scaled element (``None`` for ``None`` or ``k == 0``) [-].
    """
    if f is None or k <= 0:
        return None
    d = f.model_dump()
    for n in ("fc_pos", "fc_neg", "fs_pos", "fs_neg", "fv_pos", "fv_neg"):
        d[n] = d[n] * k
    if isinstance(f, LuGreFriction):
        d["sigma0"] *= k  # keeps the pre-sliding displacement
        d["sigma1"] *= k
    return type(f)(**d)


def as_stribeck(f):
    """The Stribeck element with the levels of a LuGre element (else unchanged) [-]."""
    if isinstance(f, LuGreFriction):
        d = f.model_dump()
        d.pop("sigma0")
        d.pop("sigma1")
        return StribeckFriction(**d)
    return f


def draw_contact(rng, fc, fs_ratio, fv, lugre, m_t):
    """One friction contact (guideway or screw) in table units.

    Parameters
    ----------
    rng : numpy.random.Generator
        Random generator [-].
    fc : float
        Mean Coulomb level [N].
    fs_ratio : float
        Static over Coulomb level [-].
    fv : float
        Viscous coefficient [N s/m].
    lugre : bool
        LuGre instead of Stribeck [-].
    m_t : float
        Carriage mass, sets the bristle damping of LuGre [kg].

    Returns
    -------
    StribeckFriction or LuGreFriction
        The element; levels asymmetric by up to +-15 % [-].
    """
    a = rng.uniform(-0.15, 0.15)
    vs = 2e-3 * log_uniform(rng, 0.5, 3.0)
    kw = dict(fc_pos=fc * (1 + a), fc_neg=fc * (1 - a), fs_pos=fs_ratio * fc * (1 + a),
              fs_neg=fs_ratio * fc * (1 - a), vs=vs, fv_pos=fv, fv_neg=fv)
    if not lugre:
        return StribeckFriction(**kw)
    z_pre = 1e-6 * log_uniform(rng, 0.3, 2.0)  # pre-sliding deflection at the static level [m]
    sigma0 = fs_ratio * fc / z_pre
    zeta = log_uniform(rng, 0.05, 0.3)
    return LuGreFriction(**kw, sigma0=sigma0, sigma1=2 * zeta * math.sqrt(sigma0 * m_t))


def draw_axis(rng, base: Axis, base_fric: dict, servo_mode: str, K_pp: float, k_ff: float,
              sensors: Sensors, lugre_fraction: float, backlash: bool):
    """One perturbed axis and a description of the draw.

    Parameters
    ----------
    rng : numpy.random.Generator
        Random generator [-].
    base : Axis
        Built-in axis [SI].
    base_fric : dict
        Built-in ``{"guideway": (Fc, Fs, Fv), "screw": (...)}`` [N, N, N s/m].
    servo_mode : {"tuned", "scaled"}
        Re-tune the velocity loop to the new inertia, or scale the built-in gains [-].
    K_pp : float
        Position-loop gain, shared by the axes of the machine [1/s].
    k_ff : float
        Velocity feedforward [-].
    sensors : Sensors
        Sensor resolutions [SI].
    lugre_fraction : float
        Probability of LuGre friction [-].
    backlash : bool
        Draw a lost motion of 0-8 um [-].
    """
    mf = {k: log_uniform(rng, 0.6, 1.6) for k in MASSES}
    mf.update({k: log_uniform(rng, 0.4, 2.5) for k in STIFFNESSES})
    mf.update({k: log_uniform(rng, 0.5, 2.0) for k in DAMPINGS})
    mech = base.mechanics.scaled(**mf)
    level = log_uniform(rng, 0.3, 2.0)
    share = rng.uniform(0.2, 0.9)
    fc_tot = (base_fric["guideway"][0] + base_fric["screw"][0]) * level
    fv_tot = (base_fric["guideway"][2] + base_fric["screw"][2]) * level * log_uniform(rng, 0.5, 2)
    fs_ratio = rng.uniform(1.1, 1.4)
    lugre = bool(rng.uniform() < lugre_fraction)
    fric = AxisFriction(
        guideway=draw_contact(rng, share * fc_tot, fs_ratio, share * fv_tot, lugre, mech.M_t),
        screw=draw_contact(rng, (1 - share) * fc_tot, fs_ratio, (1 - share) * fv_tot, lugre,
                           mech.M_t),
        backlash=float(rng.uniform(0.0, 8e-6)) if backlash else 0.0,
    )
    if servo_mode == "tuned":
        bw, corner = rng.uniform(50.0, 120.0), rng.uniform(10.0, 30.0)
        servo = ServoParams.tuned(mech.J_total, mech.K_tc, bandwidth_hz=bw,
                                  integral_corner_hz=corner, K_pp=K_pp,
                                  current_limit=base.servo.current_limit, k_ff=k_ff)
        sdesc = f"tuned {bw:.0f} Hz, PI corner {corner:.0f} Hz"
    else:
        kvp, kvi = log_uniform(rng, 0.7, 1.3), log_uniform(rng, 0.7, 1.3)
        s = base.servo
        servo = ServoParams.create(**{**s.model_dump(), "K_pp": K_pp, "K_vp": s.K_vp * kvp,
                                      "K_vi": s.K_vi * kvi, "k_ff": k_ff})
        sdesc = f"built-in gains, K_vp x{kvp:.2f}, K_vi x{kvi:.2f}"
    axis = Axis(mechanics=mech, servo=servo, sensors=sensors, friction=fric)
    desc = {"mechanics_factors": mf, "friction_level": level, "guideway_share": share,
            "fs_over_fc": fs_ratio, "friction_model": "LuGre" if lugre else "Stribeck",
            "vs_guideway": fric.guideway.vs, "vs_screw": fric.screw.vs,
            "backlash": fric.backlash, "servo": sdesc, "K_pp": K_pp, "k_ff": k_ff,
            "K_vp": servo.K_vp, "K_vi": servo.K_vi}
    return axis, desc


def axis_spectral_radius(axis: Axis) -> float:
    """Spectral radius of the exact sampled position loop (nan if unavailable) [-]."""
    try:
        return sampled_spectral_radius(axis.mechanics, axis.servo)
    except Exception:
        return float("nan")


def axis_stable(axis: Axis) -> bool:
    """Continuous position loop stable and the sampled loop within the screen [-]."""
    if not is_stable(axis.mechanics, axis.servo):
        return False
    rho = axis_spectral_radius(axis)
    return not rho >= MAX_SPECTRAL_RADIUS


def draw_machine(seed: int, index: int, backlash: bool = False, lugre_fraction: float = 1 / 3):
    """Random machine number ``index`` of a study seeded by ``seed``.

    Parameters
    ----------
    seed : int
        Study seed [-].
    index : int
        Machine number [-].
    backlash : bool
        Draw a lost motion per axis [-].
    lugre_fraction : float
        Probability of LuGre friction per axis [-].

    Returns
    -------
    Machine, dict
        The true machine and a description of the draw (with the number of redraws) [-].
    """
    from tcpmm.builtin import _FRICTION

    rng = np.random.default_rng([seed, index])
    base = builtin_machine()
    for attempt in range(MAX_DRAWS):
        k_ff = float(rng.choice(K_FF))
        servo_mode = "tuned" if rng.uniform() < 0.5 else "scaled"
        K_pp = (rng.uniform(25.0, 60.0) if servo_mode == "tuned"
                else base.axes["X"].servo.K_pp * log_uniform(rng, 0.7, 1.3))
        sensors = Sensors(encoder_counts_per_rev=int(rng.choice(ENCODER_COUNTS)),
                          scale_resolution=float(rng.choice(SCALE_RESOLUTIONS)),
                          tcp_resolution=float(rng.choice(TCP_RESOLUTIONS)))
        axes, desc = dict(base.axes), {}
        for name in AXES:
            axes[name], desc[name] = draw_axis(
                rng, base.axes[name], _FRICTION[name], servo_mode, K_pp, k_ff, sensors,
                lugre_fraction, backlash)
        if all(axis_stable(axes[n]) for n in AXES):
            desc.update(redraws=attempt, servo_mode=servo_mode, k_ff=k_ff,
                        sensors=sensors.model_dump(),
                        spectral_radius={n: axis_spectral_radius(axes[n]) for n in AXES})
            return Machine(name=f"unseen machine {index} (seed {seed})", axes=axes), desc
    raise RuntimeError(f"no stable machine in {MAX_DRAWS} draws for index {index}")


# ------------------------------------------------------------------------- evaluation


def contact_force(f, v: float) -> float:
    """Steady sliding friction of one contact at table velocity ``v`` [N]."""
    return float(sliding_friction(v, friction_params_array(f))) if f is not None else 0.0


def friction_split(fr: AxisFriction | None, v: float = V_SHARE):
    """Guideway share and total of the steady friction at ``+v`` and ``-v``.

    Parameters
    ----------
    fr : AxisFriction or None
        Friction of the axis [-].
    v : float
        Table speed [m/s].

    Returns
    -------
    tuple of float
        ``(share, total)``: guideway force over the total [-], mean total force [N].
    """
    if fr is None:
        return float("nan"), 0.0
    g = 0.5 * (contact_force(fr.guideway, v) - contact_force(fr.guideway, -v))
    s = 0.5 * (contact_force(fr.screw, v) - contact_force(fr.screw, -v))
    tot = g + s
    return (g / tot if tot > 0 else float("nan")), tot


def resplit(fr: AxisFriction | None, share: float):
    """The same friction total shared between guideway and screw as ``share`` [-]."""
    if fr is None:
        return None
    s_id, _ = friction_split(fr)
    if fr.guideway is not None and s_id > 0:
        total = scale_friction(fr.guideway, 1 / s_id)
    else:
        total = scale_friction(fr.screw, 1 / (1 - s_id))
    return fr.model_copy(update={"guideway": scale_friction(total, share),
                                 "screw": scale_friction(total, 1 - share)})


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


def tcp_figures(result):
    """TCP spikes, their two lobes and the contour error per direction [m]."""
    out = {}
    for d in DIRECTIONS:
        s = result.pass_for(d).sensors["tcp"]
        out[d] = {"spikes": {q: float(s.spikes[q]) for q in QUADRANTS},
                  "lobes": s.lobes,
                  "contour_error": float(s.contour_error)}
    return out


def differences(meas, pred):
    """Measured minus predicted TCP figures per direction [m].

    ``lobes`` is the larger of the rise and the fall differences: it does not jump when
    the spike changes sign because rise and fall are of similar size.
    """
    out = {}
    for d in DIRECTIONS:
        m, p = meas[d], pred[d]
        out[d] = {
            "spikes": {q: m["spikes"][q] - p["spikes"][q] for q in QUADRANTS},
            "lobes": {q: lobe_difference(m["lobes"][q], p["lobes"][q]) for q in QUADRANTS},
            "contour_error": m["contour_error"] - p["contour_error"],
        }
    return out


def max_abs_spike(diff) -> float:
    """Largest ``|spike difference|`` over directions and quadrants [m]."""
    return max(abs(diff[d]["spikes"][q]) for d in DIRECTIONS for q in QUADRANTS)


def with_axes(machine: Machine, make) -> Machine:
    """A copy of ``machine`` with X and Y replaced by ``make(name)`` [-]."""
    return machine.model_copy(update={"axes": {**machine.axes, **{n: make(n) for n in AXES}}})


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


def predicted_figures(model: Machine, cmd):
    """TCP figures of a model's simulated circle [m]."""
    return tcp_figures(analyse_circle(simulate(model, cmd), RADIUS))


def without_backlash(machine: Machine) -> Machine:
    """``machine`` with the lost motion of X and Y set to zero [-]."""
    return with_axes(machine, lambda n: machine.axes[n].replace(
        friction=machine.axes[n].friction.model_copy(update={"backlash": 0.0})))


def backlash_effect(true: Machine, cmd) -> float:
    """Largest change of the TCP path when the lost motion is set to zero [m]."""
    if not any(true.axes[n].friction.backlash > 0 for n in AXES):
        return float("nan")
    a, b = simulate(true, cmd), simulate(without_backlash(true), cmd)
    return float(max(np.max(np.abs(a.axes[n].tcp - b.axes[n].tcp)) for n in AXES))


def evaluate(true: Machine, cmd, workdir: Path, attribute: bool = True,
             presliding: float = PRESLIDING) -> dict:
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
    presliding : float
        Pre-sliding displacement given to the identified contacts, ``0`` for static
        friction (:mod:`tcpmm.ident.friction.presliding`) [m].

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
    ap.add_argument("--no-attribution", action="store_true", help="skip the hybrid models")
    ap.add_argument("--presliding-um", type=float, default=PRESLIDING * 1e6,
                    help="pre-sliding displacement of the identified contacts [um]; 0: static")
    ap.add_argument("--json", type=Path, help="write the numbers (SI) to this file")
    ap.add_argument("--keep", type=Path, help="keep the bundles in this folder")
    args = ap.parse_args(argv)
    presliding = args.presliding_um * 1e-6

    cmd = paper_circle_command()
    indices = args.only if args.only else list(range(args.n))
    results, descs = {}, {}
    t_start = time.perf_counter()
    for i in indices:
        true, desc = draw_machine(args.seed, i, args.backlash, args.lugre_fraction)
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
            "presliding": presliding,
            "units": "SI (m, N, s); spikes signed, measured minus predicted",
            "machines": {i: {"draw": descs[i], **results[i]} for i in indices},
            "summary": s}), indent=1))
    return 1 if s["errors"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
