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


def jacobian_reference(mech, freqs, weights, residual, names, tied, f_i=None, gain=None,
                       pairs=None):
    """:func:`residual_jacobian` from the sensitivities of every parameter."""
    row = {p: i for i, p in enumerate(PARAMS)}
    blocks = []
    for k, f in freqs.items():
        d = log_sensitivities(mech, k, f, f_i, gain)
        if pairs is not None:
            g, n = pairs[k], f.size // 2
            d = (g[:n] * d[:, :n] + g[n:] * d[:, n:]) / (g[:n] + g[n:])
        d = d * weights[k]
        blocks += [d.real, d.imag]
    S = np.concatenate(blocks, axis=1)
    if tied:
        S[row["M_t"]] += sum(S[row[p]] for p in tied)
    J = S[[row[p] for p in names]].T
    J[~np.isfinite(J).all(axis=1) | (residual == 1e3)] = 0.0
    return np.ascontiguousarray(J)


def same_bits(a, b):
    """Equal to the bit, the sign of zero and NaNs included."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("name", ["G_M", "G_T", "G_tcp"])
@pytest.mark.parametrize("params", [PARAMS[::-1], ("K_t",), ("f_i", "J_m", "M_h"), ("C_b",)])
def test_rows_left_out_leave_the_others_to_the_bit(name, params):
    mech = builtin_machine().axes["X"].mechanics
    full = log_sensitivities(mech, name, F_HZ, 1500.0, nut_gain)
    some = log_sensitivities(mech, name, F_HZ, 1500.0, nut_gain, params)
    assert same_bits(some, full[[PARAMS.index(p) for p in params]])


@pytest.mark.parametrize("names, tied", [
    (PARAMS[:-1], {}), (PARAMS, {}), (("M_t", "C_t"), {"M_b": 1.0, "K_b": 1.0}),
    (("K_t", "J_m", "f_i"), {}), (("C_t", "K_L"), {"M_h": 1.0})])
def test_jacobian_to_the_bit_of_all_rows(names, tied):
    mech = builtin_machine().axes["X"].mechanics
    freqs = {"G_M": F_HZ, "G_T": F_HZ, "G_tcp": F_HZ}
    rng = np.random.default_rng(3)
    pairs = {k: rng.uniform(0.5, 1.5, F_HZ.size) + 0.1j for k in freqs}
    for p, size in ((None, F_HZ.size), (pairs, F_HZ.size // 2)):
        w = {k: rng.uniform(0.0, 2.0, size) for k in freqs}
        r = np.zeros(6 * size)
        r[::7] = 1e3
        assert same_bits(residual_jacobian(mech, freqs, w, r, names, tied, 1500.0, nut_gain, p),
                         jacobian_reference(mech, freqs, w, r, names, tied, 1500.0, nut_gain, p))


@pytest.mark.parametrize("name, none_of", [
    ("G_M", ("M_h", "C_h", "K_h")), ("G_T", ("J_m", "B_m", "M_h", "C_h", "K_h", "f_i")),
    ("G_tcp", ("J_m", "B_m", "J_L", "B_L", "K_L", "K_t", "f_i"))])
def test_a_parameter_an_frf_does_not_depend_on_has_a_row_of_zeros(name, none_of):
    """The row of a parameter outside an FRF's path is zero, as its central differences
    are, and those of the parameters on the path are not."""
    S = log_sensitivities(builtin_machine().axes["X"].mechanics, name, F_HZ, 1500.0, nut_gain)
    for i, p in enumerate(PARAMS):
        assert (np.all(S[i] == 0.0) if p in none_of else np.abs(S[i]).max() > 1e-9), p
