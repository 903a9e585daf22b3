"""The command line, end to end on the built-in machine."""

import json
import math
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import run_cli
from tcpmm.cli import main
from tcpmm.demo import paper_circle_command
from tcpmm.path import write_command_csv


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("cli")
    write_command_csv(paper_circle_command(), d / "cmd.csv")
    return d


def test_export_simulate_circle_compare(capsys, files):
    d = files
    code, _, _ = run_cli(capsys, "machine", "export", "vmc", "-o", d / "m.yaml")
    assert code == 0 and (d / "m.yaml").is_file()
    # builtin:vmc, as every other command takes it, was 'unknown built-in machine'
    code, _, _ = run_cli(capsys, "machine", "export", "builtin:vmc", "-o", d / "m2.yaml")
    assert code == 0 and (d / "m2.yaml").read_text() == (d / "m.yaml").read_text()
    code, out, _ = run_cli(capsys, "simulate", d / "m.yaml", "--command", d / "cmd.csv",
                       "-o", d / "run.csv")
    assert code == 0, out
    header = (d / "run.csv").read_text().splitlines()[0].split(",")
    assert header[:6] == ["time_s", "x_cmd_mm", "x_motor_mm", "x_scale_mm", "x_tcp_mm",
                          "x_current_A"]
    code, out, _ = run_cli(capsys, "circle", d / "run.csv", "--radius", 35, "--json")
    assert code == 0
    res = json.loads(out)
    assert [p["direction"] for p in res["passes"]] == ["ccw", "cw"]
    rows = {(p["direction"], r["sensor"]): r for p in res["passes"] for r in p["sensors"]}
    tcp, scale = rows[("ccw", "tcp")], rows[("ccw", "scale")]
    # The paper's observations: the TCP differs visibly from the scale, and oscillates
    # (reversal spike) more after B/D, where the heavier Y axis reverses, than after A/C.
    assert abs(tcp["contour_error_um"] - scale["contour_error_um"]) > 1.0
    assert min(abs(tcp["spike_B_um"]), abs(tcp["spike_D_um"])) > 2 * max(
        abs(tcp["spike_A_um"]), abs(tcp["spike_C_um"]))
    code, out, _ = run_cli(capsys, "compare", d / "run.csv", d / "run.csv", "--radius", 35,
                       "--json")
    assert code == 0
    cmp = json.loads(out)
    assert all(abs(r["contour_error_um"]) < 1e-9 for r in cmp["rows"])
    assert cmp["sign_flips"] == []


def test_bode_targets(capsys, files):
    code, out, _ = run_cli(capsys, "bode", "builtin:vmc", "--axis", "X", "--tf", "G_T",
                       "--freq-hz", "0.01", "--json")
    assert code == 0
    h = json.loads(out)[0]
    assert abs(complex(h["re"], h["im"]) / (0.01 / (2 * np.pi)) - 1) < 1e-3
    # Rigid bed and structure: G_tcp -> 1 up to 500 Hz.
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    stiff = m.with_axis("X", x.replace(mechanics=x.mechanics.scaled(K_b=1e6, K_h=1e6)))
    write_machine(stiff, files / "stiff.yaml")
    f = ",".join(str(v) for v in np.linspace(1, 500, 50))
    code, out, _ = run_cli(capsys, "bode", files / "stiff.yaml", "--axis", "x", "--tf", "G_tcp",
                       "--freq-hz", f, "--json")
    assert code == 0
    assert max(abs(complex(r["re"], r["im"]) - 1) for r in json.loads(out)) < 1e-3


@pytest.mark.parametrize(("args", "needle"), [
    (["simulate", "nope.yaml", "--command", "x.csv", "-o", "r.csv"], "not found"),
    (["bode", "builtin:vmc", "--axis", "Q", "--tf", "G_M"], "no axis"),
    (["machine", "export", "lathe", "-o", "m.yaml"], "unknown built-in"),
])
def test_errors_are_messages_not_tracebacks(capsys, tmp_path, monkeypatch, args, needle):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, *args)
    assert code == 2
    assert needle in err and "Traceback" not in err + out


def test_bad_model_file_names_line(capsys, tmp_path):
    p = tmp_path / "m.yaml"
    run_cli(capsys, "machine", "export", "vmc", "-o", p)
    p.write_text(p.read_text().replace("K_pp:", "Kpp:", 1))
    code, _, err = run_cli(capsys, "bode", p, "--axis", "X", "--tf", "G_M")
    assert code == 2 and "Kpp" in err and "line" in err


def console_words(page: str) -> list[str]:
    """What of a report's visible text (outside tags and so their data: URIs) is the
    command line's and not the page's: a pointer to --json, a snake_case key. File names
    and paths, and the model table's column of the model file's own keys, are left out
    [-]."""
    import html

    text = re.sub(r"<style>.*?</style>", " ", page, flags=re.S)
    text = re.sub(r'<table data-csv="model.csv">.*?</table>',
                  lambda m: re.sub(r"<tr><td>[^<]*</td><td>[^<]*</td>", "<tr>", m.group(0)),
                  text, flags=re.S)
    text = html.unescape(re.sub(r"<[^>]+>", " ", text))
    text = re.sub(r"[^\s(]+\.(?:csv|yaml|json|png|html)\b|\S*/\S*", " ", text)  # files
    return re.findall(r".{0,40}(?:--json|\b[a-z][a-z0-9]*(?:_[a-z0-9]+)+\b)", text)


def test_demo_writes_everything(capsys, tmp_path):
    """The demo writes its report by default and prints its absolute path; the page opens
    with the verdict on the measured circle against the tolerance given."""
    code, out, _ = run_cli(capsys, "demo", "-o", tmp_path / "demo", "--tolerance-um", 100)
    assert code == 0
    for name in ("model.yaml", "run.csv", "circle.png", "bode_X.png", "bode_Y.png",
                 "time.png", "circle_table.csv", "circle.json", "table2.csv", "spread.csv",
                 "spread.json", "spread.png", "report.html"):
        assert (tmp_path / "demo" / name).stat().st_size > 0, name
    flat = out.replace("\n", "")
    report = (tmp_path / "demo" / "report.html").resolve()
    assert str((tmp_path / "demo").resolve()) in flat and "Spread over 16 drawn machines" in flat
    assert f"report: {report}" in flat
    # its tables' titles say µm as their columns do: 'Table 2 ... [um]' over '[µm]'
    assert "[um]" not in out
    assert "Table 2 at the TCP against the predicted 90 % interval [µm]" in out.splitlines()
    # each spike named for what it is, the directions as the tables after it write them,
    # the interval as compare names it, and µm in words too (no internal column names)
    for shown in ("spike A after terms [µm]", "raw spike D [µm]", "raw spike B",
                  "90 % interval +-", "µm of the prediction"):
        assert shown in out, shown
    for internal in ("after_terms", "half width", " um "):
        assert internal not in out, internal
    assert not any(line.split()[0] in ("ccw", "cw") for line in out.splitlines()
                   if line.split())
    # every file written is in the printed list, itself or in a folder listed (the bundle)
    listed = [Path(line.split()[-1]) for line in out.splitlines()
              if line.startswith("  ") and len(line.split()) == 2]
    # in one column, however long the longest name
    starts = {line.index(line.split()[-1]) for line in out.splitlines()
              if line.startswith("  ") and len(line.split()) == 2}
    assert len(starts) == 1, starts
    for f in (tmp_path / "demo").resolve().rglob("*"):
        assert f.is_dir() or any(f == p or p in f.parents for p in listed), f
    page = report.read_text(encoding="utf-8")
    # the page says things in its own words: "(the raw e - b are in --json)", "(the move
    # is in --json, tail_shift)" and "axis X guideway_share, open" (24 times) were the
    # command line's
    assert not console_words(page)
    order = [page.index(f'data-section="{kind}"') for kind in
             ("verdict", "circle", "comparison", "spread", "identification", "model")]
    assert order == sorted(order)
    assert '<p class="pass">PASS' in page
    # the paper's circle starts where its feed-in semicircle joins, before the servo has
    # settled: the verdict says so, and that its figures are not firm for it
    verdict = page[order[0]:order[1]]
    assert "PASS (not firm: see the cautions below)" in verdict
    assert "the CCW circle starts before the servo has settled" in verdict
    for fact in ("35 mm", "5000 mm/min", "CCW then CW", "1000 Hz", "measured_run.csv"):
        assert fact in page[order[0]:order[1]], fact
    assert page.count("<h3>Diagnostics (TCP)</h3>") == 2  # simulated and virtual measurement
    # Table 2 with its uncertainty: the virtual measurement has the model's structure, so
    # each of its differences lies inside the identified model's 90 % interval
    judged = pd.read_csv(tmp_path / "demo" / "table2_judged.csv")
    assert len(judged) == 10 and judged["inside"].all()
    assert set(judged["verdict"]) <= {"firm", "uncertain", "undetermined"}
    assert "prediction's 90 % interval" in page[order[2]:order[3]]
    # its inputs are named where they are once the demo is done, not in the folder they
    # were staged in (gone when the page is read)
    inputs = page[page.index('id="inputs"'):]  # not the images' base64, long and unspaced
    named = re.findall(r"([^\s<>]+) \(written", inputs)
    assert len(named) == 2 and all(Path(p).exists() for p in named), named


@pytest.mark.parametrize("command", ["compare", "circle", "identify", "excite"])
def test_help_shows_units(capsys, command):
    """Units in brackets are text, not markup: the help keeps them."""
    args = [command, "log", "--help"] if command == "excite" else [command, "--help"]
    try:
        main(args)
    except SystemExit:
        pass
    text = capsys.readouterr().out
    assert "[mm]" in text or "[Hz]" in text or "[-]" in text


@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_identify_takes_the_pre_sliding_displacement(capsys, tmp_path):
    """``--presliding-um`` reaches the model file: the guideway of X builds its static
    level over 1.5 um, and 0 keeps the static model. X has a 0.05 um scale, so that its
    share comes from the travelling sweep (on the built-in 1 um scale the plateaus' is
    the tighter)."""
    from tcpmm.io.modelfile import read_machine
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.machines.virtual import virtual_bundle
    from tcpmm.mechanics.friction import LuGreFriction

    m = builtin_machine()
    x = m.axes["X"]
    m = m.with_axis("X", x.replace(sensors=x.sensors.model_copy(
        update={"scale_resolution": 0.05e-6})))
    virtual_bundle(m, tmp_path / "b", axes=("X",))
    for um in (1.5, 0.0):
        model = tmp_path / f"m{um}.yaml"
        code, out, err = run_cli(capsys, "identify", tmp_path / "b", "-o", model,
                             "--presliding-um", um, "--json")
        assert code == 0, err
        x = json.loads(out)["axes"]["X"]
        assert x["presliding_m"] == pytest.approx(um * 1e-6)
        tv = x["friction_split"]["table_viscous_N_s_per_m"]
        assert tv["value"] > 0 and 0 < tv["std"] < tv["value"]
        g = read_machine(model).axes["X"].friction.guideway
        if um:
            assert g.sigma0 * 1.5e-6 == pytest.approx(max(g.fs_pos, g.fs_neg), rel=1e-6)
        else:
            assert not isinstance(g, LuGreFriction)
    code, out, err = run_cli(capsys, "identify", tmp_path / "b", "-o", tmp_path / "d.yaml",
                         "--report", tmp_path / "ident.html")
    assert code == 0, err
    page = (tmp_path / "ident.html").read_text(encoding="utf-8")
    assert page.count("<section") == 2 and 'data-section="identification"' in page
    assert 'alt="Bode plots of axis X" src="data:image/png;base64,' in page
    from tcpmm.ident.friction import PRESLIDING

    text = " ".join(out.split())
    assert f"pre-sliding of {PRESLIDING * 1e6:g} um assumed" in text
    # where the share came from, and the table damping it rests on
    assert "friction X: guideway share " in text and " N s/m (plateaus " in text


def test_json_in_a_pipe_is_written_as_it_is(capsys, monkeypatch):
    """Not on a terminal, ``--json`` is the JSON indented by two, not rich's highlighted
    rendering (seconds for the thousands of corners of a long run); the same text."""
    import rich.json

    def refused(*args, **kw):
        raise AssertionError("rendered by rich in a pipe")

    monkeypatch.setattr(rich.json.JSON, "__init__", refused)
    code, out, _ = run_cli(capsys, "bode", "builtin:vmc", "--axis", "X", "--tf", "G_T",
                       "--freq-hz", "0.01,1", "--json")
    assert code == 0
    assert out == json.dumps(json.loads(out), indent=2, ensure_ascii=False) + "\n"


def test_bode_text_columns_line_up(capsys):
    """The phase column started wherever the magnitude's digits ended (|H| 8.58824 and
    |H| 0.0440112 put it two columns apart)."""
    code, out, _ = run_cli(capsys, "bode", "builtin:vmc", "--axis", "X", "--tf", "G_M",
                       "--freq-hz", "1,10,100,1000,10000,0.001")
    assert code == 0
    lines = [line for line in out.splitlines() if line.strip()][1:]  # after the heading
    assert len(lines) == 6
    assert len({line.index("phase") for line in lines}) == 1
    assert len({line.index("|H|") for line in lines}) == 1


@pytest.mark.parametrize(("tf", "unit"), [("G_M", "rad/s/A"), ("G_T", "m/rad"),
                                          ("cmd_to_current", "A/m"), ("cmd_to_tcp", "m/m"),
                                          ("L_p", "-")])
def test_bode_says_what_the_response_relates_and_its_unit(capsys, tf, unit):
    """|H| came without its unit: 8.58824 of G_M could be rad/s or mm/min per A."""
    code, out, _ = run_cli(capsys, "bode", "builtin:vmc", "--axis", "X", "--tf", tf,
                       "--freq-hz", "10,20")
    assert code == 0
    head, *rows = [line for line in out.splitlines() if line.strip()]
    assert head.startswith(f"{tf} of axis X: ") and head.endswith(f"[{unit}]")
    assert len(rows) == 2 and all(f" {unit} " in r.split("|H|")[1] for r in rows)
    code, out, _ = run_cli(capsys, "bode", "builtin:vmc", "--axis", "X", "--tf", tf,
                       "--freq-hz", "10", "--json")
    assert json.loads(out)[0]["unit"] == unit


def test_a_raw_spike_is_named_raw_where_circle_leads_with_another(tmp_path, capsys):
    """``tcpmm circle`` leads with the spike after the fitted terms; the spread, the
    verdicts and compare give the raw e - b under the same letters, and say so (a user
    set a spread's 13.84 um against circle's 18.90 um as a miss of a firm figure)."""
    from tcpmm.demo import paper_circle_command
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine
    from tcpmm.model import AxisUncertainty
    from tcpmm.path import write_command_csv

    m = builtin_machine()
    m = m.model_copy(update={"axes": {n: m.axes[n] for n in ("X", "Y")}})
    for n in ("X", "Y"):  # an identified model: every quantity known
        m = m.with_axis(n, m.axes[n].replace(uncertainty=AxisUncertainty()))
    write_machine(m, tmp_path / "m.yaml")
    write_command_csv(paper_circle_command(m), tmp_path / "cmd.csv")
    code, out, err = run_cli(capsys, "spread", str(tmp_path / "m.yaml"), "--command",
                         str(tmp_path / "cmd.csv"), "--radius", "35", "--draws", "10")
    assert code == 0, err
    text = " ".join(out.split())
    assert "tcp raw reversal spikes (e - b) over 10 drawn machines" in text
    assert "verdict R35 raw spike A (e - b) (" in text and "verdict R35 spike" not in text


def test_a_record_period_off_the_loop_is_refused_by_its_option(tmp_path, capsys):
    """A record period that is no whole number of velocity-loop periods is the option's
    fault, not the program's: the message named the NC program."""
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90 G1 X10 Y0 F3000\nX0\n")
    code, _out, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", str(prog), "-o",
                         str(tmp_path / "r.csv"), "--record-period-s", "0.0007")
    text = " ".join(err.split())
    assert code == 2 and "Invalid value for --record-period-s" in text and "p.nc" not in text
    assert "e.g. 0.00075 s" in text and not (tmp_path / "r.csv").exists()


@pytest.mark.parametrize("out", ["r.csv", "r.parquet"])  # parquet: the program streams
def test_a_record_period_longer_than_the_run_writes_no_run(tmp_path, capsys, out):
    """`tcpmm simulate ... --record-period-s 1` of a shorter program said "wrote r.csv (1
    samples ...)" with exit code 0: a run file that every analysis refuses ("a run needs
    two or more")."""
    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90 G1 X10 Y0 F3000\nX0\n")
    code, out_text, err = run_cli(capsys, "simulate", "builtin:vmc", "--gcode", str(prog),
                                  "-o", str(tmp_path / out), "--record-period-s", "1")
    text = " ".join(err.split())
    assert code == 2 and "wrote" not in out_text, (out_text, text)
    assert "the record period, 1 s, is longer than the run" in text
    assert not (tmp_path / out).exists()


def test_a_reader_that_goes_away_ends_the_command_as_sigpipe_would(tmp_path):
    """``tcpmm ... | head``: the command stops quietly with 141 (128 + SIGPIPE, as a shell
    reports a command the pipe stopped), not with 1, the code of a failure."""
    import subprocess
    import sys

    freqs = ",".join(f"{1 + 0.5 * i:g}" for i in range(4000))  # some 250 kB of lines
    cmd = [sys.executable, "-c", "import sys; from tcpmm.cli import run; sys.exit(run())",
           "bode", "builtin:vmc", "--axis", "X", "--tf", "G_M", "--freq-hz", freqs]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            cwd=tmp_path)
    assert proc.stdout.read(100).startswith(b"G_M of axis X")
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=120) == 141
    assert "Traceback" not in err and "Exception" not in err
    done = subprocess.run(cmd, capture_output=True, cwd=tmp_path, timeout=120)
    assert done.returncode == 0 and len(done.stdout.splitlines()) == 4001  # read to the end


@pytest.mark.skipif(not hasattr(__import__("select"), "poll"), reason="no poll() here")
def test_a_pipe_without_reader_is_told_from_one_with():
    """A write outside rich's console that the closed pipe refused ends with 141 too: the
    pipe's end that writes polls as an error once no one reads."""
    import os

    from tcpmm.cli import _reader_gone

    r, w = os.pipe()
    try:
        assert not _reader_gone(w)
        os.close(r)
        assert _reader_gone(w)
    finally:
        os.close(w)


def test_identifys_verdicts_say_which_circles_they_are_of(capsys):
    """identify's "verdict R35 F5000 contour error: 16.42 um" read as the user's own R35
    F5000 circle (measured 15.35 um through the controller's filter); the circles the
    verdicts are of are said before them."""
    from types import SimpleNamespace

    from tcpmm.cli.ident import _print_verdict, reference_note

    fig = SimpleNamespace(verdict="firm", settle="", nominal=16.42e-6, text=lambda: "firm",
                          direction="cw")
    verdict = SimpleNamespace(axes={}, figures=[fig],
                              worst=lambda: {"R35 F5000 contour error": fig})
    _print_verdict(verdict, reference_note())
    lines = [ln for ln in capsys.readouterr().out.splitlines() if ln.strip()]
    assert lines[0].startswith("the verdicts' circles: R 35 mm about the origin")
    assert "fed in from the centre" in lines[0] and "tcpmm spread" in lines[0]
    # the least firm of both directions is the one shown, and which it is is said (the CW
    # figures stood for the circle while the CCW one was larger)
    assert lines[1] == "verdict R35 F5000 contour error (CW): 16.42 um, firm"


def test_machine_show_gives_a_light_modes_damping_its_digits(capsys):
    """A mode of damping 0.00052 printed as "zeta 0.001", and machine D's 0.0002 as
    "zeta 0.000": undamped, to a reader."""
    assert main(["machine", "show", "builtin:vmc"]) == 0
    text = capsys.readouterr().out
    assert "zeta 0.00052" in text and "zeta 0.000)" not in text


def test_machine_show_of_an_unstable_sampled_loop_does_not_read_as_stable(tmp_path, capsys):
    """With X's velocity gain raised till the drive's sampled loop is unstable, machine show
    read 'closed loop stable; sampled loop UNSTABLE' and gave the position loop's margins as
    if they held. It says which loop is the continuous one, and that the position loop's
    margins mean nothing there."""
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    write_machine(m.with_axis("X", x.replace(servo=x.servo.model_copy(update={"K_vp": 8.0}))),
                  tmp_path / "m.yaml")
    assert main(["machine", "show", str(tmp_path / "m.yaml")]) == 0
    lines = capsys.readouterr().out.splitlines()
    head = next(ln for ln in lines if ln.startswith("X:"))
    assert "continuous closed loop" in head and "sampled loop UNSTABLE" in head
    pos = [ln for ln in lines if "position loop:" in ln]
    assert "of no meaning: the sampled velocity loop is unstable" in pos[0]
    assert "of no meaning" not in pos[1]  # Y's loops hold


@pytest.mark.parametrize("change, velocity, position", [
    ({"current_bandwidth_hz": 5.0}, False, False),  # the velocity loop's crossover at +153 deg
    ({"K_pp": 2000.0}, True, False),
    ({"K_vi": 0.0}, True, True),  # a P velocity loop: its integrator's 0 is no mode
])
def test_machine_show_marks_the_margins_of_each_unstable_loop(tmp_path, capsys, change,
                                                             velocity, position):
    """A current loop of 5 Hz left the velocity loop unstable alone, and machine show gave
    its margins (2.0 dB, 4.9 deg) unmarked; a P velocity loop read as a continuous loop
    UNSTABLE that the sampled check called stable."""
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    write_machine(m.with_axis("X", x.replace(servo=x.servo.model_copy(update=change))),
                  tmp_path / "m.yaml")
    assert main(["machine", "show", str(tmp_path / "m.yaml"), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["X"]
    assert got["sampled_loop_stable"] == {"velocity": velocity, "position": position}
    assert got["closed_loop_stable"] or not position
    assert main(["machine", "show", str(tmp_path / "m.yaml")]) == 0
    lines = capsys.readouterr().out.splitlines()
    for loop, stable in (("velocity", velocity), ("position", position)):
        line = next(ln for ln in lines if f"{loop} loop:" in ln)  # X's, the first
        assert ("of no meaning" not in line) == stable, line


def test_a_measured_run_without_command_compares_to_its_own_signals_as_zero(capsys, files):
    """A TCP device's record has no command columns: its passes are found on the sensor.
    The prediction's were cut on its command, so the same signals compared up to 3.6 um
    apart; both are now cut alike, in compare and in the report."""
    d = files
    code, _, _ = run_cli(capsys, "simulate", "builtin:vmc", "--command", d / "cmd.csv",
                     "-o", d / "pred.csv")
    assert code == 0
    frame = pd.read_csv(d / "pred.csv")
    frame.drop(columns=[c for c in frame if "_cmd_" in c]).to_csv(d / "meas.csv", index=False)
    code, out, err = run_cli(capsys, "compare", d / "meas.csv", d / "pred.csv", "--radius", 35,
                         "--json")
    assert code == 0, err
    rows = json.loads(out)["rows"]
    assert len(rows) == 6
    for r in rows:
        assert r["contour_error_um"] == 0.0 and r["radial_max_um"] == 0.0, r
    assert "passes are found on its sensors" in err
    code, _, err = run_cli(capsys, "report", "-o", d / "r.html", "--measured", d / "meas.csv",
                       "--predicted", d / "pred.csv", "--radius", 35)
    assert code == 0, err
    import tcpmm

    with pytest.warns(UserWarning, match="passes are found on its sensors"):
        cmp = tcpmm.compare(d / "meas.csv", d / "pred.csv", radius_m=35e-3)
    assert max(abs(r["radial_max_um"]) for r in cmp.rows) == 0.0


def test_numpys_runtime_warnings_do_not_reach_the_user(capsys, monkeypatch):
    """A degenerate record (a clamped sweep under --accept-suspect) printed eight of
    numpy's 'Mean of empty slice' notes with their source lines among tcpmm's own
    warnings; TCPMM_TRACEBACK=1 shows them for a defect report."""
    import importlib
    import warnings

    cli = importlib.import_module("tcpmm.cli")
    real = cli.register

    def noisy(argv):
        warnings.warn("Mean of empty slice", RuntimeWarning, stacklevel=1)
        real(argv)

    monkeypatch.setattr(cli, "register", noisy)
    monkeypatch.delenv("TCPMM_TRACEBACK", raising=False)
    passed_on = []
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = lambda message, *a, **k: passed_on.append(str(message))
        code, out, err = run_cli(capsys, "machine", "show", "builtin:vmc")
        assert code == 0 and "empty slice" not in out + err and not passed_on
        monkeypatch.setenv("TCPMM_TRACEBACK", "1")
        code, out, err = run_cli(capsys, "machine", "show", "builtin:vmc")
    assert code == 0 and passed_on == ["Mean of empty slice"]


def test_a_signal_ends_the_command_without_waiting_for_its_kernel_threads(tmp_path):
    """SIGTERM raised SystemExit(143) in the main thread, but the interpreter then waited for
    the worker threads still running the axes' kernels: a long simulate went on for
    minutes after it. The console script now ends at once with 143."""
    import subprocess
    import sys
    import time

    script = (
        "import sys, threading, time\n"
        "import tcpmm.cli as cli\n"
        "def main(argv=None):\n"
        "    threading.Thread(target=time.sleep, args=(30,)).start()\n"
        "    return 143\n"
        "cli.main = main\n"
        "sys.exit(cli.run())\n")
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", script], timeout=25)
    assert done.returncode == 143 and time.perf_counter() - t0 < 15


def test_machine_show_of_an_undamped_model_lists_its_modes_alone(tmp_path, capsys):
    """With every damping 0 the rigid body's double eigenvalue at 0, split by rounding,
    was listed as a mode of "0.0 Hz (zeta -3.3e-08)", and the modes' damping as -1e-16."""
    from tcpmm.io.modelfile import write_machine
    from tcpmm.machines.builtin import builtin_machine

    m = builtin_machine()
    x = m.axes["X"]
    undamped = x.mechanics.model_copy(update=dict.fromkeys(("B_m", "B_L", "C_t", "C_b",
                                                            "C_h"), 0.0))
    write_machine(m.with_axis("X", x.replace(mechanics=undamped)), tmp_path / "m.yaml")
    assert main(["machine", "show", str(tmp_path / "m.yaml"), "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["X"]
    want = json.loads(_show_json(capsys, "builtin:vmc"))["X"]["modes_hz"]
    assert len(got["modes_hz"]) == len(want) and min(got["modes_hz"]) > 1.0
    assert got["damping"] == [0.0] * len(want)


def _show_json(capsys, model) -> str:
    assert main(["machine", "show", model, "--json"]) == 0
    return capsys.readouterr().out


def test_bode_of_an_identified_model_gives_the_range_of_its_draws(capsys, tmp_path, once):
    """Machine C's identified model at 746 Hz, beside its torsion mode: |H| of G_M read
    86.7 rad/s/A at -108.6 deg as exact numbers, the true machine's 272 at +47.9 deg. The
    response of an identified model comes with its range over machines drawn from its
    uncertainty, which there spans a factor of tens; at 50 Hz, a few per cent."""
    import warnings

    from conftest import bench_path
    from tcpmm import save_model
    from tcpmm.ident.pipeline import identify_bundle
    from tcpmm.io.bundle import read_bundle

    def make():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return identify_bundle(read_bundle(bench_path("c") / "bundle"), verdict=False)

    model = save_model(once("bench_c", make).machine, tmp_path / "c.yaml")
    code, out, err = run_cli(capsys, "bode", model, "--axis", "X", "--tf", "G_M",
                             "--freq-hz", "50,746", "--json")
    assert code == 0, err
    low, mode = json.loads(out)
    assert low["abs_low"] <= math.hypot(low["re"], low["im"]) <= low["abs_high"]
    assert low["abs_high"] / low["abs_low"] < 1.5
    assert mode["abs_high"] / mode["abs_low"] > 10.0
    code, out, _ = run_cli(capsys, "bode", model, "--axis", "X", "--tf", "G_M",
                           "--freq-hz", "746", "--plot", tmp_path / "b.png")
    assert "(drawn: |H|" in out and "drawn from the identified model's uncertainty" in out
    assert (tmp_path / "b.png").stat().st_size > 0  # the draws' ends drawn beside it
