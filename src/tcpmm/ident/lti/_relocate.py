"""Pole relocation of vector fitting, a start for the transfer-function fit that puts the
poles where the response is large.

Vector fitting (Gustavsen and Semlyen 1999, relaxed as in Gustavsen 2006) fits
``sigma(x) H(x) ~ p(x)`` with ``sigma = d + sum c_k / (x - a_k)`` and ``p`` rational on
the same poles ``a_k``; both are linear in their coefficients, and the zeros of ``sigma``
(the eigenvalues of ``A - b c^T / d`` for a real state-space form ``(A, b)`` of the poles)
are the poles of the next step. The relaxation (``d`` free, ``sum Re sigma = N`` instead
of ``d = 1``) keeps the step from shrinking ``sigma`` towards zero. Bins count alike, so
what is minimised is the absolute error ``|H_model - H|``, dominated by the large part of
the response: the opposite of the fit's relative error, which is why it is a start worth
having. Everything is in the normalised frequency ``x = s / omega_0`` of
:mod:`~tcpmm.ident.lti._tfcore`.
"""

from __future__ import annotations

import numpy as np

#: Most relocation steps, as scikit-rf's VectorFitting takes. The poles mostly settle
#: within twenty, but on coarse or noisy bins they can wander for tens of steps [-].
RELOCATIONS = 100
#: Relative change of the poles below which the relocation has settled [-].
SETTLED = 1e-6


def start_poles(n: int, x_lo: float, x_hi: float) -> list[np.ndarray]:
    """Pole pairs of damping 0.01 log-spaced over the band, and, if ``n`` is odd, one real
    pole at the band's centre or (a second start) at its low end, where an integrating
    response wants it; relocation from the two may settle in different places [-]."""
    mags = np.geomspace(x_lo, x_hi, n // 2) if n >= 2 else np.zeros(0)
    p = [m * (-0.01 + 1j) for m in mags]
    if n % 2 == 0:
        return [np.asarray(p, complex)]
    return [np.asarray([*p, -r + 0j], complex) for r in (np.sqrt(x_lo * x_hi), x_lo)]


def _basis(x, up):
    """Real-coefficient partial fractions of the poles ``up`` (upper half plane and real
    ones): one column per real pole, two per conjugate pair [-]."""
    cols = []
    for p in up:
        if p.imag == 0:
            cols.append(1 / (x - p.real))
        else:
            a, b = 1 / (x - p), 1 / (x - np.conj(p))
            cols += [a + b, 1j * (a - b)]
    return np.array(cols).T


def _state(up):
    """Real ``(A, b)`` whose ``(xI - A)^-1 b`` are the columns of :func:`_basis` [-]."""
    n = sum(1 if p.imag == 0 else 2 for p in up)
    A, b, i = np.zeros((n, n)), np.zeros(n), 0
    for p in up:
        if p.imag == 0:
            A[i, i], b[i] = p.real, 1.0
            i += 1
        else:
            A[i : i + 2, i : i + 2] = [[p.real, p.imag], [-p.imag, p.real]]
            b[i] = 2.0
            i += 2
    return A, b


def _upper(z) -> np.ndarray:
    """Roots as real ones and the upper member of each conjugate pair, mirrored into the
    left half plane (a stable fit is wanted) [-]."""
    z = np.where(z.real > 0, -z.real + 1j * z.imag, z)
    real = np.abs(z.imag) <= 1e-12 * np.abs(z)
    return np.r_[z[real].real + 0j, z[~real & (z.imag > 0)]]


def _step(x, H, up):
    """One relaxed relocation: the zeros of ``sigma``, or None if the step is singular."""
    phi = _basis(x, up)
    n, N = phi.shape[1], x.size
    M = np.hstack([phi, np.ones((N, 1)), -H[:, None] * phi, -H[:, None]])
    M = np.vstack([M.real, M.imag])
    # the relaxation row, scaled to weigh as much as the data
    row = np.r_[np.zeros(n + 1), np.sum(phi, axis=0).real, N] * np.linalg.norm(H) / N
    M = np.vstack([M, row])
    rhs = np.r_[np.zeros(2 * N), np.linalg.norm(H)]
    sc = np.linalg.norm(M, axis=0)
    sc[sc == 0] = 1.0
    sol = np.linalg.lstsq(M / sc, rhs, rcond=None)[0] / sc
    c, d = sol[n + 1 : 2 * n + 1], sol[-1]
    if not np.all(np.isfinite(sol)) or abs(d) < 1e-8 * max(np.max(np.abs(c), initial=0), 1):
        return None
    A, b = _state(up)
    return _upper(np.linalg.eigvals(A - np.outer(b, c) / d))


def relocated_poles(x, H, n: int, start: np.ndarray | None = None) -> np.ndarray | None:
    """Poles that vector fitting relocates from log-spaced starts.

    Parameters
    ----------
    x : ndarray
        Normalised frequencies ``j omega / omega_0`` of the bins, increasing [-].
    H : ndarray
        Complex response at ``x`` [SI].
    n : int
        Number of poles [-].
    start : ndarray, optional
        Starting poles, one of :func:`start_poles` (the first when omitted) [-].

    Returns
    -------
    ndarray or None
        ``n`` stable poles in ``x`` (conjugate pairs both given) where they settle, or after
        :data:`RELOCATIONS` steps; None if a step was singular [-].
    """
    up = _upper(start_poles(n, x[0].imag, x[-1].imag)[0] if start is None else start)
    if up.size == 0:
        return None
    with np.errstate(all="ignore"):
        for _ in range(RELOCATIONS):
            try:
                new = _step(x, H, up)
            except np.linalg.LinAlgError:
                return None
            if new is None or not np.all(np.isfinite(new)):
                return None
            settled = new.size == up.size and np.all(
                np.abs(np.sort_complex(new) - np.sort_complex(up)) <= SETTLED * np.abs(new))
            up = new
            if settled:
                break
    return np.r_[up, np.conj(up[up.imag != 0])]


def partial_fraction_response(x, H, poles) -> np.ndarray:
    """Least-squares response ``d + sum r_k / (x - p_k)`` of the poles at ``x``, the model
    of vector fitting with a constant term [SI]."""
    up = poles[poles.imag >= 0]
    phi = np.hstack([_basis(x, up).reshape(x.size, -1), np.ones((x.size, 1))])
    M = np.vstack([phi.real, phi.imag])
    coef = np.linalg.lstsq(M, np.r_[H.real, H.imag], rcond=None)[0]
    return phi @ coef
