"""``tcpmm.compensate`` judges the circle ``tcpmm compensate`` judges: the one given, in
the program's plane about its centre, else the one the command runs where it is a
circular test; ``settings["circle"]`` of the result names it. The API judged a circle in
XY about the origin only, and none where no radius was given: a G18 circle or one off
the origin had no spikes or G judged, or those of a circle it does not run."""

import json

import pytest

import tcpmm
from tcpmm.cli import main
from test_compensate import _circle_program


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
@pytest.mark.parametrize(("plane", "centre_mm", "given"), [("ZX", (0.0, 0.0), False),
                                                           ("XY", (50.0, 40.0), True)])
def test_the_api_judges_the_circle_the_command_line_judges(tmp_path, capsys, plane,
                                                           centre_mm, given):
    prog = tmp_path / "c.nc"
    prog.write_text(_circle_program(plane, centre_mm))
    opts = ["--radius", "20", "--centre", ",".join(f"{c:g}" for c in centre_mm)]
    assert main(["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
                 "--draws", "0", "--json", *(opts if given else [])]) == 0
    cli = json.loads(capsys.readouterr().out)
    where = {"radius_m": 0.02, "centre_m": tuple(c * 1e-3 for c in centre_mm)} if given else {}
    comp = tcpmm.compensate("builtin:vmc", prog, draws=0, **where)
    said = comp.settings["circle"]
    assert said == cli["settings"]["circle"]
    assert said["plane"] == plane and said["from"] == ("given" if given else "command")
    assert said["radius_m"] == pytest.approx(0.02, abs=1e-6)
    assert said["centre_m"] == pytest.approx([c * 1e-3 for c in centre_mm], abs=1e-6)
    for when in ("before", "after"):
        circle = comp.to_dict()["scores"][when]["circle"]
        # as the command line writes it: a spike not determined is null, JSON has no NaN
        plain = json.loads(json.dumps(circle).replace("NaN", "null"))
        assert plain == cli["scores"][when]["circle"], when
    before = cli["scores"]["before"]["circle"]
    assert 5 < before["circular_deviation_um"] < 500
    assert len(before["passes"][0]["spikes_um"]) == 4 and before["largest_spike_um"] > 0


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_the_api_compensates_a_g18_program_on_a_machine_of_x_and_z(tmp_path, capsys):
    """The API refused a G18 circle on a model of X and Z only ("the command drives axis Y
    that the model lacks": the interpreter writes the Y the program never names), where
    the command line compensates it; it now leaves the Y out as the command line does and
    says where it stands."""
    from tcpmm import builtin_machine, save_model

    vmc = builtin_machine()
    model = tmp_path / "xz.yaml"
    save_model(vmc.model_copy(update={"axes": {n: a for n, a in vmc.axes.items()
                                               if n != "Y"}}), model)
    prog = tmp_path / "g18.nc"
    prog.write_text("G21 G90 G18\nG0 X20 Z0\nG2 X20 Z0 I-20 K0 F3000\nM30\n")
    assert main(["compensate", str(model), "--gcode", str(prog), "-o",
                 str(tmp_path / "c.csv"), "--draws", "0", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    comp = tcpmm.compensate(model, prog, draws=0)
    assert comp.command.axes == ["X", "Z"] and comp.settings["held_axes_m"] == {"Y": 0.0}
    for key in ("circle", "held_axes_m"):
        assert comp.settings[key] == cli["settings"][key], key
    assert comp.settings["circle"]["plane"] == "ZX"
    api = json.loads(json.dumps(comp.to_dict()["scores"]["after"]).replace("NaN", "null"))
    assert api == cli["scores"]["after"]
