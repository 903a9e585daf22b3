"""Machine model files: YAML with a format version, validated, unknown keys are errors.

All values are SI (kg, m, s, N, A, rad). What is exported loads back to identical numbers
(floats are written with their shortest exact representation).
"""

from __future__ import annotations

from typing import Literal

from ..errors import InputError
from ..machines.builtin import builtin_machine
from ..model import Machine
from ..path.settings import InterpolatorSettings
from .atomic import write_text_atomic
from .text import read_text
from .truthfile import FORMAT as TRUTH_FORMAT
from .truthfile import truth_machine
from .unitchecks import warn_unit_suspects

FORMAT = "tcpmm-model/1"
_HINT = "see the keys that `tcpmm machine export` writes"
#: the units of a number whose key's name does not say them, as the header lists them
_UNITS = "in SI units (the file's header, docs/formats.md section 5)"

#: the last line of every model file tcpmm writes: a file with tcpmm's header and without
#: it was cut short, and what is missing would otherwise be read as the defaults [-]
END_LINE = "# end of the model file"
#: how the first line of every model file tcpmm writes begins [-]
_HEADER_START = "# tcpmm machine model ("
_HEADER = _HEADER_START + """{fmt}). SI units throughout:
#   mechanics: J [kg m^2], B [N m s/rad], K_L [N m/rad], lead [m], M [kg], C [N s/m],
#              K [N/m], K_tc [N m/A], load_force [N]
#   servo: K_pp [1/s], K_vp [A s/rad], K_vi [A/rad], k_ff [-], T_p, T_v [s],
#          current_limit [A], current_bandwidth_hz [Hz], delay_samples [-],
#          velocity_filter [-] (FIR taps, newest first), feedforward [segment|centred],
#          filters: current-setpoint filters, {{type: lowpass, f_hz [Hz], zeta [-]}} or
#          {{type: notch, f_hz [Hz], bandwidth_hz [Hz], depth_db [dB]}}
#   friction (table units): fc, fs, fv [N, N, N s/m], vs [m/s], sigma0 [N/m],
#          sigma1 [N s/m], sigma1_fades [-], backlash [m] (total free play of the
#          screw-nut), guideway_velocity [table|relative]
#   sensors: encoder_counts_per_rev [-], scale_resolution [m], tcp_resolution [m]
#   uncertainty (identified models): one standard deviation of the mechanics [as above],
#          friction_level [-] (relative), guideway_share [-], backlash [m],
#          presliding [-] (of the logarithm of the pre-sliding distance), open: what the
#          data leave open, {{quantity, low, high [SI], cause, settle}}
#   interpolation (CNC interpolator, docs/paths.md): period_s [s], profile
#          [trapezoid|scurve], path_accel_m_per_s2 [m/s^2], path_jerk_m_per_s3 [m/s^3],
#          axis_velocity_m_per_s [m/s], axis_accel_m_per_s2 [m/s^2], rapid_m_per_s [m/s],
#          corner_tolerance_m [m], filter_kind [none|linear|bell], filter_time_s [s],
#          blend_tolerance_m [m] (G64 without P; 0: sharp corners), corner_step_share [-]
#          (of the axis acceleration a sharp corner's velocity step takes; 0: exact stops),
#          transition_jerk_m_per_s3 [m/s^3] (axis jerk where the curvature steps at a
#          tangent block transition; null: no limit)
#   specification (what the builder states it meets): circular_deviation_m [m] (ISO 230-4
#          G of a circular test at the tool; a circle verdict given no tolerance judges
#          against it)
"""


class ModelFile(Machine):
    """Schema of a model file: a machine and its format version."""

    format: Literal["tcpmm-model/1"]


def machine_to_dict(machine: Machine) -> dict:
    """Plain dict of a machine in the model-file layout."""
    d = machine.model_dump(mode="python")
    for a in d["axes"].values():
        if a.get("uncertainty") is None:
            a.pop("uncertainty", None)  # files of hand-made models stay as they were
        elif not a["uncertainty"].get("open"):
            a["uncertainty"].pop("open", None)
        else:
            a["uncertainty"]["open"] = [dict(r) for r in a["uncertainty"]["open"]]
        if not a["servo"].get("filters"):
            a["servo"].pop("filters", None)
    out = {"format": FORMAT, "name": d["name"]}
    if d.get("suspect"):
        out["suspect"] = list(d["suspect"])  # first, where a reader sees it
    out["axes"] = d["axes"]
    if d.get("interpolation") is not None:
        out["interpolation"] = d["interpolation"]
    if d.get("specification") is not None:
        out["specification"] = d["specification"]
    return out


def with_interpolation(machine: Machine) -> Machine:
    """The machine with every interpolator setting written out: its own where it has
    them, the defaults where not (the numbers a program is interpolated with either way).

    Parameters
    ----------
    machine : Machine
        The model [-].
    """
    full = InterpolatorSettings.model_validate(machine.interpolation or {})
    return machine.model_copy(update={"interpolation": full.model_dump(mode="python")})


def _model_text(machine: Machine) -> str:
    import yaml  # here: a built-in machine is read without PyYAML (some 15 ms)

    body = yaml.safe_dump(machine_to_dict(machine), sort_keys=False, default_flow_style=False)
    return _HEADER.format(fmt=FORMAT) + body


def dumps_machine(machine: Machine) -> str:
    """The model file text of a machine: the header, the model, and :data:`END_LINE`."""
    return _model_text(machine) + END_LINE + "\n"


def model_identity(machine: Machine) -> dict:
    """What tells a model from another in the outputs computed from it: its name and the
    first 16 hex digits of the SHA-256 of the model file text it writes as, up to its
    last line (:func:`dumps_machine`: the same for a file and for the file read and
    written again, its comments aside) [-]."""
    import hashlib

    digest = hashlib.sha256(_model_text(machine).encode("utf-8")).hexdigest()[:16]
    return {"name": machine.name, "digest": digest}


def refuse_cut_short(text: str, file) -> None:
    """Refuse a model file that starts with the header tcpmm writes but lacks the line it
    writes last: a copy or a transfer interrupted, whose missing keys would be read as
    their defaults with no word. A file written by hand, without the header, is not held
    to it.

    Parameters
    ----------
    text : str
        The model file's text [-].
    file : str or Path
        Its name, for the message [-].
    """
    lines = text.splitlines()
    if not text.startswith(_HEADER_START) or any(
            line.strip() == END_LINE for line in lines):
        return
    last = next((k for k in range(len(lines), 0, -1) if lines[k - 1].strip()), 0)
    shown = f" ({lines[last - 1].strip()!r})" if last else ""
    raise InputError(
        f"{file}: the model file ends at line {last}{shown} without the line "
        f"{END_LINE!r} that tcpmm writes last: it was cut short (a copy or a transfer "
        "interrupted), and what is missing would be read as defaults. Write it again "
        "(tcpmm identify -o, tcpmm machine export), or copy it whole; a model edited by "
        "hand keeps that line at its end")


def write_machine(machine: Machine, path) -> None:
    """Write a model file atomically."""
    write_text_atomic(path, dumps_machine(machine))


def _to_machine(mf: ModelFile) -> Machine:
    return Machine(name=mf.name, axes=mf.axes, interpolation=mf.interpolation,
                   suspect=mf.suspect, specification=mf.specification)


def loads_machine(text: str, file="<model>") -> Machine:
    """Parse model-file text; a number that looks written in mm or um is warned of."""
    from .yamlutil import validate_yaml

    refuse_cut_short(text, file)
    machine = _to_machine(validate_yaml(text, ModelFile, file, "machine model", _HINT,
                                        FORMAT, _UNITS))
    warn_unit_suspects(machine, file)
    return machine


def read_machine(path) -> Machine:
    """Read a model file, or ``builtin:NAME`` for a built-in machine.

    Parameters
    ----------
    path : str or Path
        Model file, a reference machine's ``truth.yaml`` (as
        :func:`~tcpmm.io.truthfile.machine_from_truth` reads it), or ``builtin:vmc`` [-].
    """
    s = str(path)
    if s.startswith("builtin:"):
        return builtin_machine(s.split(":", 1)[1])
    text = read_text(path, "machine model", hint=(
        "give a model file tcpmm identify wrote, a reference machine's truth.yaml, or a "
        "built-in machine (builtin:vmc)"))
    if TRUTH_FORMAT in text:  # a reference machine's true parameters are a model too
        from .yamlutil import load_yaml

        d, _ = load_yaml(text, path)
        if isinstance(d, dict) and d.get("format") == TRUTH_FORMAT:
            return truth_machine(d, path)
    return loads_machine(text, path)
