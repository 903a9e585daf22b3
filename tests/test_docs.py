"""The documentation holds together: every page of the navigation exists, every page is in
the navigation, and every docs page or script the code, the README and the docs name
exists. (`make docs` builds the site strictly; this is the part that needs no MkDocs.)"""

import re
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def _nav_files(node) -> list[str]:
    if isinstance(node, str):
        return [node]
    if isinstance(node, dict):
        return [f for v in node.values() for f in _nav_files(v)]
    if isinstance(node, list):
        return [f for v in node for f in _nav_files(v)]
    return []


def _nav() -> list[str]:
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text(encoding="utf-8"))
    return _nav_files(config["nav"])


def test_every_nav_page_exists():
    missing = [f for f in _nav() if not (DOCS / f).is_file()]
    assert not missing, f"mkdocs.yml names pages that do not exist: {missing}"


def test_every_page_is_in_the_nav():
    pages = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    assert pages - set(_nav()) == set(), "pages left out of mkdocs.yml nav"


def test_the_docs_the_code_points_to_exist():
    """Error messages and docstrings name docs pages ("see docs/formats.md section 1"),
    the README and the pages name study scripts (``studies/NAME.py`` or ``-m
    studies.NAME``, a module or a package); each must exist."""
    named = set()
    sources = [*(ROOT / "src").rglob("*.py"), ROOT / "README.md", *DOCS.rglob("*.md")]
    for f in sources:
        text = f.read_text(encoding="utf-8")
        named.update(re.findall(r"\b(?:docs|studies)/[\w/]+\.(?:md|py)\b", text))
        named.update(f"studies/{m}.py" for m in re.findall(r"-m studies\.([a-z_]+)", text))
    assert named, "nothing names a docs page"
    # a study may be a package run by its __main__ (python -m studies.emps)
    missing = sorted(n for n in named if not (ROOT / n).is_file()
                     and not (ROOT / n.removesuffix(".py") / "__main__.py").is_file())
    assert not missing, f"named but missing: {missing}"


def test_sections_the_code_cites_exist():
    """``docs/formats.md section N`` and ``docs/model.md section N`` are headings of those
    pages."""
    cited = set()
    for f in (ROOT / "src").rglob("*.py"):
        cited.update(re.findall(r"docs/(formats|model)\.md section (\d)",
                                f.read_text(encoding="utf-8")))
    for page, n in cited:
        text = (DOCS / f"{page}.md").read_text(encoding="utf-8")
        assert re.search(rf"^## {n}\. ", text, flags=re.M), f"docs/{page}.md section {n}"


def test_the_formats_page_machine_yaml_parses():
    """The machine.yaml shown in docs/formats.md is one tcpmm reads (axis X of it)."""
    from tcpmm.io.bundle_schema import parse_machine_yaml

    text = (DOCS / "formats.md").read_text(encoding="utf-8")
    block = re.search(r"### machine\.yaml\s+```yaml\n(.*?)```", text, flags=re.S).group(1)
    x_only = block.split("\n  Y:")[0]
    m = parse_machine_yaml(x_only)
    assert m.axes["X"].lead_m == 0.010


def _readme_steps() -> list[str]:
    """The command lines of the README's five steps (comments dropped)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    part = text[text.index("## Command line in five steps"):]
    block = re.search(r"```sh\n(.*?)```", part, flags=re.S).group(1)
    return [ln.split("  #")[0].strip() for ln in block.splitlines()
            if ln.strip() and not ln.lstrip().startswith("#")]


def test_readme_steps_read_the_demo_by_variable_and_write_only_where_run():
    """Every step reads the demo through $D (absolute, set in the checkout) and writes
    relative names, so that from any folder the steps find their inputs and write only
    into that folder, not into the checkout."""
    lines = _readme_steps()
    setup, steps = lines[:2], [ln for ln in lines[2:] if ln.startswith("$T ")]
    assert setup[0].startswith("D=$(pwd)/out/demo") and "T=$(pwd)/.venv/bin/tcpmm" in setup[0]
    assert "cd " in setup[1] and len(steps) == 5
    for ln in steps:
        words = ln.split()
        assert not any(w.startswith("out/") for w in words), ln
        for flag in ("-o", "--report", "--plot"):
            if flag in words:
                target = words[words.index(flag) + 1]
                assert not target.startswith(("/", "$")), ln


def test_readme_steps_run_from_another_folder(tmp_path):
    """With a finished demo in the checkout (make demo), the five steps run in an empty
    folder and write only there."""
    import os
    import shutil
    import subprocess
    import sys

    demo = ROOT / "out" / "demo"
    exe = Path(sys.executable).with_name("tcpmm")
    if not (demo / "bundle").is_dir() or not exe.is_file() or shutil.which("bash") is None:
        import pytest

        pytest.skip("needs a finished demo in out/demo (make demo)")
    script = "\n".join(["set -e", f"D={demo} T={exe}", *_readme_steps()[1:]])
    env = {**os.environ, "HOME": str(tmp_path / "home")}
    before = sorted(p.name for p in demo.iterdir())
    subprocess.run(["bash", "-c", script.replace("~/tcpmm-work", str(tmp_path / "w"))],
                   cwd=tmp_path, env=env, check=True, capture_output=True)
    assert {p.name for p in (tmp_path / "w").iterdir()} == {"model.yaml", "ident",
                                                           "predicted.csv", "circle.png"}
    assert sorted(p.name for p in demo.iterdir()) == before


def test_the_measure_page_tdms_example_writes_a_bundle(tmp_path, monkeypatch):
    """The example of docs/measure.md, "From TDMS or MATLAB files", run on a TDMS file of
    the channels it names, writes a bundle that reads back with the samples mapped."""
    import math

    import numpy as np
    from nptdms import ChannelObject, TdmsWriter

    from tcpmm.io.bundle import read_bundle

    text = (DOCS / "measure.md").read_text(encoding="utf-8")
    part = text[text.index("## From TDMS or MATLAB files"):]
    code = re.search(r"```python\n(.*?)```", part, flags=re.S).group(1)
    machine = re.search(r"### machine\.yaml\s+```yaml\n(.*?)```",
                        (DOCS / "formats.md").read_text(encoding="utf-8"), flags=re.S)
    (tmp_path / "machine.yaml").write_text(machine.group(1).split("\n  Y:")[0])
    fs, n = 4000.0, 8000
    t = np.arange(n) / fs
    exc = 2.0 * np.sin(2 * np.pi * (5 * t + 0.5 * 395 * t**2 / t[-1]))
    angle = 0.5 * np.sin(2 * np.pi * 1.5 * t) + 1e-3 * exc
    scale_mm = angle * 10.0 / (2 * math.pi)
    channels = {"exc": exc, "icmd": 1.1 * exc, "enc": angle / (2 * math.pi / 10000),
                "ls": scale_mm * 1e3, "tcp": scale_mm * 1.0001}
    with TdmsWriter(tmp_path / "sweep_X.tdms") as w:
        w.write_segment([ChannelObject("Sweep", k, v, properties={"wf_increment": 1 / fs})
                         for k, v in channels.items()])
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/measure.md", "exec"), {})
    sweep = read_bundle(tmp_path / "bundle", check=False).axes["X"].sweep
    assert math.isclose(sweep.fs_hz, fs, rel_tol=1e-9)
    np.testing.assert_allclose(sweep.motor_angle_rad, angle, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sweep.scale_m, scale_mm * 1e-3, rtol=1e-9, atol=1e-15)
