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
    the README and the pages name study scripts; each must exist."""
    named = set()
    sources = [*(ROOT / "src").rglob("*.py"), ROOT / "README.md", *DOCS.rglob("*.md")]
    for f in sources:
        named.update(re.findall(r"\bdocs/[\w/]+\.(?:md|py)\b", f.read_text(encoding="utf-8")))
    assert named, "nothing names a docs page"
    missing = sorted(n for n in named if not (ROOT / n).is_file())
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
