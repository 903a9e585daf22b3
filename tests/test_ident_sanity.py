"""Warnings before an identified model misleads: a sweep held by friction, and a loop that is
unstable as the drive samples it."""

import json
import warnings

import pytest

from tcpmm.cli import main
from tcpmm.ident.gates import FRICTION_LEAD_DEG, friction_holds_sweep, warn_unstable_sampled_loop
from tcpmm.ident.pipeline import MIN_COHERENCE, identify_axis
from tcpmm.machines.builtin import builtin_machine
from tcpmm.machines.virtual import axis_config, virtual_friction, virtual_sweep
from tcpmm.servo.sampled import sampled_spectral_radius


def identify(machine, travel, friction=True):
    a = machine.axes["X"]
    cfg = axis_config(machine, "X")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_axis("X", virtual_sweep(a, name="X", travel_speed_m_per_s=travel), cfg,
                            friction=virtual_friction(a, name="X") if friction else None)
    return idn, [str(w.message) for w in caught if "friction holds the axis" in str(w.message)]


def test_a_standing_sweep_held_by_friction_is_flagged(identify_builtin):
    """Built-in X with its friction, swept at 2 A: standing, the motor's velocity at 3-6 Hz is
    nearly in phase with the current (lead about 97 deg over a free mass); travelling at
    20 mm/s it lags by 90 deg like a mass, and nothing is said."""
    m = builtin_machine()
    idn, said = identify(m, 0.0)
    assert len(said) == 1
    assert "axis X" in said[0] and "stands still" in said[0] and "20 mm/s" in said[0]
    held = idn.friction_hold
    assert held.lead_deg > FRICTION_LEAD_DEG + 30.0 and held.f_hi_hz <= 15.0
    idn, said = identify_builtin("X")  # the default sweep travels at 20 mm/s
    said = [w for w in said if "friction holds the axis" in w]
    assert said == [] and idn.friction_hold is None
    assert friction_holds_sweep(idn.frfs["G_M"], MIN_COHERENCE) is None


def test_a_standing_sweep_without_friction_is_not_flagged():
    idn, said = identify(builtin_machine(friction=False), 0.0, friction=False)
    assert said == []
    assert friction_holds_sweep(idn.frfs["G_M"], MIN_COHERENCE) is None


def test_an_unstable_sampled_loop_is_reported():
    """A motor inertia fitted a hundred times too small (as a standing sweep gave on one
    unseen axis) leaves the continuous loop of the built-in X stable but makes the sampled
    loop diverge."""
    a = builtin_machine().axes["X"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert warn_unstable_sampled_loop("X", a, []) < 1.0
    bad = a.replace(mechanics=a.mechanics.replace(J_m=a.mechanics.J_m / 100))
    with pytest.warns(UserWarning, match="unstable as the drive samples it") as caught:
        rho = warn_unstable_sampled_loop("X", bad, ["J_m", "B_L"])
    assert rho > 1.0 and "J_m, B_L" in str(caught[0].message)
    assert rho == sampled_spectral_radius(bad.mechanics, bad.servo)


def test_machine_show_reports_the_sampled_loop(capsys):
    assert main(["machine", "show", "builtin:vmc", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for d in data.values():
        assert d["closed_loop_stable"] and 0.9 < d["sampled_loop_spectral_radius"] < 1.0


def test_an_axis_s_warnings_name_it_and_say_what_its_kept_fit_leaves_open_once():
    """identify of bench H said "the FRFs do not determine B_m, B_L" and then "the FRFs
    do not determine B_L" (two fits of X on the way to the one kept), and "no excitation
    power in 993.7-1223 Hz, ..." (gaps above the sweep's 1000 Hz end), none naming its
    axis or file. Each warning of an axis now names both; what the FRFs leave open is said
    once, of the fit the model keeps, and only gaps within the swept band are listed."""
    from conftest import bench_path
    from tcpmm.ident.chain import AxisRun, run_axis
    from tcpmm.ident.options import IdentifyOptions
    from tcpmm.io.bundle import read_bundle

    bundle = read_bundle(bench_path("h") / "bundle")
    rec = bundle.axes["X"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = run_axis(AxisRun("X", rec.sweep, bundle.machine.axes["X"], rec.friction),
                       IdentifyOptions(verdict=False))
    said = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert said and all("axis X: " in s for s in said), said
    open_ = [s for s in said if "do not determine" in s]
    assert open_ == [f"{rec.sweep.source}: axis X: the FRFs do not determine "
                     f"{', '.join(idn.physical.undetermined)} (relative standard deviation "
                     "above 50 %); their values are a guess"]
    assert not [s for s in said if "no excitation power" in s]
