import fcntl
import hashlib
import os
import pickle
import warnings
from pathlib import Path

import pytest

from tcpmm.machines.builtin import builtin_machine

# The run has a worker per core already (pytest -n): identify's axes and verdict, asked for
# one process per core, run here one after the other, in the commands the tests start too.
# The tests of the processes themselves ask for them by number.
os.environ.setdefault("TCPMM_JOBS", "1")


@pytest.fixture(scope="session")
def vmc():
    return builtin_machine()


@pytest.fixture(scope="session")
def xmech(vmc):
    return vmc.axes["X"].mechanics


@pytest.fixture(scope="session")
def vmc_linear():
    """The built-in machine as the paper models it: linear, no feedforward."""
    return builtin_machine(friction=False, k_ff=0.0)


@pytest.fixture(scope="session")
def unseen():
    """:mod:`studies.unseen`, whose random machines some known-answer cases use."""
    from studies import unseen

    return unseen


@pytest.fixture(scope="session")
def identify_unseen(unseen, once):
    """``identify(seed, index, ax, sweep_seed=0, shared=False, **options)``: axis ``ax`` of
    machine ``index`` of the unseen machines with play of seed ``seed``
    (:mod:`studies.unseen`), identified from its sweep and friction runs (``options`` go
    to ``identify_axis``); returns the machine, the axis, the identification and the
    warnings given on the way. ``shared``: once per test run, for tests that change
    nothing in the package on the way [-]."""
    from tcpmm.ident.pipeline import identify_axis
    from tcpmm.machines.virtual import FRICTION_SPEEDS, axis_config, virtual_friction, virtual_sweep

    def identify(seed, index, ax, sweep_seed=0, shared=False, **options):
        if shared:
            what = repr((seed, index, ax, sweep_seed, sorted(options.items())))
            key = "unseen_" + hashlib.sha1(what.encode()).hexdigest()
            return once(key, lambda: identify(seed, index, ax, sweep_seed, **options))
        true, _ = unseen.draw_machine(seed, index, backlash=True)
        a = true.axes[ax]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            idn = identify_axis(ax, virtual_sweep(a, name=ax, seed=sweep_seed),
                                axis_config(true, ax),
                                friction=virtual_friction(a, FRICTION_SPEEDS, name=ax),
                                **options)
        return true, a, idn, [str(w.message) for w in caught]

    return identify


@pytest.fixture(scope="session")
def identify_builtin(once):
    """``identify(ax, friction=True)``: axis ``ax`` of the built-in machine identified from
    its default sweep and friction runs, or, without ``friction``, the machine without
    friction from its sweep alone; returns the identification and the warnings given on
    the way. Once per test run: the tests of several modules read the same one [-]."""
    from tcpmm.ident.pipeline import identify_axis
    from tcpmm.machines.virtual import FRICTION_SPEEDS, axis_config, virtual_friction, virtual_sweep

    def make(ax, friction):
        m = builtin_machine(friction=friction)
        a = m.axes[ax]
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            runs = virtual_friction(a, FRICTION_SPEEDS, name=ax) if friction else None
            idn = identify_axis(ax, virtual_sweep(a, name=ax), axis_config(m, ax), friction=runs)
        return idn, [str(w.message) for w in caught]

    def identify(ax, friction=True):
        key = f"builtin_{ax}_{'friction' if friction else 'linear'}"
        return once(key, lambda: make(ax, friction))

    return identify


#: Reference machines of an independent simulator, beside the checkout (`../shared`).
BENCH_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"

#: The Sinumerik Operate trace of a speed loop [-].
SINUMERIK_TRACE = BENCH_DATA / "sinumerik" / "freq_trace.XML"


@pytest.fixture(scope="session")
def trace_fit(once):
    """``fit_frf`` of :data:`SINUMERIK_TRACE` with its defaults, once per test run: the
    tests of several modules read the same fit [-]."""
    from tcpmm.ident.lti import fit_frf
    from tcpmm.io.sinumerik import read_sinumerik_frf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the reader's note on the trace's bins
        return once("sinumerik_trace_fit", lambda: fit_frf(read_sinumerik_frf(SINUMERIK_TRACE)))


def bench_path(letter: str) -> Path:
    """Folder of reference machine ``letter``; fails under CI (``CI=true``) when missing,
    since the validation against it must run there, and skips elsewhere."""
    import os

    d = BENCH_DATA / f"bench_{letter}"
    if not d.is_dir():
        msg = f"reference machine data not found: expected {d} (../shared beside the checkout)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return d


#: The sample columns of a sweep record
SWEEP_SAMPLES = ("time_s", "excitation_A", "current_cmd_A", "motor_angle_rad", "scale_m",
                 "tcp_m")


def bench_x_alone(letter: str, change):
    """Reference machine ``letter``'s bundle with its X axis alone, whose sweep record is
    ``change(sweep)`` (a record as a recorder gone wrong would write it)."""
    import dataclasses

    from tcpmm.io.bundle import read_bundle

    b = read_bundle(bench_path(letter) / "bundle")
    x = b.axes["X"]
    return dataclasses.replace(b, axes={"X": dataclasses.replace(x, sweep=change(x.sweep))})


def refusal(bundle):
    """The ``SuspectModelError`` that identifying ``bundle`` (no verdict) raises; fails
    where it raises none."""
    from tcpmm.ident.gates.finding import SuspectModelError
    from tcpmm.ident.pipeline import identify_bundle

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(SuspectModelError) as refused:
            identify_bundle(bundle, verdict=False)
    return refused.value



def run_cli(capsys, *args):
    """``(exit code, stdout, stderr)`` of the command line run in-process on ``args``."""
    from tcpmm.cli import main

    code = main([str(a) for a in args])
    cap = capsys.readouterr()
    return code, cap.out, cap.err

@pytest.fixture(scope="session")
def once(tmp_path_factory):
    """``once(key, make)``: ``make()``, computed once per test run and shared by the workers
    of ``pytest -n`` through a pickle in the run's temporary folder (identifying a
    reference machine takes half a minute, and the tests of one are spread over the
    workers); a lock makes the others wait for the first [-]."""
    base = tmp_path_factory.getbasetemp()
    folder = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "once"
    folder.mkdir(exist_ok=True)
    memo = {}

    def get(key, make):
        if key not in memo:
            path = folder / f"{key}.pickle"
            with open(folder / f"{key}.lock", "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)
                if path.exists():
                    memo[key] = pickle.loads(path.read_bytes())
                else:
                    memo[key] = make()
                    part = path.with_suffix(".part")
                    part.write_bytes(pickle.dumps(memo[key]))
                    part.replace(path)
        return memo[key]

    return get
