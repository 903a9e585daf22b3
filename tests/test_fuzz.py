"""Fuzzing the edges where the user's input comes in: NC programs of extreme numbers, model
files changed key by key, bundles with columns swapped, scaled (mA, degrees, ms) and cut
short. The property everywhere: a sane result, or one InputError naming the file and the
line or key; never another exception, never a hang, never a result outside physical
bounds.

A few dozen cases per target run in the normal suite; ``make fuzz`` runs 10 000
(``TCPMM_FUZZ_EXAMPLES``).
"""

from __future__ import annotations

import contextlib
import math
import os
import shutil
import signal
import warnings

import numpy as np
import pandas as pd
import pytest
import yaml
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError

EXAMPLES = int(os.environ.get("TCPMM_FUZZ_EXAMPLES", "0"))
FUZZ = settings(max_examples=EXAMPLES or 30, deadline=None, database=None,
                suppress_health_check=list(HealthCheck))
#: Longest a single case may take before it counts as a hang [s].
CASE_S = 20.0


class Hang(Exception):
    """A case ran longer than :data:`CASE_S`."""


@contextlib.contextmanager
def no_hang(seconds: float = CASE_S):
    """Raise :class:`Hang` in the main thread when the block runs longer than ``seconds``."""
    def hang(signum, frame):
        raise Hang(f"longer than {seconds:g} s")

    before = signal.signal(signal.SIGALRM, hang)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, before)


def one_line_error(err: InputError, file) -> None:
    """The error names ``file`` and, where given, a line or key, in one line."""
    event("refused")
    text = str(err)
    assert "\n" not in text.strip(), text
    assert err.file is not None and str(file) in str(err.file), text


# --- NC programs -----------------------------------------------------------------------

SANE = st.floats(-200, 200, allow_nan=False).map(lambda v: f"{v:.3f}")
NUMBERS = st.one_of(
    SANE, SANE, SANE, SANE,
    st.sampled_from(["0", "-0", "1e300", "0.0000001", ".", "-", "nan", "inf", "1.5.2",
                     "00012", "+3"]),
    st.integers(-300, 300).map(lambda k: f"{10.0 ** k:.{max(0, -k) + 2}f}"),  # written out
    st.floats(-1e30, 1e30, allow_nan=False).map(lambda v: f"{v:.6f}"),
)
FEEDS = st.sampled_from(["100", "1000", "5000", "5000", "0.001", "0.0000001", "1000000"])
COORD = st.one_of(SANE, SANE, NUMBERS)
MOVE = st.builds(lambda g, x, y, f: f"{g} X{x} Y{y} F{f}", st.sampled_from(["G1", "G0"]),
                 COORD, COORD, FEEDS)
LETTERS = st.sampled_from(list("XYZIJKRFPGMNS"))
G_WORDS = st.sampled_from(["G0", "G1", "G2", "G3", "G4", "G17", "G18", "G19", "G20", "G21",
                           "G61", "G64", "G90", "G91", "G9", "M30", "M3", "G999"])


@st.composite
def programs(draw):
    lines = ["G21 G90 G17"] if draw(st.booleans()) else []
    for _ in range(draw(st.integers(1, 5))):
        if draw(st.integers(0, 3)):
            lines.append(draw(MOVE))
            continue
        words = draw(st.lists(st.one_of(G_WORDS, st.builds(lambda a, b: a + b, LETTERS,
                                                            NUMBERS)), min_size=1, max_size=6))
        lines.append(" ".join(words))
    return "\n".join(lines) + "\n"


@FUZZ
@given(text=programs())
def test_fuzz_gcode(tmp_path_factory, text):
    from tcpmm.path import program_to_command

    prog = tmp_path_factory.mktemp("nc") / "p.nc"
    prog.write_text(text)
    with warnings.catch_warnings(), no_hang():
        warnings.simplefilter("ignore")
        try:
            cmd = program_to_command(prog)
        except InputError as err:
            one_line_error(err, prog)
            return
    event("interpolated")
    pos = np.array(list(cmd.positions.values()))
    assert np.all(np.isfinite(pos)) and np.all(np.isfinite(cmd.time_s)), text
    assert np.all(np.diff(cmd.time_s) > 0), text


# --- model files ------------------------------------------------------------------------

def _leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _leaves(v, (*path, k))
    else:
        yield path


@pytest.fixture(scope="module")
def model_text():
    from tcpmm.io.modelfile import dumps_machine, with_interpolation
    from tcpmm.machines.builtin import builtin_machine

    return dumps_machine(with_interpolation(builtin_machine("vmc")))


VALUES = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**12, 10**12),
    st.booleans(), st.none(), st.text(max_size=4),
    st.lists(st.floats(-10, 10, allow_nan=False), max_size=3),
    st.sampled_from([0, -1, 1e-300, 1e300, 1e-12, 1e12, "1e-4", "0x10", [], {}]),
)


def _short_step():
    from tcpmm.path.command import Command

    t = np.arange(40) * 1e-3
    return Command(time_s=t, positions={"X": np.minimum(t, 0.01) * 0.01})


@FUZZ
@given(data=st.data())
def test_fuzz_model_file(tmp_path_factory, model_text, data):
    from tcpmm.io.modelfile import read_machine
    from tcpmm.sim.simulate import simulate

    doc = yaml.safe_load(model_text)
    path = data.draw(st.sampled_from(sorted(_leaves(doc), key=str)))
    holder = doc
    for k in path[:-1]:
        holder = holder[k]
    holder[path[-1]] = data.draw(VALUES)
    f = tmp_path_factory.mktemp("model") / "m.yaml"
    f.write_text(yaml.safe_dump(doc, sort_keys=False))
    with warnings.catch_warnings(), no_hang():
        warnings.simplefilter("ignore")
        try:
            machine = read_machine(f)
            run = simulate(machine, _short_step())
        except InputError as err:
            one_line_error(err, f)
            assert err.line is not None or err.column is not None, str(err)
            return
    event("simulated, with faults" if run.meta["faults"] else "simulated")
    faults = run.meta["faults"]
    for name, a in run.axes.items():
        said = any(x["axis"] == name for x in faults)
        finite = all(np.all(np.isfinite(s)) for s in (a.cmd, a.scale, a.tcp, a.current))
        assert said or finite, f"{path}: axis {name} not finite and not said"


# --- bundles ----------------------------------------------------------------------------

CURRENTS, POSITIONS = ("current_cmd_A", "excitation_A"), ("motor_angle_rad", "scale_mm",
                                                          "tcp_mm")
#: Column scalings no physical gate may let pass: factor -> columns.
WRONG_UNITS = {1e3: ("current_cmd_A", "time_s"), 180.0 / math.pi: ("motor_angle_rad",)}


@pytest.fixture(scope="module")
def small_bundle(tmp_path_factory, vmc):
    from tcpmm.io.bundle import write_bundle
    from tcpmm.machines.virtual import bundle_machine_yaml, virtual_friction, virtual_sweep

    a = vmc.axes["X"]
    recs = {"sweep": virtual_sweep(a, duration_s=1.0, band_hz=(10.0, 1000.0), name="X"),
            "friction": virtual_friction(a, speeds_m_per_s=(0.002, 0.005, 0.01, 0.02),
                                         plateau_s=0.3, name="X")}
    return write_bundle({"machine": bundle_machine_yaml(vmc, ["X"]), "axes": {"X": recs}},
                        tmp_path_factory.mktemp("bundle") / "b")


@st.composite
def bundle_changes(draw):
    file = draw(st.sampled_from(["sweep.csv", "friction.csv"]))
    kind = draw(st.sampled_from(["swap", "scale", "truncate"]))
    if kind == "swap":
        return file, kind, tuple(draw(st.permutations(
            ["time_s", *CURRENTS, *POSITIONS]))[:2])
    if kind == "scale":
        col = draw(st.sampled_from(["time_s", *CURRENTS, *POSITIONS]))
        return file, kind, (col, draw(st.sampled_from([1e3, 1e-3, 180.0 / math.pi, -1.0])))
    return file, kind, draw(st.integers(0, 300))


def _must_refuse(file, kind, what) -> bool:
    """Changes that leave a bundle physically absurd, which no gate may pass."""
    if kind == "swap":
        a, b = what
        return (a in CURRENTS and b in POSITIONS[:2]) or (b in CURRENTS and a in POSITIONS[:2])
    if kind == "scale":
        col, k = what
        return col in WRONG_UNITS.get(k, ())
    return False


@FUZZ
@given(change=bundle_changes())
def test_fuzz_bundle_columns(tmp_path_factory, small_bundle, change):
    from tcpmm.ident.chain import check_records
    from tcpmm.ident.options import IdentifyOptions
    from tcpmm.io.bundle import read_bundle

    file, kind, what = change
    root = tmp_path_factory.mktemp("fuzzb") / "b"
    shutil.copytree(small_bundle, root)
    f = root / "X" / file
    table = pd.read_csv(f)
    if kind == "swap":
        if not set(what) <= set(table.columns):
            return event("no such columns")
        table = table.rename(columns={what[0]: what[1], what[1]: what[0]})
    elif kind == "scale":
        if what[0] not in table.columns:
            return event("no such column")
        table[what[0]] = table[what[0]] * what[1]
    else:
        table = table.iloc[:what]
    table.to_csv(f, index=False, float_format="%.15g")
    with warnings.catch_warnings(), no_hang():
        warnings.simplefilter("ignore")
        try:
            check_records(read_bundle(root), IdentifyOptions())
        except InputError as err:
            one_line_error(err, root)
            return
    event("passed")
    assert not _must_refuse(file, kind, what), f"{file} {kind} {what} passed the gates"
