"""The user scripts of examples/ run as a user runs them, and stay short."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SCRIPTS = sorted(EXAMPLES.glob("*.py"))


def test_examples_are_short_user_scripts():
    assert {p.name for p in SCRIPTS} >= {"quickstart.py", "own_machine.py"}
    for p in SCRIPTS:
        assert len(p.read_text(encoding="utf-8").splitlines()) < 80, p.name


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_example_runs(script, tmp_path):
    """Exit 0, the plots written, a table of spikes printed."""
    out = subprocess.run([sys.executable, str(script), str(tmp_path / "out")],
                         capture_output=True, text=True, cwd=tmp_path, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert list((tmp_path / "out").glob("*.png"))
    assert "spike_A_um" in out.stdout
