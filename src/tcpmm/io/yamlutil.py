"""YAML files validated by pydantic models, with errors that name the key path and line.

A safe loader that rejects duplicate keys and reads ``1e-4`` as a number (as YAML 1.2
does); every validation problem is reported with its key path (``axes.X.servo.K_pp``)
and the line of that key.
"""

from __future__ import annotations

import re
from typing import Any

import yaml
from pydantic import ValidationError

from ..errors import InputError
from .keyunits import name_unit
from .text import read_text
from .yamlbools import refuse_bools

FORMATS = {
    "tcpmm-model/1": ("machine model", "give it where a model file is expected"),
    "tcpmm-bundle/1": ("measurement-bundle description", "run `tcpmm identify` on its folder"),
    "tcpmm-tf/1": ("transfer-function fragment", "read it with tcpmm.read_tf_fragment"),
}


class StrictLoader(yaml.SafeLoader):
    """Safe loader that rejects duplicate keys and reads 1e-4 as a number (YAML 1.2)."""

    def construct_mapping(self, node, deep=False):
        seen: dict[Any, int] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            line = key_node.start_mark.line + 1
            if key in seen:
                raise InputError(
                    f"key '{key}' appears twice (first at line {seen[key]}); "
                    "keep one, the second would silently replace the first",
                    file=self.name, line=line, column=str(key))
            seen[key] = line
        return super().construct_mapping(node, deep=deep)


StrictLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)


def key_lines(node, prefix=(), out=None) -> dict[tuple, int]:
    """Map every key path of a composed YAML node to its 1-based line; an item of a list
    is keyed by its index, as a validation error's place names it."""
    out = {} if out is None else out
    if isinstance(node, yaml.MappingNode):
        out.setdefault(prefix, node.start_mark.line + 1)
        for k, v in node.value:
            path = (*prefix, k.value)
            out[path] = k.start_mark.line + 1
            key_lines(v, path, out)
    elif isinstance(node, yaml.SequenceNode):
        for i, v in enumerate(node.value):
            out[(*prefix, str(i))] = v.start_mark.line + 1
            key_lines(v, (*prefix, str(i)), out)
    return out


def line_for(loc: tuple, lines: dict[tuple, int]) -> int | None:
    """Line of the deepest key of ``loc`` that the file has, a part of ``loc`` the file
    does not have passed over (the tag of a union, ``filters.0.notch.f_hz`` for a filter
    whose ``f_hz`` the file has under ``filters.0``) [-]."""
    at, best = (), lines.get(())
    for part in (str(p) for p in loc):
        if (*at, part) in lines:
            at = (*at, part)
            best = lines[at]
    return best


def error_loc(err: dict) -> tuple:
    """Key path of a pydantic error, down to the key that a mapping check's message names."""
    loc, data = tuple(err["loc"]), err.get("input")
    if err["type"] == "value_error" and isinstance(data, dict):
        named = [(m.start(), k) for k in data
                 if (m := re.search(rf"(?<!\w){re.escape(str(k))}(?!\w)", err["msg"]))]
        if named:
            loc = (*loc, min(named, key=lambda n: n[0])[1])
    return loc


#: pydantic's errors for a value that is no number where one is expected
_NOT_A_NUMBER = ("float_parsing", "float_type", "int_parsing", "int_type")
def _number_fix(loc, units: str) -> str:
    """What to write for a value that is no number at ``loc`` [-]."""
    for part in reversed([p for p in loc if isinstance(p, str)]):
        if (unit := name_unit(part)) is not None:
            return f"write the number alone, in {unit} (the unit its name ends with)"
    return f"write the number alone, {units}" if units else "write the number alone"


def describe(err: dict, hint: str = "", units: str = "") -> str:
    """A readable sentence for one pydantic error; ``units`` says in which units a number
    of the file is written where its key's name does not say [-]."""
    if err["type"] == "extra_forbidden":
        return "unknown key" + (f" ({hint})" if hint else "")
    if err["type"] == "missing":
        return "required key is missing"
    got = err.get("input")
    if err["type"].startswith("int_") and isinstance(got, float) and got == got:
        whole = f"{int(got)}" if got.is_integer() and abs(got) < 1e18 else "a whole number"
        return f"not a whole number (got {got!r}); write {whole}, with no decimal point"
    if err["type"] in _NOT_A_NUMBER:
        got = ("a list" if isinstance(got, list) else "a mapping" if isinstance(got, dict)
               else repr(got))
        return f"not a number (got {got}); {_number_fix(err['loc'], units)}"
    msg = err["msg"]
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    if isinstance(err.get("input"), dict | list):
        return msg
    return f"{msg} (got {err['input']!r})"


def check_format(data: dict, fmt: str, what: str, file, line=None) -> None:
    """Raise :class:`InputError` in one line when ``format:`` names another known format.

    Parameters
    ----------
    data : dict
        The parsed document [-].
    fmt : str
        The format the reader expects, e.g. ``tcpmm-model/1`` [-].
    what : str
        What the document should be, for the message [-].
    file : str or Path
        Name used in messages [-].
    line : int, optional
        Line of the ``format`` key [-].
    """
    got = data.get("format", fmt)
    if got == fmt or not isinstance(got, str) or got not in FORMATS:
        return  # the schema reports an unknown version, or a value that is no text
    noun, advice = FORMATS[got]
    raise InputError(f"this is a {noun} (format {got}), not a {what}; {advice}",
                     file=file, line=line, column="format")


def _tab_at(text: str, last: int | None) -> tuple[int, int] | None:
    """Line and column (1-based) of the first tab in the indentation of the last line up
    to ``last`` that indents with one [-]."""
    found = None
    for i, s in enumerate(text.splitlines(), 1):
        if last is not None and i > last:
            break
        if re.match(r" *\t\s*[^\s#]", s):
            found = (i, s.index("\t") + 1)
    return found


def load_yaml(text: str, file) -> tuple[Any, Any]:
    """Parse YAML text into ``(data, node)``; syntax errors name line and column."""
    loader = StrictLoader(text)
    loader.name = str(file)
    try:
        node = loader.get_single_node()
        data = loader.construct_document(node) if node is not None else None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = None if mark is None else mark.line + 1
        tab = _tab_at(text, line)
        if tab is not None:
            raise InputError("tab character in the indentation; YAML indents with spaces",
                             file=file, line=tab[0], column=tab[1]) from None
        raise InputError(f"not valid YAML: {exc.problem or exc}", file=file, line=line,
                         column=None if mark is None else mark.column + 1) from None
    finally:
        loader.dispose()
    return data, node


def _read_as(data) -> str:
    """What YAML made of a document that is no mapping, in words [-]."""
    if data is None:
        return "nothing (an empty file)"
    if isinstance(data, list):
        return "a list"
    if isinstance(data, str) and ("," in data or "\t" in data):
        return "plain text with commas or tabs (a table such as a CSV file?)"
    return f"a single {type(data).__name__} value"


def validate_yaml(text: str, model_cls, file, what: str, hint: str = "",
                  fmt: str | None = None, units: str = ""):
    """Parse YAML text and validate it into ``model_cls``.

    Parameters
    ----------
    text : str
        YAML text [-].
    model_cls : type
        Pydantic model of the document [-].
    file : str or Path
        Name used in messages [-].
    what : str
        What the document is, for messages ("machine description") [-].
    hint : str
        Where the valid keys are documented, for unknown-key messages [-].
    fmt : str, optional
        The ``format:`` value the document must have, see :func:`check_format` [-].
    units : str
        In which units a number is written where its key's name does not say, for the
        message on a value that is no number ("in SI units (docs/formats.md)") [-].
    """
    data, node = load_yaml(text, file)
    if not isinstance(data, dict):
        raise InputError(f"expected a mapping: {what}; the file reads as {_read_as(data)}, not "
                         "as `key: value` lines" + (f" ({hint})" if hint else ""), file=file)
    lines = key_lines(node)
    if fmt is not None:
        check_format(data, fmt, what, file, lines.get(("format",)))
    try:
        refuse_bools(data, model_cls)
    except InputError as exc:
        raise InputError(exc.message, file=file, line=line_for(exc.column.split("."), lines),
                         column=exc.column) from None
    try:
        return model_cls.model_validate(data)
    except ValidationError as exc:
        # unknown keys (typos) first, then the rest, each in file order
        errors = sorted(((error_loc(e), e) for e in exc.errors()),
                        key=lambda le: (le[1]["type"] != "extra_forbidden",
                                        line_for(le[0], lines) or 0))
        missing = [loc for loc, e in errors if e["type"] == "missing"]
        parts = []
        for loc, err in errors:
            key = ".".join(str(p) for p in loc) or "<top>"
            line = line_for(loc, lines)
            at = f" (line {line})" if line is not None else ""
            meant = _meant(loc, err, model_cls, missing, lines)
            parts.append(f"{key}{at}: {describe(err, hint, units)}{meant}")
        first = errors[0][0]
        raise InputError(f"{len(errors)} problem(s) in {what}: " + "; ".join(parts),
                         file=file, line=line_for(first, lines),
                         column=".".join(str(p) for p in first) or None) from None


def _meant(loc, err: dict, model_cls, missing, lines) -> str:
    """For an unknown key, the key it is most likely a typo of; empty for none [-].

    A key missing beside it comes first: renaming ``K_pp`` to ``K_p`` makes ``K_pp``
    missing, and ``K_vp``, as close but present already, is no fix.
    """
    if err["type"] != "extra_forbidden" or not loc:
        return ""
    name, parent = str(loc[-1]), tuple(str(p) for p in loc[:-1])
    gone = [str(m[-1]) for m in missing if tuple(str(p) for p in m[:-1]) == parent]
    there = {k[-1] for k in lines if len(k) == len(loc) and k[:-1] == parent}
    close = (_closest(name, gone, 0.6)
             or _closest(name, sorted(known_keys(model_cls) - there - {name}), 0.75))
    return f"; did you mean '{close}'?" if close else ""


def _closest(name: str, candidates, cutoff: float) -> str | None:
    """The candidate most like ``name`` at a similarity of ``cutoff`` or more; of equally
    similar ones the one equal but for case, then the one sharing the longest start
    (``K_p``: ``K_pp`` before ``K_vp``) [-]."""
    import difflib
    from itertools import takewhile

    def score(c):
        ratio = difflib.SequenceMatcher(None, name, c).ratio()
        same = zip(name, c, strict=False)  # the shorter one ends it
        start = sum(1 for _ in takewhile(lambda ab: ab[0] == ab[1], same))
        return (ratio, c.lower() == name.lower(), start)

    scored = [(score(c), c) for c in candidates]
    scored = [sc for sc in scored if sc[0][0] >= cutoff]
    return max(scored, key=lambda sc: sc[0])[1] if scored else None


def known_keys(model_cls, seen=None) -> set:
    """Every key a pydantic model and the models within it take, by name and alias [-]."""
    import typing

    from pydantic import BaseModel

    seen = set() if seen is None else seen
    if model_cls in seen:
        return set()
    seen.add(model_cls)
    out = set()
    for name, f in model_cls.model_fields.items():
        out |= {name, f.alias} - {None}
        todo = [f.annotation]
        while todo:
            t = todo.pop()
            if isinstance(t, type) and issubclass(t, BaseModel):
                out |= known_keys(t, seen)
            todo.extend(typing.get_args(t))
    return out


def read_yaml_model(path, model_cls, what: str, hint: str = "", fmt: str | None = None,
                    units: str = ""):
    """Read a YAML file and validate it into ``model_cls`` (see :func:`validate_yaml`)."""
    return validate_yaml(read_text(path, what), model_cls, path, what, hint, fmt, units)
