"""What-if sweeps: names, designs, a variant's row, and the runs that must lose nothing."""

import functools
import json
import os

import numpy as np
import pandas as pd
import pytest

from tcpmm.cli import main
from tcpmm.errors import InputError
from tcpmm.model import AxisUncertainty
from tcpmm.whatif.sweep import (
    CircleProgram,
    GcodeProgram,
    Variant,
    apply_parameters,
    canonical_name,
    draws_design,
    evaluate_variant,
    grid_design,
    latin_hypercube,
    lhs_design,
    parse_param,
    path_distance,
    path_metrics,
    read_results,
    run_sweep,
)

#: A short circle: 5 mm at 6000 mm/min, CCW then CW.
SHORT = CircleProgram(radius_m=5e-3, feed_m_per_s=0.1)


def specs(machine, *texts, program="circle"):
    return [parse_param(t, lambda n: canonical_name(machine, n, program)) for t in texts]


def table(out):
    return read_results(out).sort_values("variant").reset_index(drop=True)


@pytest.fixture(scope="module")
def design(vmc):
    return grid_design(specs(vmc, "X.servo.position_gain=30:50:10",
                             "Y.mechanics.M_t=300,400"))


@pytest.fixture(scope="module")
def serial(vmc, design, tmp_path_factory):
    out = tmp_path_factory.mktemp("serial")
    return run_sweep(vmc, SHORT, design, out, workers=1)


@pytest.fixture(scope="module")
def client():
    from distributed import Client

    from tcpmm.whatif.sweep import local_cluster

    with local_cluster(2) as cluster, Client(cluster) as c:
        yield c


def test_names_are_checked_against_the_model_and_aliases_resolve(vmc):
    assert canonical_name(vmc, "x.servo.position_gain") == "X.servo.K_pp"
    assert canonical_name(vmc, "Y.friction.screw.fc_pos") == "Y.friction.screw.fc_pos"
    with pytest.raises(InputError, match=r"did you mean 'servo'.*mechanics, servo"):
        canonical_name(vmc, "X.servoo.K_pp")
    with pytest.raises(InputError, match=r"no such axis.*X.GROUP.FIELD"):
        canonical_name(vmc, "W.servo.K_pp")
    with pytest.raises(InputError, match=r"program\.feed_override"):
        canonical_name(vmc, "program.radius_mm", "gcode")
    m = apply_parameters(vmc, {"X.servo.K_pp": 25.0, "Y.mechanics.M_t": 420.0,
                               "X.friction.level": 2.0, "Z.friction.backlash": 3e-6})
    assert m.axes["X"].servo.K_pp == 25.0 and m.axes["Y"].mechanics.M_t == 420.0
    assert m.axes["X"].friction.screw.fc_pos == 2 * vmc.axes["X"].friction.screw.fc_pos
    assert m.axes["Z"].friction.backlash == 3e-6
    with pytest.raises(InputError, match="K_pp = -1"):
        apply_parameters(vmc, {"X.servo.K_pp": -1.0})


def test_designs(vmc):
    g = grid_design(specs(vmc, "X.servo.K_pp=20:60:5", "Y.servo.K_pp=1,2"))
    assert len(g) == 18 and g[-1].params == {"X.servo.K_pp": 60.0, "Y.servo.K_pp": 2.0}
    assert len({v.id for v in g}) == 18
    u = latin_hypercube(10, 3, seed=4)
    for col in u.T:  # one point in each tenth
        assert sorted(np.floor(col * 10).astype(int)) == list(range(10))
    a, b = (lhs_design(specs(vmc, "X.servo.K_pp=20:60", "X.servo.k_ff=0.5"), 10, 7)
            for _ in range(2))
    assert [v.id for v in a] == [v.id for v in b]
    assert all(20 <= v.params["X.servo.K_pp"] <= 60 and v.params["X.servo.k_ff"] == 0.5
               for v in a)
    d = draws_design(specs(vmc, "X.servo.K_pp=30,40"), 3, seed=1)
    assert [(v.params["X.servo.K_pp"], v.draw) for v in d][:4] == [
        (30.0, 0), (30.0, 1), (30.0, 2), (40.0, 0)]
    with pytest.raises(InputError, match="NAME=START:STOP:STEP"):
        parse_param("X.servo.K_pp")
    with pytest.raises(InputError, match="lhs"):
        grid_design(specs(vmc, "X.servo.K_pp=20:60"))


def test_a_variant_gives_the_circle_metrics_in_metres(vmc, design):
    row = evaluate_variant(vmc, SHORT, design[0])
    assert row["variant"] == design[0].id and row["error"] == ""
    assert 1e-6 < row["ccw_contour_error"] < 1e-3
    assert row["spike_max"] == max(abs(row[f"{d}_spike_{q}"]) for d in ("ccw", "cw")
                                   for q in "ABCD")
    bad = evaluate_variant(vmc, SHORT, Variant((("X.servo.K_pp", -1.0),)))
    assert "K_pp" in bad["error"] and np.isnan(bad["spike_max"])


def test_path_distance_is_the_distance_to_the_polyline():
    ref = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    pts = np.array([[0.5, 0.2], [1.3, 0.5], [2.0, 2.0], [0.0, 0.0]])
    assert path_distance(ref, pts) == pytest.approx([0.2, 0.3, np.hypot(1, 1), 0.0])


@pytest.mark.parametrize("program", [
    "G21 G90 G17\nG0 X0 Y0\nG64\nG1 X50 F3000\nY50\nX0\nY0\nG4 P0.5\nM30\n",
    "G21 G90 G17\nG0 X40 Y30\nG1 X0 Y30 F3000\nG1 X0 Y0\nG4 P0.3\nM30\n"],
    ids=["square", "after-a-rapid"])
def test_a_programs_contour_error_is_tcpmm_contours(vmc, program):
    """A sweep over one program measured each sample against the nearest point anywhere on
    the path, ``tcpmm contour`` and a study over programs against the command within 0.2 s
    of it: the same square under G64 read 5.68 um RMS in one and 5.88 um in the others.
    It counted a G0 rapid's samples, which they leave out: 6.954 um RMS against 6.985."""
    import warnings

    from tcpmm.analysis.contour import contour_error
    from tcpmm.path import program_to_command
    from tcpmm.sim.simulate import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run = simulate(vmc, program_to_command(program))
    ours = path_metrics(run, ["X", "Y"])
    theirs = contour_error(run, plane="XY").summary()["tcp"]
    assert ours["contour_error_rms"] == pytest.approx(theirs["rms_m"], rel=1e-9)
    assert ours["contour_error"] == pytest.approx(theirs["max_abs_m"], rel=1e-9)


def test_nc_program_contour_error_with_feed_override(vmc, tmp_path):
    prog = GcodeProgram("G21 G17 G90\nG1 X5 Y0 F3000\nG1 X5 Y5\nG1 X0 Y5\nG1 X0 Y0\n", "sq")
    vs = grid_design(specs(vmc, "program.feed_override=0.5,1", program="gcode"))
    res = run_sweep(vmc, prog, vs, tmp_path / "o", workers=1, keep_runs=tmp_path / "runs")
    t = res.to_pandas()
    assert list(t["program.feed_override"]) == [0.5, 1.0]
    assert (t["contour_error_um"] > t["contour_error_rms_um"]).all()
    assert t["contour_error_um"][0] < t["contour_error_um"][1]  # slower is closer
    key = json.loads((tmp_path / "o" / "study.json").read_text())["key"]
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == sorted(
        f"{v.id}-{key[:12]}.csv" for v in vs)


def test_studies_sharing_a_runs_folder_keep_their_runs_apart(vmc, tmp_path):
    """Two models with the same variant shared one run file name: the second study
    overwrote the first's run, and the first, run again, took it as its own."""
    stiff = apply_parameters(vmc, {"X.mechanics.K_h": 4 * vmc.axes["X"].mechanics.K_h})
    runs = tmp_path / "runs"
    for m, out in ((vmc, "a"), (stiff, "b")):
        vs = grid_design(specs(m, "X.servo.K_pp=30"))
        run_sweep(m, SHORT, vs, tmp_path / out, workers=1, keep_runs=runs)
    assert len(list(runs.glob("*.csv"))) == 2
    again = run_sweep(vmc, SHORT, vs, tmp_path / "a", workers=1, keep_runs=runs)
    assert (again.computed, again.reused) == (0, 1)


def test_a_local_cluster_gives_the_serial_rows(vmc, design, serial, client, tmp_path):
    res = run_sweep(vmc, SHORT, design, tmp_path, client=client)
    assert (res.computed, res.failed) == (len(design), [])
    pd.testing.assert_frame_equal(table(tmp_path), table(serial.out_dir))
    pd.testing.assert_frame_equal(res.to_pandas(), serial.to_pandas())


def _dies_once(marker, victim, machine, program, variant, *rest):
    """The task, except that its worker process dies the first time it runs ``victim``."""
    if variant.id == victim and not os.path.exists(marker):
        open(marker, "w").close()
        os._exit(1)
    return evaluate_variant(machine, program, variant, *rest)


def test_a_worker_that_dies_costs_no_variant(vmc, design, serial, client, tmp_path):
    marker = tmp_path / "died"
    task = functools.partial(_dies_once, str(marker), design[2].id)
    res = run_sweep(vmc, SHORT, design, tmp_path / "o", client=client, task=task)
    assert marker.exists()
    assert (res.computed, res.failed) == (len(design), [])
    pd.testing.assert_frame_equal(table(tmp_path / "o"), table(serial.out_dir))


def test_model_lost_with_the_only_worker_holding_it_is_scattered_again(vmc, design, serial,
                                                                        tmp_path):
    """With one worker, the model scattered to it dies with it; the scheduler cannot run
    scattered data again, so the sweep scatters it anew to the restarted worker."""
    from distributed import Client

    from tcpmm.whatif.sweep import local_cluster

    marker = tmp_path / "died"
    task = functools.partial(_dies_once, str(marker), design[2].id)
    with local_cluster(1) as cluster, Client(cluster) as one:
        res = run_sweep(vmc, SHORT, design, tmp_path / "o", client=one, task=task)
    assert marker.exists()
    assert (res.computed, res.failed) == (len(design), [])
    pd.testing.assert_frame_equal(table(tmp_path / "o"), table(serial.out_dir))


def _raises_for(victim, machine, program, variant, *rest):
    """The task, except that it raises for ``victim``."""
    if variant.id == victim:
        raise ValueError("no such gain")
    return evaluate_variant(machine, program, variant, *rest)


def test_a_variant_that_raises_is_named_and_its_task_mates_land(vmc, design, serial, client,
                                                                tmp_path):
    """Variants travel in tasks of several: one that raises is reported with its error,
    and the variants that share its task are not lost."""
    task = functools.partial(_raises_for, design[1].id)
    res = run_sweep(vmc, SHORT, design, tmp_path, client=client, task=task)
    assert res.failed == [{"variant": design[1].id, "reason": "ValueError: no such gain"}]
    assert res.computed == len(design) - 1
    want = table(serial.out_dir)
    want = want[want["variant"] != design[1].id].reset_index(drop=True)
    pd.testing.assert_frame_equal(table(tmp_path), want)


def test_a_stopped_sweep_resumes_with_the_missing_variants(vmc, design, serial, tmp_path):
    def stop(done, total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(vmc, SHORT, design, tmp_path, workers=1, progress=stop)
    kept = set(read_results(tmp_path)["variant"])
    assert len(kept) == 2  # what was computed is kept
    seen = []
    res = run_sweep(vmc, SHORT, design, tmp_path, workers=1,
                    task=lambda m, p, v, *a: seen.append(v.id) or evaluate_variant(m, p, v, *a))
    assert (res.computed, res.reused) == (len(design) - 2, 2)
    assert sorted(seen) == sorted({v.id for v in design} - kept)
    pd.testing.assert_frame_equal(table(tmp_path), table(serial.out_dir))
    pd.testing.assert_frame_equal(res.to_pandas(), serial.to_pandas())


def test_the_first_row_is_on_disk_at_once(tmp_path):
    """A sweep whose rows take seconds each wrote its first part only after ten seconds
    or a full batch: a run killed before that (a node lost, the power cut) kept nothing,
    and the folder stayed empty while it ran."""
    from tcpmm.whatif.sweep.store import PartWriter, part_files

    w = PartWriter(tmp_path, batch=64, seconds=3600.0)
    w.add({"variant": 0, "value": 1.0})
    assert len(part_files(tmp_path)) == 1 and w.written == 1
    w.add({"variant": 1, "value": 2.0})  # then in batches again
    assert len(part_files(tmp_path)) == 1 and w.rows


def test_a_folder_another_sweep_is_writing_into_is_refused(vmc, design, serial):
    """Two sweeps into one folder at once would both compute and write the variants
    missing there: the second is refused while the first runs, and runs after it."""
    from tcpmm.whatif.sweep.store import writing

    with writing(serial.out_dir), pytest.raises(InputError, match="another sweep"):
        run_sweep(vmc, SHORT, design, serial.out_dir, workers=1)
    res = run_sweep(vmc, SHORT, design, serial.out_dir, workers=1)
    assert (res.computed, res.reused) == (0, len(design))


def test_another_study_in_the_same_folder_is_refused(vmc, design, serial):
    other = CircleProgram(radius_m=6e-3, feed_m_per_s=0.1)
    with pytest.raises(InputError, match="another study"):
        run_sweep(vmc, other, design, serial.out_dir, workers=1)


def test_draws_need_an_identified_model_and_repeat_by_seed(vmc, tmp_path):
    with pytest.raises(InputError, match="no uncertainty"):
        run_sweep(vmc, SHORT, draws_design([], 2), tmp_path, workers=1)
    m = vmc.model_copy(update={"axes": {n: a.replace(uncertainty=AxisUncertainty(
        mechanics={"M_t": 0.05 * a.mechanics.M_t})) for n, a in vmc.axes.items()}})
    v = draws_design([], 2, seed=3)
    rows = [evaluate_variant(m, SHORT, x) for x in (v[0], v[1], v[0])]
    assert rows[0] == rows[2] and rows[0]["spike_max"] != rows[1]["spike_max"]


def test_cli(tmp_path, capsys):
    args = ["sweep", "builtin:vmc", "-p", "X.servo.position_gain=30,40", "--circle", "5,6000",
            "-o", str(tmp_path / "o"), "--workers", "1", "--json"]
    assert main(args) == 0
    got = json.loads(capsys.readouterr().out)
    assert (got["variants"], got["computed"], got["failed"]) == (2, 2, [])
    assert main(args) == 0
    assert json.loads(capsys.readouterr().out)["reused"] == 2
    summary = pd.read_csv(tmp_path / "o" / "summary.csv")
    assert list(summary["X.servo.K_pp"]) == [30.0, 40.0]
    assert main(["sweep", "builtin:vmc", "-p", "X.servo.nope=1", "-o", str(tmp_path)]) == 2
    assert "no such field of X.servo" in capsys.readouterr().err.replace("\n", " ")
    assert main(["sweep", "builtin:vmc", "--list-params"]) == 0
    assert "X.servo.K_pp" in capsys.readouterr().out


def test_a_programs_errors_name_its_file(vmc):
    """A sweep's program was interpreted from its text alone: its errors named a line but
    no file."""
    from tcpmm.whatif.sweep.task import program_command

    for text in ("G21 G90\nG1 X10 F0.0000001\nM30\n", "G21 G90\nG1 X10 F1000 G2\nM30\n"):
        with pytest.raises(InputError) as e:
            program_command(GcodeProgram(text, "prog.nc"), vmc, {})
        assert (e.value.file, e.value.line) == ("prog.nc", 2)


def test_a_refused_sweep_prints_its_error_alone(tmp_path, capsys):
    """The progress bar's end left a blank line on stderr, before the error too, where
    stderr is no terminal (a log, a pipe)."""
    prog = tmp_path / "bad.nc"
    prog.write_text("G21 G90\nG1 X10 F1000 G2\nM30\n")
    args = ["sweep", "builtin:vmc", "--gcode", str(prog), "-p", "X.servo.position_gain=20,30",
            "-o", str(tmp_path / "o"), "--workers", "1"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"error: {prog}, line 2, column 14: ")
    assert not (tmp_path / "o").exists()


def test_a_faulted_variant_is_said_with_json_too(tmp_path, capsys):
    """A variant whose current stays at its limit (X.servo.K_vp=10) was said on stderr
    without --json and not at all with it: the JSON held no fault, stderr was empty."""
    args = ["sweep", "builtin:vmc", "-p", "X.servo.K_vp=10", "--circle", "5,6000",
            "-o", str(tmp_path / "o"), "--workers", "1"]
    for more in ((), ("--json",)):
        assert main([*args, *more]) == 0
        err = " ".join(capsys.readouterr().err.split())
        assert "warning: variant" in err and "current at the limit" in err, more
    # and its figures, of a machine at its limit, are not given beside the fault
    import pandas as pd

    row = pd.read_csv(tmp_path / "o" / "summary.csv").iloc[0]
    assert isinstance(row["fault"], str) and row["fault"]
    assert all(pd.isna(row[c]) for c in row.index if c.endswith("_um"))


def test_a_feed_the_circle_cannot_reach_is_said(tmp_path, capsys):
    """program.feed_mm_per_min 50000 and 1e6 gave the same rows (the interpolator's
    1 m/s2 holds the R35 circle at 11 225 mm/min) under the feed asked, with no word."""
    from tcpmm.cli import main

    assert main(["sweep", "builtin:vmc", "--param", "program.feed_mm_per_min=5000,50000",
                 "-o", str(tmp_path / "a")]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert "the circle's feed 50000 mm/min at R35 mm runs at 11225 mm/min" in err
    assert "feed 5000 " not in err
    assert main(["sweep", "builtin:vmc", "--param", "program.feed_mm_per_min=5000,8000",
                 "-o", str(tmp_path / "b")]) == 0
    assert "runs at" not in capsys.readouterr().err


def test_every_row_holds_the_programs_warnings_however_the_commands_were_built(vmc, tmp_path):
    """A program with a zero-length move, swept over two feed overrides: the sweep's own
    check built both commands first, in this process, and the rows of one worker then
    held no warning, while those of two workers (other processes) held it: the table
    depended on the number of workers."""
    prog = GcodeProgram("G21 G17 G90\nG1 X5 Y0 F3000\nG1 X5 Y0\nG1 X5 Y5\n", "zero.nc")
    design = grid_design(specs(vmc, "program.feed_override=0.5,1", program="gcode"))
    from tcpmm.errors import InputWarning

    with pytest.warns(InputWarning, match="zero-length"):  # the check says it once
        rows = run_sweep(vmc, prog, design, tmp_path / "o", workers=1).to_pandas()
    assert len(rows) == 2
    assert all("zero.nc, line 3" in w and "zero-length" in w for w in rows["warning"]), rows


def test_a_variant_whose_command_fails_keeps_the_programs_warnings(vmc):
    """The row of a variant whose program cannot be interpolated holds its error and what
    the program said before it failed (a zero-length move): the failed build is not
    cached, and what it said went with it."""
    prog = GcodeProgram("G21 G17 G90\nG1 X5 Y0 F3000\nG1 X5 Y0\nG1 X5 Y5\n", "zero.nc")
    variant = Variant(values=(("program.feed_override", 1e-7),))
    row = evaluate_variant(vmc, prog, variant, "tcp")
    assert "would last" in row["error"], row
    assert "zero.nc, line 3" in row["warning"] and "zero-length" in row["warning"], row


def _log_an_error() -> None:
    import logging

    logging.getLogger("distributed.worker").error("heartbeat to the scheduler failed")


def test_a_workers_transport_errors_stay_off_the_terminal(capfd):
    """A terminal's Ctrl-C stops the sweep's scheduler while a worker's heartbeat is in
    flight, and the worker logged "Failed to communicate with scheduler during heartbeat"
    with its traceback onto the terminal (at a load of 3, one stop in eight). The sweep
    says itself what it computed and what failed; the workers' own logs stay off."""
    from distributed import Client

    from tcpmm.whatif.sweep import local_cluster

    with local_cluster(1) as cluster, Client(cluster) as c:
        c.run(_log_an_error)
    assert "heartbeat to the scheduler failed" not in capfd.readouterr().err


def test_an_unstable_loop_is_a_fault_and_a_word_in_a_warning_is_not(vmc):
    """A variant was taken as out of control where its warning held the word 'unstable':
    the unstable loop's warning, but also any other that used the word. The unstable
    loop's warning is a run fault (UnstableLoopWarning), held in the row's fault; another
    warning leaves the row's figures as they are."""
    from tcpmm.whatif.sweep.task import out_of_control

    row = evaluate_variant(vmc, SHORT, Variant((("X.servo.K_pp", 2000.0),)))
    assert "axis X: the sampled servo loop is unstable" in row["fault"]
    assert "unstable" not in row["warning"] and np.isnan(row["spike_max"])
    said = {"warning": "a mode the model may have unstable damping", "fault": ""}
    assert out_of_control(row) and not out_of_control(said)
