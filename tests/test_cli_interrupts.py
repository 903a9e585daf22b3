"""A Ctrl-C is never lost: not where Python ignores exceptions (a finaliser, a collector's
callback), and not while a sweep's Dask workers start with the interrupt ignored."""

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

import tcpmm

#: where the tcpmm under test is, for the Pythons started here
SRC = str(Path(tcpmm.__file__).parents[1])


def test_an_interrupt_that_lands_in_a_finaliser_stops_the_command(monkeypatch, capsys):
    """A Ctrl-C that arrives while the interpreter runs a finaliser or the collector's
    callback is raised there, and Python ignores it with a traceback on stderr: a sweep
    interrupted 1.5 s after its start (the command's first collection) ran on for 72 s
    and ended with exit 0. The stop now reaches the command."""
    import signal

    import tcpmm.cli.machine as mod
    from tcpmm.cli import main

    # as at a terminal: a suite started in the background runs with the interrupt ignored
    before = signal.signal(signal.SIGINT, signal.default_int_handler)

    class Lands:
        def __del__(self):
            raise KeyboardInterrupt

    real, calls = mod.margins_line, []

    def line(mg):
        calls.append(mg)
        Lands()  # made and finalised at once: the interrupt lands in its finaliser
        time.sleep(1.0)  # the command goes on, as a sweep does
        return real(mg)

    monkeypatch.setattr(mod, "margins_line", line)
    try:
        code = main(["machine", "show", "builtin:vmc"])
    finally:
        signal.signal(signal.SIGINT, before)
    err = capsys.readouterr().err
    assert code == 130, err
    assert "Traceback" not in err and "Exception ignored" not in err
    assert len(calls) == 1  # stopped where it landed, not after the six loops


def _as_at_a_terminal() -> None:
    """In the child before it runs: the interrupt at its default and not blocked, as a
    command typed at a terminal has it (a suite started in the background, or by a worker
    that ignores it, passes it on ignored, and the command would rightly never see it)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def _run_apart(script: str, timeout: float = 120.0):
    """``script`` in a Python of its own, in a process group of its own (its interrupts
    reach no one else), with the interrupt as at a terminal: its exit code, output and
    wall time [-, -, s]."""
    env = {**os.environ, "PYTHONPATH": SRC}
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(script)], env=env,
                         capture_output=True, text=True, timeout=timeout,
                         start_new_session=True, preexec_fn=_as_at_a_terminal)
    return out.returncode, out.stdout + out.stderr, time.monotonic() - t0


@pytest.mark.skipif(not hasattr(os, "kill"), reason="needs kill")
def test_an_interrupt_that_lands_in_the_first_collection_is_not_lost():
    """The command line holds back the interpreter's first collection and restores its
    thresholds in a callback of it: a Ctrl-C that came during that collection ran its
    handler in the callback, where Python ignores it ("Exception ignored in ...
    restore"); a sweep interrupted half a second after its start, while it imported,
    ran to its end and exited 0."""
    code, out, _ = _run_apart("""
        import gc, os, subprocess, time
        from tcpmm.cli._collector import START_THRESHOLD
        import tcpmm.cli  # holds the first collection back until its callback
        gc.disable()  # the collection is this script's, not the allocations'
        junk = [[] for _ in range(3_000_000)]  # a collection long enough to land in
        assert gc.get_threshold()[0] == START_THRESHOLD, "no collection held back"
        subprocess.Popen(["sh", "-c", f"sleep 0.2; kill -INT {os.getpid()}"])
        t0 = time.monotonic()
        try:
            while time.monotonic() - t0 < 3.0:
                gc.collect()
                time.sleep(0.05)  # the command's own work between collections
            print("ran on")
        except KeyboardInterrupt:
            print("stopped")
        """)
    assert code == 0, out
    assert "stopped" in out and "Exception ignored" not in out, out


@pytest.mark.parametrize("interrupted", [True, False])
def test_the_watcher_tells_an_interrupt_that_came_while_it_was_ignored(interrupted):
    """The sweep ignores the interrupt while its workers start, so that they inherit the
    ignore; a watcher in the same process group tells whether a Ctrl-C came meanwhile."""
    code, out, _ = _run_apart(f"""
        import os, signal, time
        from tcpmm.whatif.sweep.cluster import interrupt_watch
        watch = interrupt_watch()
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        if {interrupted}:
            os.killpg(0, signal.SIGINT)
        time.sleep(0.3)
        print("interrupted:", watch())
        """)
    assert code == 0, out
    assert f"interrupted: {interrupted}" in out


@pytest.mark.skipif(not hasattr(os, "killpg"), reason="needs process groups")
def test_a_ctrl_c_while_the_sweeps_workers_start_stops_it():
    """A Ctrl-C while a sweep's local Dask workers started (the first two seconds or so)
    was ignored with them: the sweep ran to its end and exited 0. The terminal's Ctrl-C
    is sent here to the whole group as the workers start; the sweep stops with 130 and one
    line, the variants computed so far kept."""
    code, out, _ = _run_apart("""
        import os, signal, sys
        import distributed
        from tcpmm.cli import main
        real = distributed.LocalCluster

        def starting(*args, **kwargs):
            os.killpg(0, signal.SIGINT)  # the terminal's Ctrl-C, as the workers start
            return real(*args, **kwargs)

        distributed.LocalCluster = starting
        sys.exit(main(["sweep", "builtin:vmc", "-p", "X.servo.position_gain=20:60:0.2",
                       "--circle", "5,6000", "--workers", "2", "-o", sys.argv[0] + "_o"]))
        """.replace('sys.argv[0] + "_o"', repr(str(Path(os.environ.get("TMPDIR", "/tmp"))
                                                  / f"tcpmm_sweep_{os.getpid()}"))))
    assert code == 130, out[-3000:]
    assert "Traceback" not in out and "stopped:" in out, out[-3000:]
