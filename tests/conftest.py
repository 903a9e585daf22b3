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
