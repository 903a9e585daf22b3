"""The command line refuses outputs that would lose data, before any work is done."""

import json
import os
import stat
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from tcpmm.cli import main
from tcpmm.demo import paper_circle_command
from tcpmm.errors import InputWarning, RunFaultWarning
from tcpmm.io.atomic import write_text_atomic
from tcpmm.io.modelfile import write_machine
from tcpmm.machines.builtin import builtin_machine
from tcpmm.path import write_command_csv
from tcpmm.path.command import Command
from tcpmm.sim.simulate import simulate

PROGRAM = "G21 G90 G17\nG0 X0 Y0\nG1 X10 Y0 F1000\nM30\n"


def run(capsys, *args):
    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, " ".join(cap.out.split()), " ".join(cap.err.split())  # rich wraps lines


@pytest.fixture()
def nc(tmp_path):
    p = tmp_path / "prog.nc"
    p.write_text(PROGRAM)
    return p


def test_output_that_is_an_input_is_refused_and_the_input_kept(capsys, nc):
    code, out, err = run(capsys, "path", nc, "-o", nc)
    assert code == 2 and "is also an input" in out + err
    assert nc.read_text() == PROGRAM


@pytest.mark.parametrize("name", ["cmd.png", "cmd.parquet", "cmd.txt"])
def test_a_command_file_is_named_as_the_csv_it_is(capsys, nc, tmp_path, name):
    """`path -o CMD.parquet` wrote CSV text under that name, which `contour` then refused
    as no Parquet; `-o cmd.png --plot` would have had the plot overwrite the command."""
    code, out, err = run(capsys, "path", nc, "-o", tmp_path / name, "--plot")
    assert code == 2 and "a command file is written as CSV; name it cmd.csv" in out + err
    assert [p.name for p in tmp_path.iterdir()] == ["prog.nc"]


def test_output_folder_or_file_parent_is_a_named_error(capsys, nc, tmp_path):
    (tmp_path / "adir").mkdir()
    code, _, err = run(capsys, "path", nc, "-o", tmp_path / "adir")
    assert code == 2 and "is a folder; give the output a file name" in err
    (tmp_path / "file").write_text("keep")
    code, _, err = run(capsys, "machine", "export", "vmc", "-o", tmp_path / "file" / "m.yaml")
    assert code == 2 and "is a file, so the output folder" in err
    assert (tmp_path / "file").read_text() == "keep"


def test_failed_identify_leaves_the_model_file_alone(capsys, tmp_path):
    model = tmp_path / "model.yaml"
    model.write_text("keep me\n")
    (tmp_path / "report").write_text("a file, not a folder")
    code, _, err = run(capsys, "identify", tmp_path / "no_bundle", "-o", model,
                       "--report", tmp_path / "report")
    assert code == 2 and "output folder" in err
    assert model.read_text() == "keep me\n"


@pytest.mark.parametrize("args, hint", [
    (["--guideway-share", "2"], "--guideway-share"),
    (["--band", "100,10"], "0 <= F0 < F1"),
])
def test_identify_options_out_of_range_are_usage_errors(capsys, tmp_path, args, hint):
    code, out, err = run(capsys, "identify", tmp_path, "-o", tmp_path / "m.yaml", *args)
    assert code == 2 and hint in out + err


def test_plot_extension_is_checked_before_the_analysis(capsys, tmp_path):
    code, _, err = run(capsys, "circle", tmp_path / "missing.csv", "--radius", 35,
                       "--plot", tmp_path / "plot.txt")
    assert code == 2 and "a plot file needs one of the extensions" in err
    assert "missing.csv" not in err  # refused before the run file is read


@pytest.mark.parametrize("args, hint", [
    (["circle", "run.csv", "--radius", "-35"], "--radius [mm] must be a positive number, got -35"),
    (["bode", "builtin:vmc", "--axis", "X", "--tf", "G_M", "--freq-hz", "nan"], "finite"),
    (["excite", "linear", "--band", "1,100", "--amplitude-A", "1", "--duration-s", "1e6",
      "--fs-hz", "1e6", "-o", "e.csv"], "1e+12 samples"),
    (["excite", "linear", "--band", "1,100", "--amplitude-A", "-1", "--duration-s", "1",
      "--fs-hz", "1000", "-o", "e.csv"], "--amplitude-A"),
    (["spread", "builtin:vmc", "--gcode", "p.nc", "--radius", "35", "--sensor", "foo"],
     "'--sensor'"),
])
def test_option_errors_name_the_option(capsys, args, hint):
    code, out, err = run(capsys, *args)
    assert code == 2 and hint in out + " " + err


def test_analysis_error_names_the_run_file(capsys, tmp_path):
    m = builtin_machine("vmc")
    cmd = paper_circle_command()
    write_command_csv(cmd, tmp_path / "cmd.csv")
    simulate(m, cmd).write_csv(tmp_path / "run.csv")
    code, _, err = run(capsys, "circle", tmp_path / "run.csv", "--radius", 20)
    assert code == 2 and "no full circle" in err
    assert err.split("no full circle")[0].rstrip(" :").endswith("run.csv")


def test_input_warnings_print_as_warnings_not_source_lines(capsys, tmp_path):
    p = tmp_path / "spindle.nc"
    p.write_text("G21 G90 G17\nG0 X0 Y0\nM3 S1000\nG1 X10 Y0 F1000\nM30\n")
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        code, _, err = run(capsys, "path", p, "-o", tmp_path / "cmd.csv")
    assert code == 0
    assert "warning: " in err and "spindle" in err
    assert "InputWarning" not in err and ".py:" not in err


def test_unstable_model_simulates_with_a_warning():
    m = builtin_machine("vmc")
    ax = m.axes["X"]
    bad = m.with_axis("X", ax.replace(servo=ax.servo.model_copy(update={"K_pp": 40000.0})))
    t = np.arange(200) * 1e-3
    cmd = Command(t, {"X": 1e-3 * t, "Y": 0 * t})
    with (pytest.warns(InputWarning, match="axis X: the sampled servo loop is unstable"),
          pytest.warns(RunFaultWarning, match="axis X: holds its current at the limit")):
        simulate(bad, cmd)
    with warnings.catch_warnings():
        warnings.simplefilter("error", InputWarning)
        simulate(m, cmd)


def test_atomic_write_keeps_permissions_and_writes_through_links(tmp_path):
    old = os.umask(0o022)
    try:
        new = tmp_path / "new.txt"
        write_text_atomic(new, "a")
        assert stat.S_IMODE(new.stat().st_mode) == 0o644
        kept = tmp_path / "kept.txt"
        kept.write_text("a")
        kept.chmod(0o664)
        write_text_atomic(kept, "b")
        assert stat.S_IMODE(kept.stat().st_mode) == 0o664
        link = tmp_path / "link.txt"
        link.symlink_to(kept.name)
        write_machine(builtin_machine("vmc"), link)
        assert link.is_symlink() and kept.read_text().startswith("# tcpmm machine model")
    finally:
        os.umask(old)


@pytest.mark.parametrize("rapid, speed, warns", [
    (None, 0.4, False), (None, 30.0, True),  # 30 m/s: a file in um read as mm
    ({"X": 0.5}, 0.45, False), ({"X": 0.5}, 0.6, True),
    ({"y": 0.5, "x": 0.2}, 0.3, True),  # keys in any case, as the interpolator reads them
])
def test_command_faster_than_the_machine_warns(rapid, speed, warns):
    m = builtin_machine("vmc")
    if rapid is not None:
        m = m.model_copy(update={"interpolation": {"rapid_m_per_s": rapid}})
    t = np.arange(200) * 1e-3
    cmd = Command(t, {"X": np.minimum(speed * t, speed * 0.05)})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        simulate(m, cmd)
    texts = [str(w.message) for w in caught if issubclass(w.category, InputWarning)]
    assert any(f"moves at {speed * 60:.4g} m/min" in s for s in texts) == warns


@pytest.mark.parametrize("case", ["identify", "simulate", "circle", "report",
                                  "simulate-stream", "path-stream"])
def test_a_failing_command_leaves_no_output_folder(capsys, tmp_path, case):
    """Output folders are checked before the work and made only when something is written:
    a command that fails on its input leaves none behind, also where the output is
    streamed and the bad block comes after the first chunk is written (it left the
    folders of its Parquet or CSV file, empty)."""
    bad = tmp_path / "bad.csv"
    bad.write_text("garbage\n")
    (tmp_path / "bundle").mkdir()
    late = tmp_path / "late.nc"
    late.write_text("G21 G90 G17\nG1 X1 F1000\nG1 X2\nG1 X3\nG1 X4 Q3\nM30\n")
    args, made = {
        "simulate-stream": (["simulate", "builtin:vmc", "--gcode", late, "-o",
                             tmp_path / "nd" / "sub" / "r.parquet", "--chunk-blocks", 1],
                            "nd"),
        "path-stream": (["path", late, "-o", tmp_path / "nd" / "c.csv", "--chunk-blocks", 1],
                        "nd"),
        "identify": (["identify", tmp_path / "bundle", "-o", tmp_path / "m.yaml",
                      "--report", tmp_path / "ident"], "ident"),
        "simulate": (["simulate", "builtin:vmc", "--command", bad, "-o",
                      tmp_path / "out" / "run.csv"], "out"),
        "circle": (["circle", bad, "--radius", 35, "--plot", tmp_path / "plots" / "c.png"],
                   "plots"),
        "report": (["report", "-o", tmp_path / "rep" / "r.html", "--run", bad, "--radius",
                    35], "rep"),
    }[case]
    code, _, err = run(capsys, *args)
    assert code == 2, err
    assert not (tmp_path / made).exists()


def test_an_output_folder_that_cannot_be_made_is_refused_before_the_work(capsys, tmp_path):
    if os.geteuid() == 0:
        pytest.skip("root writes anywhere")
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        code, _, err = run(capsys, "machine", "export", "vmc", "-o", ro / "sub" / "m.yaml")
    finally:
        ro.chmod(0o700)
    assert code == 2 and "cannot write into" in err
    assert not (ro / "sub").exists()


def test_a_warning_is_printed_once_whatever_the_filters_did_between(capsys, monkeypatch):
    """The same input warning given twice in one command, with a filter changed between
    (any ``catch_warnings`` on the way resets Python's record of what it showed), is
    printed once; another text is printed too."""
    import tcpmm.cli as cli
    from tcpmm.io.csvutil import warn_input

    def command(args=None, standalone_mode=True):
        warn_input("axis X: the same thing")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
        warn_input("axis X: the same thing")
        warn_input("axis Y: another thing")

    monkeypatch.setattr(cli, "app", command)
    monkeypatch.setattr(cli, "register", lambda argv: None)
    assert cli.main(["path"]) == 0
    err = capsys.readouterr().err
    assert err.count("the same thing") == 1 and err.count("another thing") == 1


def test_json_holds_no_nan_a_strict_reader_refuses(capsys):
    """A figure not determined (NaN) or infinite is null: JSON has no NaN, and `compare
    --json` of two arcs wrote a bare NaN that strict readers (jq, JavaScript) refuse."""
    import json

    from tcpmm.cli._app import emit_json

    emit_json({"rows": [{"spike_A_um": float("nan"), "max_um": np.float64(np.inf),
                         "ok": 1.5}], "flips": (float("-inf"),)})

    def refuse(name):
        raise ValueError(name)

    got = json.loads(capsys.readouterr().out, parse_constant=refuse)
    assert got == {"rows": [{"spike_A_um": None, "max_um": None, "ok": 1.5}],
                   "flips": [None]}


@pytest.mark.parametrize("n", [0, 1, 2, 999, 1000, 1001, 2500])
def test_rows_written_as_they_come_are_the_json_of_the_whole(capsys, n):
    """``emit_json_rows`` writes what ``emit_json`` writes of the head with the rows last,
    to the byte: no rows, one, a batch and more; NaN and infinities null, text not
    escaped to ASCII, a head with lists and dicts in it."""
    from tcpmm.cli._app import emit_json, emit_json_rows

    head = {"axes": "XY", "sensors": {"tcp": {"max_um": float("nan"), "v": [1.5, np.inf]}},
            "list": [], "name": "Überschwinger µm"}
    rows = [{"corner": k, "sensor": "tcp", "x_mm": k * 0.1, "settle_ms": float("nan"),
             "note": "µ" if k % 7 else None, "e": [k, -np.inf]} for k in range(n)]
    emit_json({**head, "corners": rows})
    whole = capsys.readouterr().out
    emit_json_rows(head, "corners", iter(rows))
    assert capsys.readouterr().out == whole


def test_rows_are_written_before_the_next_batch_is_asked_for(capsys):
    """A long run's corners are not held as one text: when the row after a full batch is
    asked for, the batch is out already."""
    from tcpmm.cli._app import JSON_BATCH_ROWS, emit_json_rows

    seen = []

    def rows():
        for k in range(2 * JSON_BATCH_ROWS + 1):
            if k and k % JSON_BATCH_ROWS == 0:
                seen.append(capsys.readouterr().out.count('"corner"'))
            yield {"corner": k}

    emit_json_rows({"axes": "XY"}, "corners", rows())
    assert seen == [JSON_BATCH_ROWS, JSON_BATCH_ROWS]


@pytest.mark.parametrize("many", [False, True])
def test_many_rows_on_a_terminal_are_written_as_they_come(monkeypatch, many):
    """On a terminal a few rows are coloured; many (the corners of a long run) are
    written as they come, uncoloured, instead of a coloured text of them all."""
    import io
    import json

    from tcpmm.cli import _app

    buf = io.StringIO()
    monkeypatch.setattr(_app, "out", _app._Console(file=buf, force_terminal=True,
                                                   highlight=False))
    n = _app.JSON_COLOURED_ROWS + 1 if many else 3
    rows = [{"corner": k, "x_mm": 0.5 * k} for k in range(n)]
    _app.emit_json_rows({"axes": "XY"}, "corners", iter(rows), n)
    text = buf.getvalue()
    assert ("\x1b[" not in text) == many
    if many:
        assert text == json.dumps({"axes": "XY", "corners": rows}, indent=2) + "\n"


def test_a_folder_that_exists_but_takes_no_file_is_not_said_to_be_made(tmp_path, monkeypatch):
    """An existing read-only folder read "the output folder /ro cannot be made there": it
    is there, and nothing can be written into it."""
    from tcpmm.errors import InputError
    from tcpmm.io.atomic import check_output_folder

    monkeypatch.setattr(os, "access", lambda *a, **k: False)
    with pytest.raises(InputError, match="nothing can be written there") as got:
        check_output_folder(tmp_path)
    assert "cannot be made" not in str(got.value)
    with pytest.raises(InputError, match="cannot be made there"):
        check_output_folder(tmp_path / "sub")


@pytest.mark.parametrize("args", [
    ("tune", "builtin:vmc", "-o", "{d}/tuned.json"),
    ("machine", "export", "vmc", "-o", "{d}/m.json"),
    ("identify", "{d}", "-o", "{d}/m.json"),
    ("frf", "fit", "{d}/h.csv", "--model-fragment", "{d}/frag.json"),
])
def test_a_model_file_named_other_than_yaml_is_refused(capsys, tmp_path, args):
    """``tune -o t.json`` wrote YAML under a .json name; a model file or fragment is YAML,
    and the name says so. Refused before any work, nothing written."""
    code, out, err = run(capsys, *[a.format(d=tmp_path) for a in args])
    assert code == 2, out + err
    said = "a transfer-function fragment" if args[0] == "frf" else "a model file"
    assert f"{said} is written as YAML; name it" in out + err
    assert not any(p.suffix == ".json" for p in tmp_path.iterdir())


def test_a_fit_named_other_than_json_is_refused(capsys, tmp_path):
    """``frf fit -o fit.csv`` wrote the fit's JSON under a .csv name, where the other
    outputs refuse a name their format does not have; and the fragment, which is no model
    file, was called one. Refused before any work, nothing written."""
    from tcpmm.ident.frf import FRF
    from tcpmm.io.frffile import write_frf_csv

    f = np.linspace(10.0, 1000.0, 200)
    h = tmp_path / "h.csv"
    write_frf_csv(FRF(f, 1 / (1 + 1j * f / 100), np.ones(f.size), 10, np.zeros(f.size)), h)
    code, out, err = run(capsys, "frf", "fit", h, "--poles", "1", "-o", tmp_path / "fit.csv")
    assert code == 2, out + err
    assert "fit.csv: the fit is written as JSON; name it fit.json" in out + err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["h.csv"]
    code, out, err = run(capsys, "frf", "fit", h, "--poles", "1", "-o", tmp_path / "fit.json")
    assert code == 0, out + err
    assert json.loads((tmp_path / "fit.json").read_text())["poles"]


def test_the_damping_floor_s_default_is_given_as_a_number():
    """``frf fit --help`` gave the default as the name of a constant."""
    import inspect

    from tcpmm.cli.frf import fit
    from tcpmm.ident.lti import DAMPING_FLOOR

    text = inspect.signature(fit).parameters["damping_floor"].default.help
    assert f"default {DAMPING_FLOOR:g}," in text and "DAMPING_FLOOR" not in text


def test_identify_json_has_the_warnings_first(monkeypatch):
    """identify --json carried its warnings after the axes, where docs/cli.md (and
    ``tune --json``) have them as the first key."""
    from tcpmm.cli import _app
    from tcpmm.ident.identification import Identification
    from tcpmm.machines.builtin import builtin_machine

    said = ["no excitation power in 990-1220 Hz"]
    monkeypatch.setattr(_app, "WARNED", list(said))
    idn = Identification({}, builtin_machine(), meta={"warnings": list(said)})
    data = _app.with_warnings(idn.to_dict())
    assert list(data) == ["warnings", "machine", "axes", "suspect"]
    assert data["warnings"] == said


_SCALARS = (st.none() | st.booleans() | st.integers() | st.text()
            | st.floats(allow_nan=True, allow_infinity=True)
            | st.floats(width=64).map(np.float64))


@settings(max_examples=300, deadline=None)
@given(row=st.dictionaries(st.text(), _SCALARS, max_size=8), ascii_only=st.booleans())
def test_a_row_of_scalars_is_written_as_json_writes_it(row, ascii_only):
    """The corner rows' own encoder gives ``json.dumps(indent=2)``'s text to the byte:
    any text (escapes, quotes, what is not ASCII, in keys too), numbers of any size,
    floats not finite as null; a row it does not take falls back to ``json``."""
    import json
    import math

    from tcpmm.cli._jsonrow import flat_row_json

    ready = {k: None if isinstance(v, float) and not math.isfinite(v) else v
             for k, v in row.items()}
    want = json.dumps(ready, indent=2, ensure_ascii=ascii_only, allow_nan=False)
    assert flat_row_json(row, ascii_only) == want
    assert flat_row_json({**row, "e": [1]}, ascii_only) is None
    assert flat_row_json({1: 2.0}, ascii_only) is None


@pytest.mark.parametrize("args, said", [
    (["circle", "run.csv", "--bogus"], "No such option: --bogus"),
    (["circl"], "Did you mean 'circle'?"),
    (["circle"], "Missing argument"),
    (["report", "-o", "r.html", "--run", "run.csv"], "--radius [mm] is needed"),
    (["simulate", "builtin:vmc", "--record-period-s", "abc"], "'--record-period-s'"),
])
def test_misused_options_are_refused_in_one_line(capsys, args, said):
    """A misused command line is refused as every other input: one line on stderr,
    nothing on stdout, exit code 2, and where to look."""
    code = main(args)
    cap = capsys.readouterr()
    assert code == 2 and cap.out == ""
    assert cap.err.count("\n") == 1 and cap.err.startswith("error: "), cap.err
    assert said in cap.err and "--help' lists what it takes" in cap.err
