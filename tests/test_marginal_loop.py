"""A sampled loop is stable or unstable alike wherever it is judged, undamped modes too.

A structure mode of damping zero that the loop cannot move keeps its eigenvalue on the
unit circle, which rounding puts a few ulp to either side of 1: marginally stable, not
diverging. Tuning, margins, simulation, the model checks and ``machine show`` all judge
it by :func:`~tcpmm.servo.sampled.is_stable_radius`; a loop with a mode that grows
(spectral radius 1.002) stays unstable in every one of them.
"""

import json

import pytest

import tcpmm
from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.io.modelfile import read_machine, write_machine
from tcpmm.mechanics.lumped import AxisMechanics
from tcpmm.servo.params import ServoParams
from tcpmm.servo.sampled import sampled_spectral_radius

GM, PM = 6.0, 45.0


def _undamped(machine, *dampings, gain: float = 1.0):
    """The machine with the ``dampings`` of every axis zero and each velocity gain times
    ``gain`` [SI]."""
    axes = {}
    for n, a in machine.axes.items():
        mech = AxisMechanics(**{**a.mechanics.model_dump(), **dict.fromkeys(dampings, 0.0)})
        servo = ServoParams.create(**{**a.servo.model_dump(), "K_vp": a.servo.K_vp * gain})
        axes[n] = a.replace(mechanics=mech, servo=servo)
    return machine.model_copy(update={"axes": axes})


def _verdicts(machine, name: str, capsys, tmp_path) -> dict:
    """Whether each judge of a sampled loop calls axis ``name``'s stable [-]."""
    from tcpmm.cli._app import refuse_unstable
    from tcpmm.ident.gates.findings import check_sampled_loop
    from tcpmm.servo.modeshift import worst_shift
    from tcpmm.sim.simulate import unstable_loops

    a = machine.axes[name]
    path = tmp_path / "m.yaml"
    write_machine(machine, path)
    capsys.readouterr()
    assert main(["machine", "show", str(path)]) == 0
    shown = next(line for line in capsys.readouterr().out.splitlines()
                 if line.startswith(f"{name}:"))
    try:
        refuse_unstable(machine, str(path))
        refused = False
    except InputError:
        refused = True
    return {"modeshift": worst_shift(a.mechanics, a.servo, GM, tolerance=0.0) is None,
            "simulate": not unstable_loops(machine, [name]),
            "findings": not check_sampled_loop(name, a),
            "cli": not refused,
            "machine show": "sampled loop stable" in shown}


def test_an_undamped_structure_mode_is_stable_in_every_judge(capsys, tmp_path):
    m = _undamped(tcpmm.builtin_machine(), "C_h")
    a = m.axes["Y"]
    # the structure mode's eigenvalue: on the unit circle but for rounding
    assert abs(sampled_spectral_radius(a.mechanics, a.servo) - 1.0) < 1e-12
    assert all(_verdicts(m, "Y", capsys, tmp_path).values())


@pytest.mark.parametrize("dampings", [("C_h",), ("B_m", "B_L", "C_t", "C_b", "C_h")])
def test_machine_show_calls_the_continuous_loop_of_an_undamped_mode_stable(
        capsys, tmp_path, dampings):
    """Its pole on the imaginary axis but for rounding: machine show called X's continuous
    loop UNSTABLE with C_h zero and Y's and Z's with every damping zero, by the sign of
    a rounding error, beside the sampled loop stable."""
    write_machine(_undamped(tcpmm.builtin_machine(), *dampings), tmp_path / "m.yaml")
    assert main(["machine", "show", str(tmp_path / "m.yaml")]) == 0
    heads = [ln for ln in capsys.readouterr().out.splitlines() if ln[:2] in ("X:", "Y:", "Z:")]
    assert len(heads) == 3
    assert all("continuous closed loop stable; sampled loop stable" in h for h in heads)


def test_a_growing_mode_is_unstable_in_every_judge(capsys, tmp_path):
    """Just past the gain that destabilises it the loop grows by 0.2 % a period, which
    no tolerance for rounding may hide."""
    m = _undamped(tcpmm.builtin_machine(), "C_h", gain=6.61)
    a = m.axes["Y"]
    assert 1.001 < sampled_spectral_radius(a.mechanics, a.servo) < 1.01
    assert not any(_verdicts(m, "Y", capsys, tmp_path).values())


@pytest.mark.parametrize("rho, stable", [(1.0 - 6e-16, True), (1.0 + 4e-16, True),
                                         (1.0 + 1e-6, False), (1.5, False),
                                         (float("nan"), False)])
def test_radius_verdict(rho, stable):
    from tcpmm.servo.sampled import is_stable_radius

    assert is_stable_radius(rho) is stable


def test_the_verdict_of_a_loop_is_the_radius_verdict(vmc):
    from tcpmm.servo.sampled import is_stable_radius, sampled_loop_stable

    for gain in (1.0, 6.61):
        for a in _undamped(vmc, "C_h", gain=gain).axes.values():
            rho = sampled_spectral_radius(a.mechanics, a.servo)
            assert sampled_loop_stable(a.mechanics, a.servo) is is_stable_radius(rho)


@pytest.mark.parametrize("dampings", [("C_h",), ("B_m", "B_L", "C_t", "C_b", "C_h")])
def test_tune_raises_the_gains_of_a_model_with_undamped_modes(capsys, tmp_path, dampings):
    """``tcpmm tune`` on a model file with undamped modes: each axis's proposal meets the
    margins, and no loop is called unstable for a radius of 1 that is rounding."""
    model, out = tmp_path / "m.yaml", tmp_path / "tuned.yaml"
    write_machine(_undamped(tcpmm.builtin_machine(), *dampings), model)
    code = main(["tune", str(model), "--json", "--jobs", "1", "-o", str(out)])
    cap = capsys.readouterr()
    data = json.loads(cap.out)
    assert code == 0
    assert "spectral radius 1.0000" not in cap.out + cap.err
    assert all(data["axes"][n]["met"] for n in "XYZ")
    tuned = read_machine(out)
    for n in "XY":  # moved by the circle: raised, and stable as raised
        a = tuned.axes[n]
        assert a.servo.K_vp > 2 * read_machine(model).axes[n].servo.K_vp
        assert abs(sampled_spectral_radius(a.mechanics, a.servo) - 1.0) < 1e-12
