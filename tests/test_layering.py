"""The floors of the house: which of tcpmm's modules may import which.

From the ground up (a floor imports its own and the ones below it, never one above):

* ground -- :mod:`tcpmm.errors`, :mod:`tcpmm.units`, ``_validate``, ``_threads``, ``_heap``,
  ``_numba_cache``, ``_compiled`` with ``_pycc`` (the compiled kernels), and the data types
  and maths that readers and fits share: :mod:`tcpmm.frfdata` and :mod:`tcpmm.pade`;
* the plant -- ``mechanics/``, then ``servo/`` on it;
* data in and out -- ``io/``, ``path/`` (the interpolated command), :mod:`tcpmm.model` and
  :mod:`tcpmm.result`; they use one another (a model file names its interpolator settings,
  a command file is written atomically), and ``io.modelfile`` reads the ``builtin:`` names
  of ``machines.builtin``;
* the simulator -- ``sim/``; it judges the faults of the run it makes with
  ``analysis.runaway``, which stands on the ground and :mod:`tcpmm.result` alone;
* the work -- ``analysis/``, ``ident/``, ``uncertainty/``, ``machines/``, ``compensate/``,
  ``whatif/``;
* the edges -- ``plot/`` (the only importer of matplotlib, when a figure is drawn),
  ``report/``, :mod:`tcpmm.demo`, :mod:`tcpmm.api` and ``cli/``.

A result's ``.plot()`` imports ``tcpmm.plot`` inside the method, the one import up the
house that is allowed: the figures stay out of the import of the results. And no two
modules import one another, however far round: not at their tops, where the circle
breaks the import, and not inside a function either, where it would only be hidden.
"""

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "tcpmm"

GROUND = ("tcpmm.errors", "tcpmm.units", "tcpmm._validate", "tcpmm._threads", "tcpmm._heap",
          "tcpmm._numba_cache", "tcpmm._compiled", "tcpmm._pycc", "tcpmm.frfdata",
          "tcpmm.pade")
WORK = ("tcpmm.analysis", "tcpmm.ident", "tcpmm.uncertainty", "tcpmm.compensate",
        "tcpmm.whatif")
EDGES = ("tcpmm.plot", "tcpmm.report", "tcpmm.demo", "tcpmm.api", "tcpmm.cli")
ABOVE_DATA = ("tcpmm.sim", *WORK, "tcpmm.machines.virtual", "tcpmm.machines.paper", *EDGES)

#: Floor (a package or a module of the ground) -> the modules it must not import.
FLOORS = {
    **{g.removeprefix("tcpmm.") + ".py": ("tcpmm.mechanics", "tcpmm.servo", "tcpmm.io",
                                          "tcpmm.path", "tcpmm.model", "tcpmm.result",
                                          "tcpmm.machines", *ABOVE_DATA) for g in GROUND},
    "mechanics": ("tcpmm.servo", "tcpmm.io", "tcpmm.path", "tcpmm.model", "tcpmm.result",
                  "tcpmm.machines", *ABOVE_DATA),
    "servo": ("tcpmm.io", "tcpmm.path", "tcpmm.model", "tcpmm.result", "tcpmm.machines",
              *ABOVE_DATA),
    "io": ABOVE_DATA,
    "path": ABOVE_DATA,
    "model.py": ABOVE_DATA,
    "result.py": ABOVE_DATA,
    "sim": (*WORK, "tcpmm.machines", *EDGES),
    "analysis/runaway.py": ("tcpmm.sim", *WORK, "tcpmm.machines", *EDGES),
}
#: Floor -> the modules above it that it may import all the same, and why.
ALLOWED = {
    "sim": ("tcpmm.analysis.runaway",),  # the faults of a run, judged where it is made
}
#: Where a module may import tcpmm.plot at its top: the plots themselves and the edges.
PLOT_AT_TOP = ("plot", "report", "demo.py", "api.py", "cli")


def _names(node, package: tuple) -> set:
    if isinstance(node, ast.Import):
        return {a.name for a in node.names}
    base = package[: len(package) - node.level + 1] if node.level else ()
    stem = ".".join((*base, *(node.module.split(".") if node.module else ())))
    return {stem, *(f"{stem}.{a.name}" for a in node.names)}


def _package(path: Path) -> tuple:
    return path.relative_to(SRC.parent).parts[:-1]


def imported_modules(path: Path) -> set:
    """The tcpmm modules and packages the module at ``path`` imports, anywhere in it [-]."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            out |= _names(node, _package(path))
    return {m for m in out if m == "tcpmm" or m.startswith("tcpmm.")}


def top_level_imports(path: Path, in_functions: bool = False) -> set:
    """The tcpmm modules and packages imported when the module at ``path`` is: outside
    functions (with ``in_functions``, inside them too) and outside ``if TYPE_CHECKING`` [-]."""
    out = set()

    def visit(node):
        for child in ast.iter_child_nodes(node):
            if not in_functions and isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef,
                                                       ast.Lambda)):
                continue
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                continue
            if isinstance(child, (ast.Import, ast.ImportFrom)):
                out.update(_names(child, _package(path)))
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8")))
    return {m for m in out if m == "tcpmm" or m.startswith("tcpmm.")}


def module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph(in_functions: bool = False) -> dict:
    """``{module: {modules it imports at its top}}`` over the package; with
    ``in_functions``, what its functions import too, but for the figures of a ``.plot()``.
    An imported name that is not a module counts for the module it comes from [-]."""
    paths = {module_name(p): p for p in sorted(SRC.rglob("*.py"))}
    graph = {}
    for name, path in paths.items():
        found = set()
        for m in top_level_imports(path, in_functions):
            if in_functions and m.startswith("tcpmm.plot") and not name.startswith(EDGES):
                continue
            while m and m not in paths:
                m = m.rpartition(".")[0]
            if m and m != name:
                found.add(m)
        graph[name] = found
    return graph


def circles(graph: dict) -> list:
    """The strongly connected sets of more than one module (Tarjan, iterative) [-]."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]
        counter[0] += 1
        stack.append(root)
        on.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
    return out


def _floor_paths(floor: str) -> list:
    return sorted((SRC / floor).rglob("*.py")) if (SRC / floor).is_dir() else [SRC / floor]


@pytest.mark.parametrize("in_functions", [False, True], ids=["at the top", "anywhere"])
def test_no_import_circles(in_functions):
    """None at the top, where a circle breaks the import; and none through an import
    inside a function either, which would only hide one."""
    graph = import_graph(in_functions)
    assert len(graph) > 200 and graph["tcpmm.io.frffile"]  # the walk sees the package
    assert not circles(graph), f"modules that import one another: {circles(graph)}"


@pytest.mark.parametrize("floor", sorted(FLOORS))
def test_no_import_runs_up_the_house(floor):
    paths = _floor_paths(floor)
    assert paths and all(p.exists() for p in paths)
    allowed = ALLOWED.get(floor, ())
    up = {p.relative_to(SRC).as_posix(): sorted(
        m for m in imported_modules(p) - {"tcpmm.plot"}
        if m.startswith(FLOORS[floor]) and not m.startswith(allowed)
        and not m.startswith("tcpmm.plot.") and not m.startswith(module_name(p)))
        for p in paths}
    assert not {k: v for k, v in up.items() if v}, f"imports into an upper floor: {up}"


def test_plots_are_imported_at_the_top_only_by_the_edges():
    found = {}
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC)
        if rel.parts[0] in PLOT_AT_TOP:
            continue
        hits = sorted(m for m in top_level_imports(path)
                      if m == "tcpmm.plot" or m.startswith("tcpmm.plot."))
        if hits:
            found[rel.as_posix()] = hits
    assert not found, f"tcpmm.plot imported at the top below the edges: {found}"


def test_the_import_checks_can_fail(tmp_path, monkeypatch):
    """Relative and absolute imports up the house, at the top or in a function, and a
    circle of two modules through their top-level imports."""
    (tmp_path / "tcpmm" / "path").mkdir(parents=True)
    (tmp_path / "tcpmm" / "__init__.py").write_text("")
    (tmp_path / "tcpmm" / "path" / "__init__.py").write_text("")
    module = tmp_path / "tcpmm" / "path" / "interp.py"
    module.write_text("from ..sim import compiled\nfrom . import other\n\n"
                      "def f():\n    import tcpmm.sim.kernel\n")
    (tmp_path / "tcpmm" / "path" / "other.py").write_text(
        "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from . import x\n\n"
        "from .interp import f\n")
    monkeypatch.setitem(globals(), "SRC", tmp_path / "tcpmm")
    assert imported_modules(module) == {"tcpmm.sim", "tcpmm.sim.compiled", "tcpmm.sim.kernel",
                                        "tcpmm.path", "tcpmm.path.other"}
    assert top_level_imports(module) == {"tcpmm.sim", "tcpmm.sim.compiled", "tcpmm.path",
                                         "tcpmm.path.other"}
    assert circles(import_graph()) == [["tcpmm.path.interp", "tcpmm.path.other"]]
    (tmp_path / "tcpmm" / "path" / "other.py").write_text("def g():\n    from . import interp\n")
    assert not circles(import_graph())
    assert circles(import_graph(in_functions=True)) == [["tcpmm.path.interp",
                                                         "tcpmm.path.other"]]


def _module_of(path: Path) -> tuple[str, bool]:
    rel = path.relative_to(SRC.parent).with_suffix("")
    parts = list(rel.parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts), path.name == "__init__.py"


def _imported_from(node: ast.ImportFrom, module: str, is_package: bool) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".") if is_package else module.split(".")[:-1]
    base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _is_module(name: str) -> bool:
    p = SRC.parent.joinpath(*name.split("."))
    return p.with_suffix(".py").exists() or (p / "__init__.py").exists()


def private_imports() -> dict:
    """``{(module, name): importers}`` of every name with one leading underscore that a
    tcpmm module imports from another; private modules (``_compiled``) are not names."""
    out = {}
    for path in sorted(SRC.rglob("*.py")):
        module, is_package = _module_of(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom):
                continue
            source = _imported_from(node, module, is_package)
            if not source.startswith("tcpmm"):
                continue
            for alias in node.names:
                name = alias.name
                if (name.startswith("_") and not name.startswith("__")
                        and not _is_module(f"{source}.{name}")):
                    out.setdefault((source, name), []).append(module)
    return out


def test_no_private_name_crosses_a_module():
    """A name with a leading underscore belongs to its module; what another module needs
    is public, so that the reader knows what a change may break."""
    assert not private_imports(), private_imports()


def test_the_private_name_check_can_fail(tmp_path, monkeypatch):
    import sys

    pkg = tmp_path / "tcpmm"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def _helper():\n    pass\n")
    (pkg / "b.py").write_text("from .a import _helper\nfrom . import _compiled\n")
    (pkg / "_compiled.py").write_text("")
    monkeypatch.setattr(sys.modules[__name__], "SRC", pkg)
    assert private_imports() == {("tcpmm.a", "_helper"): ["tcpmm.b"]}
