"""The package's data files (``tcpmm/data/*.json``): values measured by a study, each file
with the command that reproduces it."""

from __future__ import annotations

import json
from importlib.resources import files

__all__ = ["read_data_json"]


def read_data_json(name: str) -> dict:
    """The JSON document ``tcpmm/data/NAME`` of the installed package [-].

    Parameters
    ----------
    name : str
        File name, e.g. ``model_error.json`` [-].
    """
    return json.loads(files("tcpmm").joinpath("data", name).read_text(encoding="utf-8"))
