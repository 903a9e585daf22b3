"""A YAML boolean where a schema wants a number: ``current_limit: true`` reads as 1 A under
pydantic's lax numbers, a value the user never wrote; refused with its key path instead."""

from __future__ import annotations

import types
import typing

from pydantic import BaseModel

from .._validate import is_number_text
from ..errors import InputError
from .keyunits import name_unit


def _leaves(annotation) -> list:
    """The plain types and generics a field's annotation admits (unions, optionals and
    ``Annotated`` opened) [-]."""
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _leaves(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        return [t for a in typing.get_args(annotation) for t in _leaves(a)]
    return [annotation]


def _numeric(leaves) -> bool:
    """Whether a field takes numbers and no booleans [-]."""
    plain = [typing.get_origin(t) or t for t in leaves]
    return not any(t in (bool, typing.Any, object) for t in plain) and any(
        t in (int, float) for t in plain)


def _numbers_only(leaves) -> bool:
    """Whether a field takes numbers (or nothing) and no text [-]."""
    plain = [typing.get_origin(t) or t for t in leaves]
    return any(t in (int, float) for t in plain) and all(
        t in (int, float, type(None)) for t in plain)


def _models(leaves) -> list[type[BaseModel]]:
    return [t for t in leaves if isinstance(t, type) and issubclass(t, BaseModel)]


def _items(leaves, value):
    """The element types of a list or the value types of a dict a field admits, with the
    elements of ``value`` they apply to [-]."""
    for t in leaves:
        origin, args = typing.get_origin(t), typing.get_args(t)
        if origin in (list, tuple) and isinstance(value, list) and args:
            return _leaves(args[0]), list(enumerate(value))
        if origin is dict and isinstance(value, dict) and len(args) == 2:
            return _leaves(args[1]), list(value.items())
    return None, []


def refuse_bools(data, model_cls, path=()) -> None:
    """Raise :class:`InputError` (its ``column`` the key path) at the first boolean given
    where ``model_cls`` takes a number, in this mapping or any nested one.

    Parameters
    ----------
    data : dict
        A parsed YAML mapping [-].
    model_cls : type
        The pydantic model it is validated into [-].
    path : tuple
        Key path of ``data`` in its document [-].
    """
    if not isinstance(data, dict):
        return
    for key, value in data.items():
        field = model_cls.model_fields.get(key) if isinstance(key, str) else None
        if field is not None:
            _check_value(value, _leaves(field.annotation), (*path, key))


def _check_value(value, leaves, path) -> None:
    if isinstance(value, bool) and _numeric(leaves):
        where = ".".join(str(p) for p in path)
        unit = name_unit(str(path[-1]))
        units = f"in {unit} (the unit its name ends with)" if unit else "in SI units"
        raise InputError(f"{path[-1]} must be a number, not a boolean ({str(value).lower()} "
                         f"would read as {int(value)}); write the number, {units}",
                         column=where)
    if isinstance(value, str) and _numbers_only(leaves) and is_number_text(value):
        # pydantic would read '30.0' as 30: quoted, it is text, as machine.yaml holds
        raise InputError(f"{path[-1]} must be a number, not text ({value!r}); write it "
                         "without quotes", column=".".join(str(p) for p in path))
    if isinstance(value, dict):
        for m in _models(leaves):
            if all(k in m.model_fields for k in value):
                refuse_bools(value, m, path)
                break
    inner, elements = _items(leaves, value)
    for k, v in elements:
        _check_value(v, inner, (*path, k))
