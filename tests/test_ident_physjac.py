"""The analytic sensitivities of the physical model's FRFs against central differences."""

import numpy as np
import pytest

from tcpmm.ident.physical import PARAMS, log_sensitivities, model_frfs, residual_jacobian
from tcpmm.machines.builtin import builtin_machine

F_HZ = np.geomspace(2.0, 1500.0, 120)
STEP = 1e-6  # relative step of the central differences [-]


def nut_gain(f):
    return 1.0 - 0.4 * np.exp(-((np.log(f) - np.log(80.0)) ** 2))


def log_frf(mech, name, f_i, gain, p, factor):
    if p == "f_i":
        f_i = f_i * factor
    else:
        mech = mech.model_copy(update={p: getattr(mech, p) * factor})
    return np.log(model_frfs(mech, {name: F_HZ}, f_i, 1e-4, gain)[name])


@pytest.mark.parametrize("name", ["G_M", "G_T", "G_tcp"])
@pytest.mark.parametrize("gain", [None, nut_gain])
def test_sensitivities_match_central_differences(name, gain):
    mech = builtin_machine().axes["X"].mechanics
    f_i = 1500.0
    S = log_sensitivities(mech, name, F_HZ, f_i, gain)
    for i, p in enumerate(PARAMS):
        h = np.exp(STEP)
        fd = (log_frf(mech, name, f_i, gain, p, h)
              - log_frf(mech, name, f_i, gain, p, 1 / h)) / (2 * STEP)
        scale = max(np.abs(fd).max(), 1e-3)
        assert np.abs(S[i] - fd).max() <= 1e-5 * scale, p


def test_tied_parameters_move_with_the_table_mass():
    mech = builtin_machine().axes["X"].mechanics
    freqs = {"G_tcp": F_HZ}
    w = {"G_tcp": np.ones(F_HZ.size)}
    r = np.zeros(2 * F_HZ.size)
    free = residual_jacobian(mech, freqs, w, r, PARAMS[:-1], {})
    tied = residual_jacobian(mech, freqs, w, r, ["M_t", "C_t"], {"M_b": 1.0, "K_b": 1.0})
    i = {p: PARAMS.index(p) for p in ("M_t", "M_b", "K_b", "C_t")}
    np.testing.assert_allclose(tied[:, 0], free[:, i["M_t"]] + free[:, i["M_b"]]
                               + free[:, i["K_b"]])
    np.testing.assert_allclose(tied[:, 1], free[:, i["C_t"]])
