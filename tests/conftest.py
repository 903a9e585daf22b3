import pytest

from tcpmm.builtin import builtin_machine


@pytest.fixture(scope="session")
def vmc():
    return builtin_machine()


@pytest.fixture(scope="session")
def xmech(vmc):
    return vmc.axes["X"].mechanics
