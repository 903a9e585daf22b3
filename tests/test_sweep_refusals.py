"""What a sweep takes and refuses before any work, and how it names it: the values as
typed, what differs from the study already in the folder."""

import pytest

from conftest import run_cli
from tcpmm.errors import InputError
from tcpmm.io.modelfile import read_machine
from tcpmm.whatif.sweep import apply_parameters, canonical_name, lhs_design, parse_param


def test_an_lhs_range_is_judged_at_its_ends_as_typed(capsys, tmp_path):
    """A range reaching a negative mass was taken or refused as --n and --seed fell (the
    points drawn inside it were judged), naming a value no one typed (-0.10782)."""
    for rng, n in (("-10:1000", 3), ("-10:100", 3), ("-10:100", 5)):
        code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--design", "lhs", "--n", n,
                               "-p", f"X.mechanics.M_t={rng}", "-o", tmp_path / "o",
                               "--workers", 1)
        assert code == 2, (rng, n)
        assert "X.mechanics.M_t = -10:" in " ".join(err.split()), err
    assert not (tmp_path / "o").exists()


def test_lhs_draws_whole_numbers_of_an_integer_parameter():
    """An lhs over delay_samples or encoder_counts_per_rev drew fractions, and every
    variant but a fixed one failed: 'takes whole numbers, got 0.0307'."""
    vmc = read_machine("builtin:vmc")
    specs = [parse_param(t, lambda n: canonical_name(vmc, n))
             for t in ("X.servo.delay_samples=0:3", "X.sensors.encoder_counts_per_rev=1000:20000",
                       "X.servo.K_pp=30:40")]
    vs = lhs_design(specs, 4, seed=0)
    # four strata over four whole numbers: each once
    assert sorted(v.params["X.servo.delay_samples"] for v in vs) == [0, 1, 2, 3]
    for v in vs:
        counts = v.params["X.sensors.encoder_counts_per_rev"]
        assert counts == int(counts) and 1000 <= counts <= 20000
        assert v.params["X.servo.K_pp"] != int(v.params["X.servo.K_pp"])  # not rounded
        apply_parameters(vmc, v.params)
    with pytest.raises(InputError, match="no whole number"):
        lhs_design([parse_param("X.servo.delay_samples=1.2:1.8")], 2)


def test_a_folder_of_another_study_says_what_differs(tmp_path):
    """Only the design changed (grid to draws, whose machines are drawn with floors), or
    only the sensor, and the refusal said 'model, program or sensor differ'."""
    from tcpmm.whatif.spread import MODEL_ERROR
    from tcpmm.whatif.sweep import CircleProgram
    from tcpmm.whatif.sweep.store import open_study, study_record

    vmc, circle = read_machine("builtin:vmc"), CircleProgram(5e-3, 0.1)
    open_study(tmp_path, study_record(vmc, circle, "tcp"))
    with pytest.raises(InputError, match=r"what differs: draws' floors: none .* there, the "
                                         r"model error's floors \(draws without --fit-only\) "
                                         "here") as err:
        open_study(tmp_path, study_record(vmc, circle, "tcp", MODEL_ERROR))
    assert "model:" not in str(err.value) and "sensor:" not in str(err.value)
    with pytest.raises(InputError, match=r"what differs: sensor: tcp there, scale here\)"):
        open_study(tmp_path, study_record(vmc, circle, "scale"))
    stiff = apply_parameters(vmc, {"X.servo.K_pp": 50.0})
    with pytest.raises(InputError, match="what differs: model: ") as err:
        open_study(tmp_path, study_record(stiff, CircleProgram(6e-3, 0.1), "tcp"))
    assert '"radius_mm": 5.0' in str(err.value) and '"radius_mm": 6.0' in str(err.value)


def test_a_stopped_sweep_leaves_no_summary_of_another_design(tmp_path):
    """A design stopped part way left the summary.csv of the design before it, whole and
    unmarked, beside rows of its own."""
    from tcpmm.whatif.sweep import CircleProgram, evaluate_variant, grid_design, run_sweep

    vmc, circle = read_machine("builtin:vmc"), CircleProgram(5e-3, 0.1)
    first = grid_design([parse_param("X.servo.K_pp=30,40")])
    run_sweep(vmc, circle, first, tmp_path, workers=1)
    assert (tmp_path / "summary.csv").is_file()

    def stopped(machine, program, variant, *rest):
        if variant.params["X.servo.K_pp"] > 50:
            raise KeyboardInterrupt
        return evaluate_variant(machine, program, variant, *rest)

    with pytest.raises(KeyboardInterrupt):
        run_sweep(vmc, circle, grid_design([parse_param("X.servo.K_pp=45,55")]), tmp_path,
                  workers=1, task=stopped)
    assert not (tmp_path / "summary.csv").exists()
    run_sweep(vmc, circle, first, tmp_path, workers=1)  # all there: its summary again
    assert len((tmp_path / "summary.csv").read_text().splitlines()) == 3


def test_an_interpolation_parameter_without_effect_is_said(capsys, tmp_path):
    """filter_time_s under the model's filter_kind none (and the jerk under a trapezoid
    profile) was swept in silence: every row the same."""
    from tcpmm.whatif.sweep.space import idle_parameters

    vmc = read_machine("builtin:vmc")
    names = ["interpolation.filter_time_s", "interpolation.path_jerk_m_per_s3",
             "interpolation.path_accel_m_per_s2"]
    said = idle_parameters(vmc, names)
    assert len(said) == 2 and "filter_kind is none" in said[0] and "profile" in said[1]
    acting = vmc.model_copy(update={"interpolation": {**(vmc.interpolation or {}),
                                                      "filter_kind": "linear",
                                                      "profile": "scurve"}})
    assert idle_parameters(acting, names) == []
    prog = tmp_path / "sq.nc"
    prog.write_text("G21 G90 G17\nG1 X1 Y0 F3000\nG1 X1 Y1\nM30\n")
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--gcode", prog, "-p",
                           "interpolation.filter_time_s=0.01", "-o", tmp_path / "o",
                           "--workers", 1)
    assert code == 0 and "interpolation.filter_time_s has no effect" in " ".join(err.split())


def test_a_centre_with_an_nc_program_is_refused(capsys, tmp_path):
    """--centre with --gcode was taken and did nothing: a program's contour error is
    measured along its own path."""
    prog = tmp_path / "sq.nc"
    prog.write_text("G21 G90 G17\nG1 X1 Y0 F3000\nG1 X1 Y1\nM30\n")
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--gcode", prog, "--centre", "1,2",
                           "-p", "X.servo.position_gain=30", "-o", tmp_path / "o")
    assert code == 2 and "--centre is the circle's" in " ".join(err.split())
    assert not (tmp_path / "o").exists()
