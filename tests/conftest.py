import importlib.util
from pathlib import Path

import pytest

from tcpmm.builtin import builtin_machine


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
    """``examples/unseen_machines.py``, whose random machines some known-answer cases use."""
    spec = importlib.util.spec_from_file_location(
        "unseen_machines", Path(__file__).parents[1] / "examples" / "unseen_machines.py")
    um = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(um)
    return um
