"""The axis kernel compiled ahead of time (tcpmm._compiled): the same numbers as numba's
kernel to the bit, a command that simulates without importing numba or scipy, and numba's
kernel wherever the compiled module cannot be had."""

import ast
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from tcpmm import _compiled as compiled
from tcpmm import builtin_machine, paper_circle_command
from tcpmm.errors import BuildNotice
from tcpmm.sim import kernel
from tcpmm.sim.inputs import kernel_inputs


def built_or_skip():
    """The compiled module in use; waits for it where another process (a test worker)
    builds it; skips where it cannot be built (no C compiler)."""
    path = compiled.module_path()
    deadline = time.monotonic() + 600.0
    while (not path.exists() and path.with_suffix(".lock").exists()
           and time.monotonic() < deadline):
        time.sleep(0.5)
    if path.exists() and compiled._chosen and compiled._chosen[0] is None:
        compiled._chosen.clear()  # chosen while another process was building it
    why = compiled.status()
    if not why.startswith("compiled module"):
        pytest.skip(f"no compiled kernel here: {why}")


def kernel_args(axis_name="X", rec_every=1):
    """Inputs of one axis of the paper's circle, as simulate_axis makes them."""
    command = paper_circle_command()
    axis = builtin_machine().axes[axis_name]
    t, pos = command.time_s, command.positions[axis_name]
    T_c = float(t[1] - t[0])
    n = int(np.floor((t[-1] - t[0]) / axis.servo.T_v + 1e-9)) + 1
    k = kernel_inputs(axis, pos, np.zeros(t.size), T_c, n, rec_every=rec_every)
    return list(k.as_args(k.empty_record()))


@pytest.mark.parametrize("axis_name", ["X", "Y"])
def test_same_numbers_as_numbas_kernel(axis_name):
    built_or_skip()
    a, b = kernel_args(axis_name), kernel_args(axis_name)
    xa, xb = compiled.run_axis(*a), kernel.run_axis(*b)
    assert np.array_equal(a[8], b[8]) and np.array_equal(xa, xb)
    assert np.ptp(a[8][2]) > 0.01  # the circle was run: the TCP travels 70 mm


def test_a_strided_array_is_given_as_a_contiguous_copy_and_written_back(monkeypatch):
    """Neither the module (it would read it as contiguous) nor numba (it would compile the
    kernel anew for that layout, about two minutes) is given a strided array."""
    built_or_skip()

    def numbas(*args):
        raise AssertionError("numba's kernel called")

    monkeypatch.setattr(kernel, "run_axis", numbas)
    a, b = kernel_args(), kernel_args()
    a[3] = np.asfortranarray(np.stack([a[3], a[3]]))[0]  # an input
    a[8] = np.stack([a[8], a[8]], axis=-1)[..., 0]  # the record, written by the kernel
    assert not (a[3].flags.c_contiguous or a[8].flags.c_contiguous)
    compiled.run_axis(*a)
    compiled.run_axis(*b)
    assert np.array_equal(a[8], b[8]) and np.any(b[8] != 0.0)


def test_argument_types_it_was_not_built_for_go_to_numba(monkeypatch):
    built_or_skip()
    calls = []
    monkeypatch.setattr(kernel, "run_axis", lambda *args: calls.append(args))
    a = kernel_args()
    a[7] = a[7].astype(np.int32)  # built for int64
    compiled.run_axis(*a)
    assert len(calls) == 1 and calls[0][7].dtype == np.int32
    compiled.run_axis(*kernel_args())
    assert len(calls) == 1


PROGRAM = Path(__file__).resolve().parents[1] / "examples" / "circle_r35_f5000.nc"


@pytest.mark.parametrize(("source", "suffix"), [("--command", ".csv"), ("--gcode", ".csv"),
                                               ("--gcode", ".parquet")])
def test_a_simulating_command_imports_neither_numba_nor_scipy(tmp_path, source, suffix):
    """Nor pandas, which pyarrow imports to look at numpy arrays it is given (0.4 s)."""
    built_or_skip()
    if source == "--command":
        from tcpmm.path import write_command_csv

        write_command_csv(paper_circle_command(), given := tmp_path / "cmd.csv")
    else:
        given = PROGRAM
    run = tmp_path / f"run{suffix}"
    # nor numpy.ma (8 ms), which np.unique imports
    assert heavy_imports(["simulate", "builtin:vmc", source, str(given), "-o", str(run)],
                         also=("numpy.ma",)) == []
    assert run.stat().st_size > 0


def heavy_imports(args: list, also: tuple = ()) -> list:
    """The heavy libraries (and the modules ``also``) that ``tcpmm ARGS``, run in a new
    process, imported."""
    heavy = ("numba", "scipy", "pandas", "matplotlib", "llvmlite", *also)
    code = (f"import sys; from tcpmm.cli import main; main({args!r}); "
            f"print(sorted(m for m in {heavy!r} if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    return ast.literal_eval(out.strip().splitlines()[-1])


def test_the_interpolation_is_numbas_to_the_bit(monkeypatch):
    """The paper's circle as an NC program, interpolated with the look-ahead, profiles and
    sampling of the compiled module and with numba's."""
    from tcpmm.path import program_to_command, read_program

    built_or_skip()
    program = read_program(PROGRAM)
    ours = program_to_command(program)
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = program_to_command(program)
    assert ours.time_s.size > 1000
    for axis, pos in theirs.positions.items():
        assert np.array_equal(ours.positions[axis], pos)


def test_the_g_code_lexer_is_numbas_to_the_bit(monkeypatch):
    """Plain moves of random numbers, absolute and incremental, in mm and inches, lexed
    and executed by the compiled module and by numba."""
    from tcpmm.path import parse_gcode
    from tcpmm.path.gcode_fast import scan_chunk

    built_or_skip()
    rng = np.random.default_rng(5)
    blocks = []
    for scale in (500.0, 5.0, 10.0):  # absolute mm, incremental mm, absolute inches
        v = rng.uniform(-scale, scale, (200, 3))
        blocks.append([f"G1 X{x:.{k}f} Y{y:.4f} Z{z:.9f}"
                       for (x, y, z), k in zip(v, rng.integers(0, 9, 200), strict=True)])
    text = "\n".join(["G21 G90 F3000", *blocks[0], "G91", *blocks[1], "G20 G90", *blocks[2]])
    assert (scan_chunk(text.split("\n"))[0][:, 0] == 1).sum() == 600  # all compiled
    ours = parse_gcode(text)
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = parse_gcode(text)
    assert len(ours) == 600 and repr(ours) == repr(theirs)


def test_the_corner_blends_are_numbas_to_the_bit(monkeypatch):
    """Random runs of straight blocks under G64 (turns of every size, reversals, collinear
    blocks, points) blended by the compiled module and by numba: the same lines and
    arcs."""
    from tcpmm.path.blend import blend_corners
    from tcpmm.path.segments import Line

    built_or_skip()
    rng = np.random.default_rng(11)
    pts = np.cumsum(rng.normal(size=(600, 3)) * 10.0 ** rng.uniform(-6, -2, (600, 1)), axis=0)
    pts[300:320] = pts[300]  # points: a line of no length turns nowhere
    pts[400:420] = pts[400] + np.outer(np.arange(20), [1e-4, 0.0, 0.0])  # straight on
    segs = [Line(tuple(a), tuple(b), 0.05, tolerance_m=float(t))
            for a, b, t in zip(pts[:-1], pts[1:], 10.0 ** rng.uniform(-7, -3, 599),
                               strict=True)]
    ours = blend_corners(segs, 2e-6)
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = blend_corners(segs, 2e-6)
    assert sum(type(s).__name__ == "Blend" for s in ours) > 400
    assert ours == theirs


def test_the_contour_search_is_numbas_to_the_bit(monkeypatch):
    """The three sensors of the paper's circle on the built-in machine against their
    command, signed in the plane and unsigned in space, searched by the compiled module
    and by numba."""
    from tcpmm import simulate
    from tcpmm.analysis.contour import distances_to_polyline

    built_or_skip()
    run = simulate(builtin_machine(), paper_circle_command())
    t = np.asarray(run.time_s, float)
    cmd = np.column_stack([run.axes[a].cmd for a in "XYZ"])
    qs = {s: np.column_stack([run.axes[a].sensor(s) for a in "XYZ"])
          for s in ("motor", "scale", "tcp")}

    def both():
        return [distances_to_polyline({k: q[:, :d] for k, q in qs.items()}, cmd[:, :d], t, t,
                                      0.2, d == 2) for d in (2, 3)]

    ours = both()
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = both()
    assert t.size > 1000 and np.ptp(ours[0]["tcp"][0]) > 1e-6
    for a, b in zip(ours, theirs, strict=True):
        for k in qs:
            np.testing.assert_array_equal(a[k][0].view(np.int64), b[k][0].view(np.int64))
            np.testing.assert_array_equal(a[k][1], b[k][1])


@pytest.mark.parametrize(("suffix", "program"), [(".parquet", False), (".csv", False),
                                                 (".parquet", True)])
def test_measuring_a_contour_imports_neither_numba_nor_scipy(tmp_path, suffix, program):
    """Nor pandas from a Parquet run (a CSV run is read with it), a program's with its
    integer columns nc_line and rapid too."""
    from tcpmm import simulate
    from tcpmm.path import program_to_command

    built_or_skip()
    command = program_to_command(PROGRAM) if program else paper_circle_command()
    simulate(builtin_machine(), command).write(run := tmp_path / f"r{suffix}")
    got = heavy_imports(["contour", str(run), "--plane", "XY", "--json"])
    assert got == ([] if suffix == ".parquet" else ["pandas"])


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """The choice made again, with the compiled modules kept in an empty folder and none
    in the package's."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(compiled, "_package_cache", lambda: tmp_path / "package")
    monkeypatch.setattr(compiled, "_chosen", [])
    return tmp_path


def test_a_failed_build_runs_numbas_kernel_and_is_not_tried_again(fresh, monkeypatch):
    calls = []

    def broken(path):
        calls.append(path)
        raise OSError("no C compiler")

    monkeypatch.setattr(compiled, "build", broken)
    assert "until the first run builds" in compiled.describe()  # describing builds nothing
    assert not calls
    with pytest.warns(BuildNotice):
        assert "its build failed: OSError: no C compiler" in compiled.status()
    a, b = kernel_args(), kernel_args()
    compiled.run_axis(*a)
    kernel.run_axis(*b)
    assert np.array_equal(a[8], b[8])
    monkeypatch.setattr(compiled, "_chosen", [])
    assert "its build failed" in compiled.status()
    assert len(calls) == 1  # the failure is kept beside the module's place
    assert list(fresh.rglob("*.failed"))
    monkeypatch.setattr(compiled, "_chosen", [])
    assert "build failed: OSError: no C compiler" in compiled.describe()


def test_a_build_in_another_process_is_not_waited_for(fresh, monkeypatch):
    monkeypatch.setattr(compiled, "build", lambda path: pytest.fail("built twice"))
    path = compiled.module_path()
    path.parent.mkdir(parents=True)
    path.with_suffix(".lock").touch()
    assert "being built by another process" in compiled.status()


def test_switched_off_by_the_environment(fresh, monkeypatch):
    monkeypatch.setenv("TCPMM_COMPILED", "0")
    monkeypatch.setattr(compiled, "build", lambda path: pytest.fail("built"))
    assert "TCPMM_COMPILED=0" in compiled.status()


def test_the_key_follows_the_kernels_sources(fresh, monkeypatch, tmp_path):
    before = compiled.module_path().name
    src = tmp_path / "pkg"
    for rel in compiled.KERNEL_SOURCES:
        (src / rel).parent.mkdir(parents=True, exist_ok=True)
        (src / rel).write_bytes((compiled._PKG / rel).read_bytes())
    monkeypatch.setattr(compiled, "_PKG", src)
    assert compiled.module_path().name == before
    with open(src / "sim" / "contact.py", "a") as f:
        f.write("\n# an edit\n")
    assert compiled.module_path().name != before


def _compiled_imports(sources) -> set:
    """The package's modules, as paths relative to it, that the given sources import at
    their tops and that hold compiled (``@njit``) functions."""
    import ast

    found = set()
    for rel in sources:
        base = rel.split("/")[:-1]
        tree = ast.parse((compiled._PKG / rel).read_text(encoding="utf-8"))
        for node in tree.body:
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                parts = base[:len(base) - node.level + 1] + (node.module or "").split(".")
            elif (node.module or "").startswith("tcpmm."):
                parts = node.module.split(".")[1:]
            else:
                continue
            path = compiled._PKG.joinpath(*parts).with_suffix(".py")
            if path.is_file() and "@njit" in path.read_text(encoding="utf-8"):
                found.add(path.relative_to(compiled._PKG).as_posix())
    return found


def test_the_key_covers_every_compiled_module_the_kernels_import():
    """A compiled function the kernel inlines from a module left out of the key would be
    edited without a new module being built: the old one would keep the old code."""
    assert "sim/contact.py" in _compiled_imports(["sim/frictionstep.py"])  # it sees imports
    missing = _compiled_imports(compiled.KERNEL_SOURCES) - set(compiled.KERNEL_SOURCES)
    assert not missing, f"add to KERNEL_SOURCES: {sorted(missing)}"


def test_a_new_build_deletes_all_but_the_most_recently_used_old_ones(fresh, monkeypatch):
    """An upgrade or an edit of the kernel builds a new module (about 1 MB): the others
    beyond the four most recently used go, with their failure records; locks stay."""
    monkeypatch.setattr(compiled, "build", lambda path: path.write_bytes(b"module"))
    path = compiled.module_path()
    path.parent.mkdir(parents=True)
    suffix = "".join(path.suffixes)
    for age in range(7):
        old = path.parent / f"_kernels_old{age}{suffix}"
        old.write_bytes(b"old")
        t = time.time() - 86400.0 * (age + 1)
        os.utime(old, (t, t))
        if age == 6:
            record = path.parent / f"_kernels_old{age}.cpython-x.failed"
            record.write_text("failed")
            os.utime(record, (t, t))
    (path.parent / "_kernels_other.lock").touch()
    compiled.module_path()  # naming it builds nothing
    assert len(list(path.parent.glob("_kernels_*"))) == 9
    with pytest.warns(BuildNotice):
        assert compiled._build_once(path) == "" and path.read_bytes() == b"module"
    left = sorted(p.name.split(".")[0] for p in path.parent.glob("_kernels_*"))
    assert left == sorted([path.name.split(".")[0], "_kernels_other"]
                          + [f"_kernels_old{age}" for age in range(4)])


def test_a_build_is_announced_and_the_command_line_shows_it(tmp_path, monkeypatch, capsys):
    """A build takes minutes on a fresh install; the process that starts one says so (a
    notice, not a fault), and the command line prints it as a note on stderr."""
    from tcpmm.cli import main
    from tcpmm.path import write_command_csv

    write_command_csv(paper_circle_command(), cmd := tmp_path / "cmd.csv")
    monkeypatch.setattr(compiled, "module_path", lambda: tmp_path / "k.so")
    monkeypatch.setattr(compiled, "build", lambda path: (_ for _ in ()).throw(OSError("no cc")))
    monkeypatch.setattr(compiled, "_chosen", [])
    with pytest.warns(BuildNotice, match="compiling the simulation kernel"):
        assert "its build failed" in compiled.status()
    (tmp_path / "k.failed").unlink()
    monkeypatch.setattr(compiled, "_chosen", [])
    assert main(["simulate", "builtin:vmc", "--command", str(cmd), "-o",
                 str(tmp_path / "run.csv")]) == 0
    out, err = capsys.readouterr()
    assert "compiling" not in out
    assert err.count("note: compiling the simulation kernel for this CPU") == 1


def test_the_friction_fits_run_compiled_to_numbas_bits_without_starting_numba(monkeypatch):
    """The pre-sliding fit's contact force along a path through a play, and the guideway
    friction that holds the nut on a flank, from the compiled module: an identification
    then never imports numba (its import and cache cost it about a second), and the forces
    are numba's to the bit."""
    from types import SimpleNamespace

    from tcpmm.ident.friction.preslidingfit import _contact_force
    from tcpmm.ident.steps.playrefit import bias_force
    from tcpmm.mechanics.friction import LuGreFriction, friction_params_array

    built_or_skip()
    lugre = LuGreFriction(fc_pos=20.0, fc_neg=22.0, fs_pos=28.0, fs_neg=26.0, vs=2e-3,
                          fv_pos=150.0, fv_neg=160.0, sigma0=2e6, sigma1=300.0)
    path = 1e-5 * np.sin(np.linspace(0.0, 12.0, 3001)) ** 3
    fr, mech = SimpleNamespace(guideway=lugre), SimpleNamespace(C_t=40.0)

    def both():
        return (_contact_force(friction_params_array(lugre), path, 1e-3, 4e-6),
                [bias_force(v, mech, fr) for v in (1e-4, 2e-3, 0.05)])

    ours = both()
    monkeypatch.setattr(compiled, "_chosen", [None, "numba's kernels (forced)"])
    theirs = both()
    assert np.ptp(ours[0]) > 20.0  # the contact slides both ways
    np.testing.assert_array_equal(ours[0].view(np.int64), theirs[0].view(np.int64))
    assert ours[1] == theirs[1]
    code = ("import sys, numpy as np; import tcpmm.cli.ident, tcpmm.ident.chain; "
            "from tcpmm.ident.friction.preslidingfit import _contact_force; "
            "from tcpmm.mechanics.friction import LuGreFriction, friction_params_array; "
            "p = friction_params_array(LuGreFriction(fc_pos=1.0, fc_neg=1.0, sigma0=1e5)); "
            "_contact_force(p, np.linspace(0.0, 1e-4, 50), 1e-3, 1e-6); "
            "print(sorted(m for m in ('numba', 'llvmlite') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert ast.literal_eval(out.strip().splitlines()[-1]) == []
