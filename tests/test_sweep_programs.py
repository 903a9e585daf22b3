"""A study over many programs: every (model, NC program) pair one streaming task, here and
on a real Dask scheduler with workers on loopback; each row is what ``tcpmm simulate
--gcode`` and ``tcpmm contour`` give for the pair alone, and a malformed program is a row
naming its line."""

import json
import logging

import pandas as pd
import pytest

from conftest import run_cli
from tcpmm.errors import InputError
from tcpmm.io.modelfile import read_machine, write_machine
from tcpmm.whatif.sweep import apply_parameters
from tcpmm.whatif.sweep.programs import COLUMNS, program_files, program_task, run_programs

#: a square with a repeated point and a first move to where the tool stands: two
#: zero-length moves skipped
SQUARE = ("G90 G17 G21\nG1 X0 Y0 F3000\nG1 X10 Y0\nG1 X10 Y0\nG1 X10 Y10\nG1 X0 Y10\n"
          "G1 X0 Y0\nM30\n")
ARC = "G90 G21\nG1 X5 F2000\nG2 X10 Y5 I0 J5\nG1 Y0\nM30\n"
#: line 3 has a letter without its number
BAD = "G90 G21\nG1 X5 F2000\nG1 X5 Y QQ\nM30\n"


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Three programs (one malformed) in a folder, a note that is no program beside them,
    and two models: the built-in one and a copy with a softer position loop."""
    root = tmp_path_factory.mktemp("study")
    progs = root / "progs"
    progs.mkdir()
    for name, text in (("square.nc", SQUARE), ("arc.ngc", ARC), ("bad.nc", BAD),
                       ("notes.txt", "not a program\n")):
        (progs / name).write_text(text)
    soft = root / "soft.yaml"
    vmc = read_machine("builtin:vmc")
    write_machine(apply_parameters(vmc, {"X.servo.K_pp": 20.0, "Y.servo.K_pp": 20.0}), soft)
    return {"root": root, "progs": progs, "models": ["builtin:vmc", str(soft)]}


@pytest.fixture(scope="module")
def serial(study):
    models = {m: read_machine(m) for m in study["models"]}
    import warnings

    with warnings.catch_warnings():
        # the tasks count the interpreter's warnings into their rows, not pass them on
        warnings.simplefilter("error")
        return run_programs(models, program_files(study["progs"]), study["root"] / "serial",
                            chunk_blocks=2)


def test_program_files(study, tmp_path):
    names = [p.name for p in program_files(study["progs"])]
    assert names == ["arc.ngc", "bad.nc", "square.nc"]  # sorted; notes.txt is no program
    assert [p.name for p in program_files(study["progs"] / "*.nc")] == ["bad.nc", "square.nc"]
    with pytest.raises(InputError, match="no NC program found"):
        program_files(tmp_path)
    (tmp_path / "a" / "b").mkdir(parents=True)
    (tmp_path / "a" / "b" / "deep.nc").write_text(SQUARE)
    assert [p.name for p in program_files(tmp_path / "**" / "*.nc")] == ["deep.nc"]
    with pytest.raises(InputError, match="no such folder"):
        program_files(tmp_path / "missing")


def _direct(capsys, model, program, tmp_path):
    """The pair through ``tcpmm simulate --gcode`` and ``tcpmm contour`` [-]."""
    run = tmp_path / "run.parquet"
    code, out, _ = run_cli(capsys, "simulate", model, "--gcode", program, "-o", run, "--json")
    assert code == 0
    sim = json.loads(out)
    code, out, _ = run_cli(capsys, "contour", run, "--json")
    assert code == 0
    return sim, json.loads(out)


def test_rows_are_the_single_program_results(study, serial, capsys, tmp_path):
    rows = {(r["model"], r["program"].rsplit("/", 1)[-1]): r for r in serial.rows}
    assert len(rows) == 6
    for model in study["models"]:
        for name, lines in (("square.nc", 8), ("arc.ngc", 5)):
            row = rows[model, name]
            sim, con = _direct(capsys, model, study["progs"] / name, tmp_path)
            assert row["status"] == "ok" and row["error"] is None
            assert row["blocks"] == lines
            assert row["samples"] == sim["samples"]
            assert row["duration_s"] == sim["duration_s"]
            assert row["plane"] == con["axes"] == "XY"
            tcp = con["sensors"]["tcp"]
            # the streamed RMS sums the squares chunk by chunk (a relative 1e-12)
            assert row["contour_rms_um"] == pytest.approx(tcp["rms_um"], rel=1e-10)
            assert row["contour_max_um"] == tcp["max_abs_um"]
            assert row["task_s"] > 0
            # the corners are the turns: the path's end, a row of contour's table, is none
            turns = [c for c in con["corners"] if c["sensor"] == "tcp"
                     and c["turn_deg"] is not None]
            assert row["corners"] == (len(turns) or None)
    assert rows["builtin:vmc", "square.nc"]["zero_length_skipped"] == 2
    assert rows["builtin:vmc", "arc.ngc"]["zero_length_skipped"] == 0
    # the softer position loop follows the square further off
    soft, stiff = (rows[m, "square.nc"]["contour_max_um"] for m in study["models"][::-1])
    assert soft > 1.5 * stiff


def test_a_malformed_program_is_a_row_naming_its_line(study, serial):
    bad = [r for r in serial.rows if r["program"].endswith("bad.nc")]
    assert [r["model"] for r in bad] == study["models"]
    for r in bad:
        assert r["status"] == "failed"
        assert r["error_line"] == 3 and r["error_file"].endswith("bad.nc")
        assert "bad.nc, line 3, column 7" in r["error"] and "letter Y" in r["error"]
        assert r["contour_rms_um"] is None
    assert len(serial.failed) == 2
    from tcpmm.whatif.sweep.programs import _failure

    # a cluster's error of several lines (advice after the first) is a row of one line
    lost = _failure(RuntimeError("Error during deserialization\nFor more information"))
    assert lost == {"error": "RuntimeError: Error during deserialization",
                    "error_file": None, "error_line": None}


def test_the_table_files(serial):
    csv = pd.read_csv(serial.files["csv"])
    par = pd.read_parquet(serial.files["parquet"])
    js = json.loads(serial.files["json"].read_text())
    assert list(csv.columns) == list(par.columns) == list(COLUMNS)
    assert len(csv) == len(par) == len(js) == 6
    assert list(par["error_line"].dropna()) == [3, 3]
    nan = float("nan")
    assert csv["contour_rms_um"].tolist() == pytest.approx(
        [nan if r["contour_rms_um"] is None else r["contour_rms_um"] for r in serial.rows],
        rel=1e-15, nan_ok=True)
    assert not list(serial.files["csv"].parent.glob("*.tmp*"))


@pytest.fixture(scope="module")
def loopback():
    """A real scheduler and two workers on 127.0.0.1 over TCP, on ports the system gives
    (threads of this process: a loaded two-core machine starts them in a second). Its
    HTTP server too: without an address it takes 8787, and warns where another process
    holds that."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=False, protocol="tcp://",
                      host="127.0.0.1", dashboard_address="127.0.0.1:0",
                      silence_logs=logging.ERROR) as cluster:
        yield cluster.scheduler_address


def _same(a: dict, b: dict) -> bool:
    """Rows equal but for the time a task took [-]."""
    return ({k: v for k, v in a.items() if k != "task_s"}
            == {k: v for k, v in b.items() if k != "task_s"})


def test_cli_on_a_cluster_on_loopback(study, serial, loopback, capsys, tmp_path):
    assert loopback.startswith("tcp://127.0.0.1:")
    code, out, _ = run_cli(capsys, "sweep", *study["models"], "--programs", study["progs"],
                        "--scheduler", loopback, "--chunk-blocks", 3, "-o", tmp_path,
                        "--json")
    assert code == 1  # the malformed program's rows; the others ran
    got = json.loads(out)
    assert got["pairs"] == 6 and got["failed"] == 2
    assert len(got["rows"]) == len(serial.rows)
    for a, b in zip(got["rows"], serial.rows, strict=True):
        assert _same(a, b), {k: (a[k], b[k]) for k in a if a[k] != b[k]}
    assert (tmp_path / "programs.parquet").is_file()


def test_cli_text_report_and_refusals(study, capsys, tmp_path):
    code, out, err = run_cli(capsys, "sweep", "builtin:vmc", "--programs",
                          study["progs"] / "square.nc", "--workers", 1, "-o", tmp_path)
    assert code == 0 and "1 (model, program) pairs: 1 ran, 0 failed" in out
    assert "programs.csv" in out
    code, _, err = run_cli(capsys, "sweep", *study["models"], "-p", "X.servo.K_pp=20,30",
                        "-o", tmp_path)
    assert code == 2 and "takes one model" in err.replace("\n", " ")
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--programs", study["progs"],
                        "-p", "X.servo.K_pp=20,30", "-o", tmp_path)
    assert code == 2 and "--param" in err
    code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--programs", tmp_path / "none",
                        "-o", tmp_path)
    assert code == 2 and "no such folder" in err.replace("\n", " ")


def test_tasks_in_threads_count_their_own_warnings(study):
    """A Dask worker runs tasks in threads: each counts the zero-length moves of its own
    program, however the threads interleave."""
    from concurrent.futures import ThreadPoolExecutor

    vmc = read_machine("builtin:vmc")
    progs = [study["progs"] / ("square.nc" if k % 2 else "arc.ngc") for k in range(8)]
    with ThreadPoolExecutor(4) as pool:
        rows = list(pool.map(lambda p: program_task("vmc", vmc, p, 1), progs))
    assert [r["zero_length_skipped"] for r in rows] == [0, 2] * 4
    assert all(r["status"] == "ok" and r["warnings"] == "" for r in rows)


def test_workers_get_the_programs_by_a_path_that_leads_from_anywhere(study, loopback,
                                                                     capsys, tmp_path,
                                                                     monkeypatch):
    """A folder given relative to where the command runs went to the workers as given:
    from a worker started in another folder, every program was 'not found'. The tasks
    get absolute paths; the rows name the programs as the user gave them."""
    from tcpmm.whatif.sweep import programs as module

    real, seen = module.program_task, tmp_path / "seen.txt"

    def task(name, machine, prog, *args):  # sent to the workers by value: a file is shared
        with open(seen, "a") as f:
            f.write(f"{prog}\n")
        return real(name, machine, prog, *args)

    monkeypatch.setattr(module, "program_task", task)
    monkeypatch.chdir(study["root"])
    code, out, _ = run_cli(capsys, "sweep", "builtin:vmc", "--programs", "progs", "--scheduler",
                        loopback, "-o", tmp_path / "out", "--json")
    paths = seen.read_text().split()
    assert code == 1 and len(paths) == 3 and all(p.startswith("/") for p in paths)
    assert sorted(r["program"] for r in json.loads(out)["rows"]) == [
        "progs/arc.ngc", "progs/bad.nc", "progs/square.nc"]


def test_the_column_counts_rapids_to_where_the_tool_stands(tmp_path):
    """Two G0 to where the tool stood went uncounted: ``zero_length_skipped`` said 1 of 3,
    and nothing else of them."""
    prog = tmp_path / "rep.nc"
    prog.write_text("G21 G90 G17\nG1 X1 Y0 F3000\nX2\nG0 X2\nG0 X2\nG1 X3\nX3\nM30\n")
    row = program_task("vmc", read_machine("builtin:vmc"), prog, 2)
    assert row["status"] == "ok" and row["zero_length_skipped"] == 3 and row["warnings"] == ""


#: two squares in XY at Z0, the tool lifted and lowered by G0 between them
LIFTED = ("G21 G90 G17\nG0 X10 Y0 Z0\nG1 X20 Y0 F3000\nG1 X20 Y10\nG1 X10 Y10\n"
          "G1 X10 Y0\nG0 Z20\nG0 X40 Y0\nG0 Z0\nG1 X50 Y0\nG1 X50 Y10\nG1 X40 Y10\n"
          "G1 X40 Y0\nG4 P0.5\nM30\n")


def test_the_plane_is_that_of_the_feed_moves_as_contour_takes_it(capsys, tmp_path):
    """The G0 lift between two squares moves Z: ``tcpmm contour`` takes the plane from the
    feed moves, XY, as it leaves the rapids out of the error, but the row took it from
    the whole travel and measured in 3-D, unsigned: another RMS and largest error
    (11.9 and 63.1 um against 10.5 and 57.5 um)."""
    prog = tmp_path / "lifted.nc"
    prog.write_text(LIFTED)
    row = program_task("builtin:vmc", read_machine("builtin:vmc"), prog, 3)
    _, con = _direct(capsys, "builtin:vmc", prog, tmp_path)
    assert row["status"] == "ok" and row["plane"] == con["axes"] == "XY"
    tcp = con["sensors"]["tcp"]
    # the streamed RMS sums the squares chunk by chunk (a relative 1e-12)
    assert row["contour_rms_um"] == pytest.approx(tcp["rms_um"], rel=1e-10)
    assert row["contour_max_um"] == tcp["max_abs_um"]


def test_an_unstable_machine_is_a_fault_without_figures(study, capsys, tmp_path):
    """A model whose sampled X loop is unstable (K_pp 1000) gave status ok with contour
    figures, the instability among the warnings; a sweep of variants puts it in its faults
    and leaves the figures out, and so does the study of programs."""
    model = tmp_path / "unstable.yaml"
    write_machine(apply_parameters(read_machine("builtin:vmc"), {"X.servo.K_pp": 1000.0}),
                  model)
    code, out, err = run_cli(capsys, "sweep", model, "--programs",
                             study["progs"] / "square.nc", "--workers", 1, "-o", tmp_path,
                             "--json")
    assert code == 0
    (row,) = json.loads(out)["rows"]
    assert row["status"] == "fault" and "unstable" in row["faults"]
    assert "unstable" not in (row["warnings"] or "")
    assert row["contour_rms_um"] is None and row["contour_max_um"] is None
    assert "square.nc" in err and "no figures" in err


def test_the_sensor_is_honoured_and_the_variant_options_refused(study, capsys, tmp_path):
    """--sensor, --design, --n, --seed and --centre were taken with --programs and did
    nothing: --sensor scale gave the TCP's figures. The rows are now the sensor's, and the
    options of a sweep of variants are refused."""
    square = study["progs"] / "square.nc"
    _, con = _direct(capsys, "builtin:vmc", square, tmp_path)
    code, out, _ = run_cli(capsys, "sweep", "builtin:vmc", "--programs", square, "--sensor",
                           "scale", "--workers", 1, "-o", tmp_path / "s", "--json")
    (row,) = json.loads(out)["rows"]
    assert code == 0 and row["contour_max_um"] == con["sensors"]["scale"]["max_abs_um"]
    assert row["contour_max_um"] != con["sensors"]["tcp"]["max_abs_um"]
    for given in (["--design", "lhs"], ["--n", 3], ["--seed", 0], ["--centre", "1,1"],
                  ["--fit-only"], ["--sensor", "cmd"]):
        code, _, err = run_cli(capsys, "sweep", "builtin:vmc", "--programs", square, *given,
                               "-o", tmp_path / "r")
        assert code == 2 and given[0] in err, (given, err)


def test_a_failed_row_names_the_program_as_given_on_workers_too(study, loopback, capsys,
                                                                tmp_path, monkeypatch):
    """On workers the error and error_file of a failed pair held the absolute path the
    task was sent, in this process the path as given: the same study gave two tables."""
    monkeypatch.chdir(study["root"])
    code, out, _ = run_cli(capsys, "sweep", "builtin:vmc", "--programs", "progs/bad.nc",
                           "--scheduler", loopback, "-o", tmp_path / "out", "--json")
    (row,) = json.loads(out)["rows"]
    assert code == 1 and row["program"] == row["error_file"] == "progs/bad.nc"
    assert row["error"].startswith("progs/bad.nc, line 3, column 7")


def test_a_pair_refused_past_the_parse_names_its_program(tmp_path):
    """A program that moves Z, on a model of X and Y, is refused once its command is made:
    the row's error named no file ('failed  xy: the command drives axis Z ...' on the
    console), and among many programs the one refused was not said. It names the program,
    as `tcpmm simulate` does."""
    vmc = read_machine("builtin:vmc")
    xy = vmc.model_copy(update={"axes": {a: vmc.axes[a] for a in "XY"}})
    prog = tmp_path / "lift.nc"
    prog.write_text("G21 G90\nG1 X1 F3000\nG1 Z0.5\nM30\n")
    row = program_task("xy", xy, prog, 2)
    assert row["status"] == "failed" and row["error_file"] == str(prog)
    assert row["error"] == f"{prog}: the command drives axis Z that the machine does not " \
                           "have (machine axes: X, Y)"


def test_corners_the_command_cuts_have_no_rounding_as_in_contour(tmp_path, capsys):
    """A model that interpolates every 10 ms: its command's samples cut the square's
    corners by 27 um, and ``tcpmm contour`` gives their rounding as n/a; the row gave a
    largest rounding of 71 um all the same, and would have given 0 for corners n/a."""
    vmc = read_machine("builtin:vmc")
    coarse = vmc.model_copy(update={"interpolation": {**vmc.interpolation, "period_s": 0.01}})
    model, prog = tmp_path / "coarse.yaml", tmp_path / "lifted.nc"
    write_machine(coarse, model)
    prog.write_text(LIFTED)
    row = program_task("coarse", coarse, prog, 3)
    _, con = _direct(capsys, str(model), prog, tmp_path)
    turns = [c for c in con["corners"] if c["sensor"] == "tcp" and c["turn_deg"] is not None]
    assert turns and all(c["rounding_um"] is None for c in turns)
    assert row["status"] == "ok" and row["corners"] == len(turns)
    assert row["corner_rounding_max_um"] is None
