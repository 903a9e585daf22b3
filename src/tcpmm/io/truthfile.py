"""True parameters of a reference machine (``tcpmm-truth/1``) as a tcpmm model.

Reference machines from an independent simulator come with a ``truth.yaml`` holding every
parameter of that simulator, in its own units (screw friction as a torque on the screw,
LuGre pre-sliding as a displacement, loop periods and feedforward as the drive has them).
:func:`machine_from_truth` writes them into a :class:`~tcpmm.model.Machine` with the
structure that simulator has, so that a prediction can be traced to the model or to the
identification: what the true parameters predict is the floor of any identified model.
"""

from __future__ import annotations

from ..errors import InputError
from ..mechanics.friction import LuGreFriction
from ..mechanics.lumped import AxisMechanics
from ..model import Axis, AxisFriction, Machine, Sensors
from ..servo.params import ServoParams
from .text import read_text

FORMAT = "tcpmm-truth/1"


def _mechanics(m: dict, s: dict) -> AxisMechanics:
    return AxisMechanics.create(
        J_m=m["Jm_kgm2"], B_m=m["Bm_Nms_per_rad"], J_L=m["JL_kgm2"], B_L=m["BL_Nms_per_rad"],
        K_L=m["KL_Nm_per_rad"], lead=s["lead_mm"] * 1e-3, M_t=m["Mt_kg"],
        C_t=m["Ct_Ns_per_m"], K_t=m["Kt_N_per_m"], M_b=m["Mb_kg"], C_b=m["Cb_Ns_per_m"],
        K_b=m["Kb_N_per_m"], M_h=m["Mh_kg"], C_h=m["Ch_Ns_per_m"], K_h=m["Kh_N_per_m"],
        K_tc=s["Ktc_Nm_per_A"],
    )


def _lugre(fc, fs, vs, presliding, sigma1, fv) -> LuGreFriction:
    """LuGre contact in table units; ``sigma0`` from the pre-sliding distance at ``fc``."""
    return LuGreFriction(fc_pos=fc, fc_neg=fc, fs_pos=fs, fs_neg=fs, vs=vs, fv_pos=fv,
                         fv_neg=fv, sigma0=fc / presliding, sigma1=sigma1, sigma1_fades=True)


def _friction(f: dict, R: float) -> AxisFriction:
    r2 = R * R
    screw = _lugre(f["screw_Tc_Nm"] / R, f["screw_Ts_Nm"] / R, f["screw_stribeck_mm_s"] * 1e-3,
                   f["screw_presliding_um"] * 1e-6, f["screw_sigma1_Nms_per_rad"] / r2,
                   f["screw_viscous_Nms_per_rad"] / r2)
    guide = _lugre(f["guide_Fc_N"], f["guide_Fs_N"], f["guide_stribeck_mm_s"] * 1e-3,
                   f["guide_presliding_um"] * 1e-6, f["guide_sigma1_Ns_per_m"],
                   f["guide_viscous_Ns_per_m"])
    return AxisFriction(screw=screw, guideway=guide, guideway_velocity="relative")


def _axis(a: dict) -> Axis:
    s, sen = a["servo"], a["sensors"]
    mech = _mechanics(a["mechanics"], s)
    servo = ServoParams.create(
        position_feedback=s["position_feedback"], K_pp=s["Kpp_1_per_s"],
        K_vp=s["Kvp_A_s_per_rad"], K_vi=s["Kvi_A_per_rad"], k_ff=s["velocity_feedforward"],
        T_p=s["position_loop_period_s"], T_v=s["velocity_loop_period_s"],
        current_limit=s["current_limit_A"], current_bandwidth_hz=s["current_loop_bw_Hz"],
        delay_samples=1, velocity_feedback="difference", feedforward="segment",
    )
    sensors = Sensors(encoder_counts_per_rev=sen["encoder_counts_per_rev"],
                      scale_resolution=sen["scale_resolution_um"] * 1e-6,
                      tcp_resolution=sen["tcp_resolution_um"] * 1e-6)
    return Axis(mechanics=mech, servo=servo, sensors=sensors,
                friction=_friction(a["friction"], mech.R_L))


def machine_from_truth(path) -> Machine:
    """Read a ``truth.yaml`` of a reference machine into a model.

    Parameters
    ----------
    path : str or Path
        The truth file [-].

    Returns
    -------
    Machine
        The true machine with the reference simulator's structure: LuGre friction whose
        micro-damping fades with speed, guideway friction on the table-minus-bed velocity,
        one velocity period of computation delay, feedforward from the slope of the current
        command segment, velocity from the backward difference of the encoder [SI].
    """
    from .yamlutil import load_yaml  # here: reading a model needs PyYAML, a built-in not

    d, _ = load_yaml(read_text(path, "truth file"), path)
    return truth_machine(d, path)


def truth_machine(d, path=None) -> Machine:
    """:func:`machine_from_truth` of a truth file's contents ``d``, read from ``path`` [-]."""
    if not isinstance(d, dict) or d.get("format") != FORMAT:
        got = d.get("format") if isinstance(d, dict) else None
        raise InputError(f"not a {FORMAT} file (format: {got!r})", file=path)
    try:
        axes = {name: _axis(a) for name, a in d["axes"].items()}
    except (KeyError, TypeError, AttributeError) as exc:
        raise InputError(f"missing or malformed entry {exc} in a {FORMAT} file",
                         file=path) from None
    name = str(d.get("case", "reference machine"))
    return Machine(name=f"{name} (true parameters)", axes=axes)
