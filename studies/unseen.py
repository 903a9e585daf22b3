"""Random machines derived from the built-in one: the unseen machines of the validation.

Each machine has its X and Y axes perturbed from the built-in ones: mechanics (masses
x0.6-1.6, stiffnesses x0.4-2.5, damping x0.5-2, log-uniform), friction level (x0.3-2),
split between guideway and screw (0.2-0.9), Stribeck or LuGre friction (pre-sliding
0.3-2 um), servo gains (re-tuned to 50-120 Hz or the built-in gains x0.7-1.3), velocity
feedforward (0, 0.5, 0.9), sensor resolutions and, with ``backlash=True``, a lost motion
of 0-8 um per axis. Machine ``index`` of a study seeded by ``seed`` comes from a generator
seeded by ``(seed, index)``, so it can be drawn alone (:func:`draw_machine`).

Used by the validation studies (``studies/unseen_machines.py``,
``studies/spike_sensitivity.py``), whose robust spread of identified over true values on
the machines with play of seeds 0-3 is :data:`tcpmm.whatif.spread.MODEL_ERROR`, and by the
known-answer tests that replay the machines those studies found hard. It is research
code, so it stays out of the installed package.
"""

from __future__ import annotations

import math

import numpy as np

from tcpmm.analysis.circular import QUADRANTS, analyse_circle
from tcpmm.analysis.compare import lobe_difference
from tcpmm.demo import RADIUS_MM, paper_circle_command
from tcpmm.machines.builtin import builtin_machine
from tcpmm.mechanics.friction import LuGreFriction, StribeckFriction, friction_params_array
from tcpmm.model import Axis, AxisFriction, Machine, Sensors
from tcpmm.servo.closedloop import is_stable
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import sampled_spectral_radius
from tcpmm.sim.contact import sliding_friction
from tcpmm.sim.simulate import simulate
from tcpmm.units import mm_to_m

__all__ = ["PAPER_MAX", "RADIUS", "differences", "draw_machine", "friction_split",
           "paper_circle_command", "predicted_figures", "tcp_figures", "with_axes",
           "without_backlash"]

AXES = ("X", "Y")
DIRECTIONS = ("ccw", "cw")
#: Spike-difference bounds of the paper's Table 2 [m].
PAPER_MAX = 4.1e-6
PAPER_MIN = 0.4e-6
#: Range of the guideway share of the friction that machines are drawn from [-].
SHARE_RANGE = (0.2, 0.9)

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
              sensors: Sensors, lugre_fraction: float, backlash: bool,
              share_range: tuple = SHARE_RANGE):
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
    share_range : tuple of float
        Range of the guideway share of the friction, drawn uniformly [-].
    """
    mf = {k: log_uniform(rng, 0.6, 1.6) for k in MASSES}
    mf.update({k: log_uniform(rng, 0.4, 2.5) for k in STIFFNESSES})
    mf.update({k: log_uniform(rng, 0.5, 2.0) for k in DAMPINGS})
    mech = base.mechanics.scaled(**mf)
    level = log_uniform(rng, 0.3, 2.0)
    share = rng.uniform(*share_range)
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


def draw_machine(seed: int, index: int, backlash: bool = False, lugre_fraction: float = 1 / 3,
                 share_range: tuple = SHARE_RANGE):
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
    share_range : tuple of float
        Range of the guideway share of the friction, drawn uniformly per axis [-].

    Returns
    -------
    Machine, dict
        The true machine and a description of the draw (with the number of redraws) [-].
    """
    from tcpmm.machines.builtin import _FRICTION

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
                lugre_fraction, backlash, share_range)
        if all(axis_stable(axes[n]) for n in AXES):
            desc.update(redraws=attempt, servo_mode=servo_mode, k_ff=k_ff,
                        sensors=sensors.model_dump(),
                        spectral_radius={n: axis_spectral_radius(axes[n]) for n in AXES})
            return Machine(name=f"unseen machine {index} (seed {seed})", axes=axes), desc
    raise RuntimeError(f"no stable machine in {MAX_DRAWS} draws for index {index}")


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


def predicted_figures(model: Machine, cmd):
    """TCP figures of a model's simulated circle [m]."""
    return tcp_figures(analyse_circle(simulate(model, cmd), RADIUS))


def without_backlash(machine: Machine) -> Machine:
    """``machine`` with the lost motion of X and Y set to zero [-]."""
    return with_axes(machine, lambda n: machine.axes[n].replace(
        friction=machine.axes[n].friction.model_copy(update={"backlash": 0.0})))
