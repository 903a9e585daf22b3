"""Work done side by side in forked processes (:mod:`tcpmm._forked`), as the axes of an
identification are: the results, warnings and errors of one piece after the other, in
the same order."""

import multiprocessing
import os
import warnings

import pytest

from tcpmm._forked import results_in_order, usable_jobs
from tcpmm.errors import InputError, InputWarning


def _axis(run, options):
    """A stand-in for one axis's identification: warns as identification does (the same
    text from the same place twice, another category), then returns or fails."""
    for _ in range(2):
        warnings.warn(InputWarning(f"axis {run}: {options}"), stacklevel=1)
    warnings.warn(f"axis {run}: numbers", RuntimeWarning, stacklevel=1)
    if run == "Y":
        raise InputError(f"axis {run}: no fit", column="scale_m")
    if run == "Z":
        raise ZeroDivisionError("a defect, not the input")
    return run, os.getpid()


def _collect(runs, jobs):
    """What each axis gave, with the warnings in the order they reached this process."""
    got = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        with results_in_order(_axis, runs, "look", jobs) as results:
            for result in results:
                try:
                    got.append(result())
                except InputError as exc:
                    got.append(("error", exc.format(), exc.column))
    return got, [(w.category, str(w.message)) for w in caught]


def test_side_by_side_gives_what_one_after_the_other_gives():
    runs = ["X", "Y", "A"]
    one, said_one = _collect(runs, 1)
    two, said_two = _collect(runs, 2)
    assert said_two == said_one
    # shown once per place as Python shows them, the failing axis's included
    assert said_one == [(InputWarning, "axis X: look"), (RuntimeWarning, "axis X: numbers"),
                        (InputWarning, "axis Y: look"), (RuntimeWarning, "axis Y: numbers"),
                        (InputWarning, "axis A: look"), (RuntimeWarning, "axis A: numbers")]
    assert [g[:1] for g in two] == [("X",), ("error",), ("A",)]
    assert two[1][1:] == one[1][1:] == ("column 'scale_m': axis Y: no fit", "scale_m")
    assert {two[0][1], two[2][1]}.isdisjoint({os.getpid()})  # in other processes
    assert one[0][1] == os.getpid()
    assert not multiprocessing.active_children()


def test_a_defect_in_one_axis_reaches_the_caller_and_no_process_is_left():
    with pytest.raises(ZeroDivisionError, match="a defect"):
        with results_in_order(_axis, ["X", "Z", "A"], "look", 2) as results:
            for result in results:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result()
    assert not multiprocessing.active_children()


def test_the_processes_asked_for_are_capped_by_the_axes(monkeypatch):
    assert usable_jobs(8, 2) == 2
    assert usable_jobs(1, 3) == 1
    monkeypatch.delenv("TCPMM_JOBS", raising=False)
    assert 1 <= usable_jobs(0, 3) <= 3
    assert usable_jobs(None, 1) == 1
    monkeypatch.setenv("TCPMM_JOBS", "1")  # as the test run sets it
    assert usable_jobs(0, 3) == usable_jobs(None, 3) == 1
    assert usable_jobs(2, 3) == 2  # asked for, it is not the environment's
    monkeypatch.setenv("TCPMM_JOBS", "two")
    with pytest.raises(InputError, match="TCPMM_JOBS='two': give a whole number"):
        usable_jobs(0, 3)


def test_the_play_an_axis_was_fitted_with_goes_between_processes():
    """An axis refitted with the nut's play carries the play's stiffness factor; it goes
    from the process that identified the axis to the parent and gives the same factors."""
    import pickle

    import numpy as np

    from tcpmm.ident.friction.playdf import play_gain

    gain = play_gain([10.0, 100.0, 1000.0], [1e-6, 3e-6, 8e-6], 4e-6, 10.0, 1e8)
    back = pickle.loads(pickle.dumps(gain))
    f = np.array([5.0, 20.0, 300.0, 2000.0])
    np.testing.assert_array_equal(back(f), gain(f))
    assert back(f)[0] == 1.0 and back(f)[1] < 1.0


def _dies(piece, shared):
    """A piece whose process is killed (as the system kills one out of memory)."""
    import signal

    if piece == "dies":
        os.kill(os.getpid(), signal.SIGKILL)
    return piece


def test_a_process_that_dies_is_an_error_not_a_wait():
    from tcpmm.errors import TcpmmError

    with pytest.raises(TcpmmError, match="ended before its work was done"):
        with results_in_order(_dies, ["X", "dies", "A"], None, 2) as results:
            assert results[0]() == "X"
            results[1]()
    assert not multiprocessing.active_children()


def test_a_result_that_cannot_go_between_processes_is_an_error():
    from tcpmm.errors import TcpmmError

    with pytest.raises(TcpmmError, match="could not be sent between processes"):
        with results_in_order(lambda piece, shared: (lambda: piece), ["X", "Y"], None,
                              2) as results:
            results[0]()
    assert not multiprocessing.active_children()


def test_an_interrupt_between_the_fork_and_the_work_is_left_to_the_parent(monkeypatch):
    """Ctrl-C reaches the whole process group, also a child that has only just been
    forked: it must not end it with a traceback of its own (it did, from inside
    multiprocessing's start-up, where the signal came before the child ignored it)."""
    import signal

    from tcpmm import _forked

    quiet = _forked._quiet_child

    def interrupted_first():
        os.kill(os.getpid(), signal.SIGINT)  # as the terminal would, just after the fork
        quiet()

    monkeypatch.setattr(_forked, "_quiet_child", interrupted_first)
    with results_in_order(lambda piece, shared: piece, ["X", "Y"], None, 2) as results:
        assert [r() for r in results] == ["X", "Y"]
    assert not multiprocessing.active_children()
