"""The compiled module is built in an interpreter of its own.

Its name hashes the sources on disk. A process that has run since before an upgrade
holds the former modules in memory, and built there they were filed under the new
sources' name: every later process would have run the former kernel with the new code
around it.
"""

import subprocess
import sys
from pathlib import Path

import pytest

import tcpmm
from tcpmm import _compiled, _pycc


def test_the_build_runs_the_sources_on_disk_in_a_fresh_interpreter(monkeypatch, tmp_path):
    seen = {}

    def run(args, **kw):
        seen.update(args=args, env=kw["env"])
        return subprocess.CompletedProcess(args, 0, "", "")

    monkeypatch.setattr(subprocess, "run", run)
    monkeypatch.setenv("PYTHONPATH", "/elsewhere")
    _compiled.build(tmp_path / "_kernels_x.so")
    assert seen["args"][0] == sys.executable and seen["args"][1] == "-c"
    assert "build_module" in seen["args"][2] and seen["args"][3] == str(tmp_path / "_kernels_x.so")
    # the tcpmm this process runs, found first
    first = seen["env"]["PYTHONPATH"].split(":")[0]
    assert Path(first) / "tcpmm" == Path(tcpmm.__file__).resolve().parent
    assert seen["env"]["PYTHONPATH"].endswith("/elsewhere")


def test_a_build_that_stops_says_its_last_line(monkeypatch, tmp_path):
    monkeypatch.setattr(subprocess, "run", lambda args, **kw: subprocess.CompletedProcess(
        args, 1, "", "Traceback ...\n  ...\nOSError: no C compiler\n"))
    with pytest.raises(OSError, match="the build stopped: OSError: no C compiler"):
        _pycc.build_apart(tmp_path / "_kernels_x.so")
