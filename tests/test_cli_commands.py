"""The command map of the command line: each command's module is imported when that
command runs, and the list of commands still names every one."""

import importlib
import subprocess
import sys
from pathlib import Path

import pytest
import typer

from tcpmm import cli
from tcpmm.cli._app import app


def _registered() -> set:
    """The commands and command groups registered on the application so far."""
    return set(typer.main.get_command(app).commands)


@pytest.mark.parametrize("name", sorted(cli.COMMANDS))
def test_every_command_in_the_map_resolves_to_its_module(name):
    importlib.import_module(f"tcpmm.cli.{cli.COMMANDS[name]}")
    assert name in _registered()


def test_the_map_names_every_command_the_modules_register():
    cli.register([])  # no command named: every module
    assert _registered() == set(cli.COMMANDS)


def test_help_lists_every_command(capsys):
    assert cli.main(["--help"]) == 0
    listing = capsys.readouterr().out.split("Commands:", 1)[1]
    listed = {line.split()[0] for line in listing.splitlines() if line.strip()}
    assert listed == set(cli.COMMANDS)


@pytest.mark.parametrize(("argv", "modules"), [(["simulate", "--help"], ["tcpmm.cli.run"]),
                                               (["--version"], [])])
def test_a_command_imports_only_its_own_module(argv, modules):
    code = (f"import sys; from tcpmm.cli import main; rc = main({argv!r}); "
            "print(sorted(m for m in sys.modules if m.startswith('tcpmm.cli.') "
            "and not m.startswith('tcpmm.cli._')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip().splitlines()[-1] == repr(modules)


def test_a_simulate_to_csv_on_the_built_in_machine_imports_only_what_it_uses(tmp_path):
    """No PyYAML (the built-in machine is read from no file), no table of rich's emoji (no
    message has an emoji code), none of the libraries of other commands: each would be
    start-up time of the command (``tcpmm simulate`` of the paper's circle)."""
    program = Path(__file__).resolve().parents[1] / "examples" / "circle_r35_f5000.nc"
    argv = ["simulate", "builtin:vmc", "--gcode", str(program), "-o", str(tmp_path / "r.csv")]
    unused = ("yaml", "rich._emoji_codes", "scipy", "pandas", "pyarrow", "matplotlib")
    code = (f"import sys; from tcpmm.cli import main; rc = main({argv!r}); "
            f"print(rc, sorted(m for m in {unused!r} if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip().splitlines()[-1] == "0 []"
    assert (tmp_path / "r.csv").stat().st_size > 0


def test_a_mistyped_command_gets_a_suggestion(capsys):
    assert cli.main(["simulat"]) == 2
    assert "Did you mean 'simulate'" in capsys.readouterr().err


def test_the_console_script_leaves_without_a_last_collection(tmp_path):
    """``tcpmm`` is :func:`tcpmm.cli.run`: the command's exit code and outputs, then the
    objects frozen out of the interpreter's last collections (some 45 000 objects of a
    simulation, a fifth of a short command's time)."""
    import tomllib
    from pathlib import Path

    project = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())
    assert project["project"]["scripts"]["tcpmm"] == "tcpmm.cli:run"
    code = ("import gc, sys; from tcpmm.cli import run; sys.argv[1:] = ['machine', 'show', "
            "'builtin:vmc', '--json']; c = run(); print(c, gc.get_freeze_count() > 10000)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, check=True)
    assert done.stdout.splitlines()[-1] == "0 True"
    code = code.replace("'builtin:vmc'", "'nosuch.yaml'")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          cwd=tmp_path, check=True)
    assert done.stdout.splitlines()[-1] == "2 True" and "nosuch.yaml" in done.stderr


def _in_fresh_interpreter(code: str) -> str:
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    return done.stdout.strip().splitlines()[-1]


def test_the_command_line_holds_the_first_collection_back_then_collects_as_before():
    """Importing the command line raises the first generation's threshold (its imports
    build some hundred thousand objects that are no garbage); the first collection puts
    back the thresholds that were set, so a long command collects as before."""
    code = ("import gc; gc.set_threshold(500, 7, 9); import tcpmm.cli, tcpmm.cli._collector "
            "as c; up = gc.get_threshold(); gc.collect(); "
            "print(up == (c.START_THRESHOLD, 7, 9), gc.get_threshold())")
    assert _in_fresh_interpreter(code) == "True (500, 7, 9)"


def test_a_switched_off_collector_stays_off_and_other_callbacks_still_run():
    code = ("import gc; gc.disable(); gc.set_threshold(0); from tcpmm.cli._collector import "
            "collect_late; collect_late(); print(gc.get_threshold()[0], gc.isenabled())")
    assert _in_fresh_interpreter(code) == "0 False"
    code = ("import gc; gc.set_threshold(600); from tcpmm.cli._collector import collect_late; "
            "collect_late(); "
            "seen = []; gc.callbacks.append(lambda phase, info: seen.append(phase)); "
            "gc.collect(); gc.collect(); print(seen, gc.get_threshold()[0])")
    assert _in_fresh_interpreter(code) == "['start', 'stop', 'start', 'stop'] 600"


def test_once_the_thresholds_are_restored_no_python_callback_is_left():
    """The callback stayed in gc.callbacks for the whole command: a Ctrl-C that fell in it
    on a later collection was printed as "Exception ignored" and lost, and a sweep ran on
    to its end with exit 0. Once done it is a function of C, where no interrupt lands."""
    code = ("import gc, types; gc.set_threshold(600); from tcpmm.cli._collector import "
            "collect_late; collect_late(); n = len(gc.callbacks); gc.collect(); "
            "print(len(gc.callbacks) == n, any(isinstance(c, types.FunctionType) "
            "for c in gc.callbacks))")
    assert _in_fresh_interpreter(code) == "True False"
