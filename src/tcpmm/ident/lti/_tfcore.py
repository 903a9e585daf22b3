"""Numerical core of the transfer-function fit: linear stage, stable sections, projection.

All functions work in the normalised frequency ``x = s / omega_0``. Past the linear stage
the denominator is kept as poles (or as section coefficients), not as an expanded
polynomial, so that far or nearly cancelling poles do not cost accuracy.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares


def upper_pairs(p: np.ndarray) -> np.ndarray:
    c = p[p.imag > 1e-9 * np.maximum(np.abs(p), 1e-300)]
    return c[np.argsort(np.abs(c))]


def _den_value(x, pn):
    d = np.ones_like(x)
    for p in pn:
        d = d * (x - p)
    return d


def tf_response(f_hz, bn, pn, omega0, k, delay_s):
    s = 2j * np.pi * f_hz
    x = s / omega0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        h = np.polyval(bn[::-1], x) / (_den_value(x, pn) * x**k)
    if delay_s:
        h = h * np.exp(-s * delay_s)
    return h


def sanathanan_koerner(x, Hd, w, nb, na, iterations, start=None, powers=None):
    """Levy start plus Sanathanan-Koerner iterations on the relative error.

    ``start`` (poles in ``x``) replaces Levy's first step ``A_prev = 1`` by
    ``A_prev = prod(x - start)``, as vector fitting starts from spread poles.

    Each step minimises ``sum (w / (|H| |A_prev|))^2 |B - H A|^2`` under ``||A|| = 1`` (in
    scaled coefficients): the numerator is projected out by QR, the denominator is the
    smallest right singular vector of what remains. Neither the leading nor the constant
    coefficient of ``A`` is pinned, so surplus poles may go to infinity or near zero.
    ``powers``, where given, holds ``x ** k`` in column ``k`` for ``k`` up to the larger
    degree at least, so that fits on the same bins compute them once.
    """
    if powers is None:
        powers = x[:, None] ** np.arange(max(nb, na) + 1)
    xb = np.ascontiguousarray(powers[:, : nb + 1])
    xa = np.ascontiguousarray(powers[:, : na + 1])
    base = w / np.abs(Hd)
    a_prev = np.ones(x.size) if start is None else _den_value(x, start)
    an = np.r_[np.zeros(na), 1.0]
    bn = np.zeros(nb + 1)
    h_prev = None
    # the real and imaginary parts of the weighted columns, written in place each step
    n, nc = x.size, nb + na + 2
    M = np.empty((2 * n, nc))
    for _ in range(max(1, iterations)):
        a_abs = np.abs(a_prev)
        wt = base / np.maximum(a_abs, 1e-12 * np.max(a_abs))
        wt = wt / np.max(wt)
        Mb, Ma = wt[:, None] * xb, -(wt * Hd)[:, None] * xa
        M[:n, : nb + 1], M[n:, : nb + 1] = Mb.real, Mb.imag
        M[:n, nb + 1 :], M[n:, nb + 1 :] = Ma.real, Ma.imag
        sc = np.sqrt(np.einsum("ij,ij->j", M, M))
        sc[sc == 0] = 1.0
        # min ||Mb b + Ma a|| with ||a|| = 1: after M = Q R, only the small R matters
        R = np.linalg.qr(M / sc, mode="r")
        R11, R12, R22 = R[: nb + 1, : nb + 1], R[: nb + 1, nb + 1 :], R[nb + 1 :, nb + 1 :]
        v = np.linalg.svd(R22)[2][-1]
        bs = -np.linalg.lstsq(R11, R12 @ v, rcond=None)[0]
        an = v / sc[nb + 1 :]
        bn = bs / sc[: nb + 1]
        a_prev = np.polyval(an[::-1], x)
        if not np.all(np.isfinite(a_prev)) or np.any(a_prev == 0):
            break
        h = np.polyval(bn[::-1], x) / a_prev
        if h_prev is not None and np.max(np.abs(h - h_prev) / np.abs(h)) < 1e-10:
            break
        h_prev = h
    return bn, an


def spread_poles(n: int, x_lo: float, x_hi: float) -> np.ndarray:
    """Lightly damped pole pairs spread log-uniformly over the band (and one real pole)."""
    mags = np.geomspace(x_lo, x_hi, n // 2 + 2)[1:-1] if n >= 2 else np.zeros(0)
    p = [m * (-0.01 + 1j) for m in mags]
    p = p + [np.conj(q) for q in p]
    if n % 2:
        p.append(-np.sqrt(x_lo * x_hi) + 0j)
    return np.asarray(p, complex)


def reflect_poles(p: np.ndarray) -> np.ndarray:
    """Poles with those in the closed right half plane mirrored into the left half plane."""
    scale = np.maximum(np.abs(p), 1e-12)
    re = np.where(p.real >= 0, -np.maximum(p.real, 1e-9 * scale), p.real)
    return re + 1j * p.imag


def _quad_roots(a1: float, a0: float) -> np.ndarray:
    """Roots of ``x^2 + a1 x + a0`` without cancellation."""
    disc = a1 * a1 - 4.0 * a0
    if disc >= 0:
        q = -0.5 * (a1 + np.copysign(np.sqrt(disc), a1 if a1 != 0 else 1.0))
        r1 = q
        r2 = a0 / q if q != 0 else 0.0
        return np.array([r1, r2], dtype=complex)
    re = -0.5 * a1
    im = 0.5 * np.sqrt(-disc)
    return np.array([re + 1j * im, re - 1j * im])


def _sections_from_poles(p: np.ndarray, stable: bool):
    """Initial parameters of second-order (and one first-order) sections."""
    p = np.asarray(p, complex)
    tiny = 1e-8
    if stable:
        p = np.where(
            p.real >= 0, -np.abs(p.real) - tiny * np.maximum(np.abs(p), 1.0) - tiny + 1j * p.imag, p
        )
    cplx = p[p.imag > 0]
    real = np.sort(p[p.imag == 0].real)
    quads = [(-2 * c.real, abs(c) ** 2) for c in cplx]
    first = None
    if real.size % 2:
        # the real pole nearest the band (|x| closest to 1) gets its own section
        i = int(np.argmin(np.abs(np.log(np.abs(real) + 1e-300))))
        first = -real[i]
        real = np.delete(real, i)
    for i in range(0, real.size, 2):
        quads.append((-(real[i] + real[i + 1]), real[i] * real[i + 1]))
    theta = []
    for a1, a0 in quads:
        theta += [np.log(max(a1, tiny)), np.log(max(a0, tiny))] if stable else [a1, a0]
    if first is not None:
        theta.append(np.log(max(first, tiny)) if stable else first)
    return np.asarray(theta, float), len(quads), first is not None


def _section_coefs(theta, stable):
    return np.exp(np.clip(theta, -300.0, 300.0)) if stable else theta


def _den_sections(x, theta, n_quad, has_first, stable):
    """Denominator value at ``x`` as a product of sections."""
    c = _section_coefs(theta, stable)
    d = np.ones_like(x)
    for i in range(n_quad):
        d = d * ((x + c[2 * i]) * x + c[2 * i + 1])
    if has_first:
        d = d * (x + c[2 * n_quad])
    return d


def _poles_from_sections(theta, n_quad, has_first, stable):
    c = _section_coefs(theta, stable)
    p = [_quad_roots(c[2 * i], c[2 * i + 1]) for i in range(n_quad)]
    if has_first:
        p.append(np.array([-c[2 * n_quad]], dtype=complex))
    return np.concatenate(p) if p else np.zeros(0, complex)


class _VarPro:
    """Weighted relative error with the numerator projected out (variable projection).

    The residual is ``w (H_model / H - 1)``, real and imaginary parts stacked; the Jacobian
    is Kaufman's approximation ``P_perp dG/dtheta c``.
    """

    def __init__(self, f, H, w, omega0, k, nb, n_quad, has_first, stable, delay):
        self.s = 2j * np.pi * f
        self.x = self.s / omega0
        self.xb = self.x[:, None] ** np.arange(nb + 1)
        self.base = w / (H * self.x**k)
        self.rhs = np.r_[w, np.zeros(w.size)]
        self.n_quad, self.has_first, self.stable = n_quad, has_first, stable
        self.delay = delay  # None: fitted as last parameter [omega0 * tau]; else fixed [s]
        self.omega0 = omega0
        self.bn = None
        self._key = None

    def split(self, theta):
        if self.delay is None:
            return theta[:-1], theta[-1] / self.omega0
        return theta, self.delay

    def _evaluate(self, theta):
        key = theta.tobytes()
        if key == self._key:
            return
        self._key = key
        th, tau = self.split(theta)
        c = _section_coefs(th, self.stable)
        x = self.x
        with np.errstate(all="ignore"):
            dlog = []
            D = np.ones_like(x)
            for i in range(self.n_quad):
                Di = (x + c[2 * i]) * x + c[2 * i + 1]
                D = D * Di
                if self.stable:
                    dlog += [c[2 * i] * x / Di, c[2 * i + 1] / Di]
                else:
                    dlog += [x / Di, 1.0 / Di]
            if self.has_first:
                Di = x + c[2 * self.n_quad]
                D = D * Di
                dlog.append((c[2 * self.n_quad] if self.stable else 1.0) / Di)
            g = self.base / D
            if tau:
                g = g * np.exp(-self.s * tau)
            G = g[:, None] * self.xb
        n = self.rhs.size
        if not np.all(np.isfinite(G)):
            self.r = np.full(n, 1e6)
            self.J = np.zeros((n, theta.size))
            return
        Gr = np.vstack([G.real, G.imag])
        # numpy's 2-norm along an axis, without its dispatch on the arguments
        scale = np.sqrt(np.add.reduce(Gr * Gr, axis=0))
        scale[scale == 0] = 1.0
        Q, R = np.linalg.qr(Gr / scale)
        cs = np.linalg.lstsq(R, Q.T @ self.rhs, rcond=None)[0]
        coef = cs / scale
        self.bn = coef
        m = G @ coef  # model response times w / H
        self.r = np.concatenate((m.real, m.imag)) - self.rhs
        # the Jacobian is formed when asked for: the solver asks for none at the steps
        # it rejects
        self.J = None
        self._pieces = (Q, m, dlog)

    def _jacobian(self):
        Q, m, dlog = self._pieces
        cols = [-m * d for d in dlog]
        if self.delay is None:
            cols.append(-self.x * m)
        dm = np.array(cols).T
        dmr = np.vstack([dm.real, dm.imag])
        return dmr - Q @ (Q.T @ dmr)

    def __call__(self, theta):
        self._evaluate(theta)
        return self.r

    def jac(self, theta):
        self._evaluate(theta)
        if self.J is None:
            self.J = self._jacobian()
        return self.J


def relative_cost(f, H, w, bn, pn, omega0, k, tau):
    h = tf_response(f, bn, pn, omega0, k, tau)
    r = w * (h / H - 1.0)
    return float(np.sum(r.real**2 + r.imag**2))


def refine_vp(f, H, w, omega0, k, n_num, stable, fit_delay, bn, pn, tau, cost, max_nfev):
    """Nonlinear least squares from a linear-stage result; keeps the start if no better."""
    theta0, n_quad, has_first = _sections_from_poles(pn, stable)
    vp = _VarPro(f, H, w, omega0, k, n_num, n_quad, has_first, stable, None if fit_delay else tau)
    if fit_delay:
        theta0 = np.r_[theta0, tau * omega0]
    try:
        sol = least_squares(
            vp, theta0, jac=vp.jac, method="lm", xtol=1e-10, ftol=1e-12, max_nfev=max_nfev
        )
        th, tau_new = vp.split(sol.x)
        vp(sol.x)
        pn_new = _poles_from_sections(th, n_quad, has_first, stable)
        bn_new = vp.bn
        cost_new = relative_cost(f, H, w, bn_new, pn_new, omega0, k, tau_new)
        if np.isfinite(cost_new) and cost_new <= cost and (not fit_delay or tau_new >= 0):
            return bn_new, pn_new, float(tau_new), cost_new
    except (np.linalg.LinAlgError, ValueError):
        pass
    return bn, pn, tau, cost


def fit_numerator(x, Hd, w, pn, nb):
    """Least-squares numerator for fixed poles (relative error)."""
    g = w / (Hd * _den_value(x, pn))
    G = g[:, None] * x[:, None] ** np.arange(nb + 1)
    Gr = np.vstack([G.real, G.imag])
    rhs = np.r_[w, np.zeros(w.size)]
    scale = np.linalg.norm(Gr, axis=0)
    scale[scale == 0] = 1.0
    return np.linalg.lstsq(Gr / scale, rhs, rcond=None)[0] / scale


def peaks_and_dips(f, H, coherence, k, prominence_db, min_phase_deg=30.0, rel_std=None):
    """Resonance peaks and antiresonance dips of ``|H (j omega)^k|``.

    A peak counts if the phase falls across it, a dip if the phase rises across it, each
    by at least ``min_phase_deg`` between the points half its prominence down: a valley
    between two resonances is no antiresonance. With the random error ``rel_std`` of the
    bins, the prominence must also exceed four standard deviations of the magnitude in dB
    (noise makes peaks of its own). Returns two lists of
    ``(prominence [dB], frequency [Hz], damping estimate [-])``, most prominent first.
    """
    from scipy.signal import find_peaks, peak_widths

    Hk = H * (2j * np.pi * f) ** k
    mag = 20.0 * np.log10(np.abs(Hk))
    phase = np.degrees(np.unwrap(np.angle(Hk)))
    idx = np.arange(f.size)

    def find(sign):
        found, props = find_peaks(sign * mag, prominence=prominence_db, width=0)
        out = []
        if found.size == 0:
            return out
        # half-power (3 dB) width gives the damping: 2 zeta = bandwidth / frequency
        rel = np.clip(3.0 / props["prominences"], 0.0, 1.0)
        hp = [peak_widths(sign * mag, [i], rel_height=r) for i, r in zip(found, rel, strict=True)]
        for j, i in enumerate(found):
            lo, hi = props["left_ips"][j], props["right_ips"][j]
            lo_i, hi_i = max(int(np.floor(lo)) - 1, 0), min(int(np.ceil(hi)) + 1, f.size - 1)
            turn = np.interp(hi_i, idx, phase) - np.interp(lo_i, idx, phase)
            noise_db = 0.0 if rel_std is None else 4.0 * 8.69 * rel_std[i]
            if (
                coherence[i] >= 0.5
                and -sign * turn >= min_phase_deg
                and props["prominences"][j] >= prominence_db + noise_db
            ):
                f_lo = np.interp(hp[j][2][0], idx, f)
                f_hi = np.interp(hp[j][3][0], idx, f)
                zeta = float(np.clip((f_hi - f_lo) / (2.0 * f[i]), 1e-4, 0.5))
                out.append((float(props["prominences"][j]), float(f[i]), zeta))
        return sorted(out, reverse=True)

    return find(1.0), find(-1.0)


def peak_poles(f, H, k, n, x_scale):
    """Start poles in ``x``: pairs at the most prominent resonance peaks, the rest spread."""
    peaks, _ = peaks_and_dips(f, H, np.ones(f.size), k, 3.0)
    p = []
    for _, fp, zeta in peaks[: n // 2]:
        wn = 2 * np.pi * fp / x_scale
        p += [wn * (-zeta + 1j * np.sqrt(1 - zeta**2)), wn * (-zeta - 1j * np.sqrt(1 - zeta**2))]
    rest = spread_poles(n - len(p), 2 * np.pi * f[0] / x_scale, 2 * np.pi * f[-1] / x_scale)
    return np.r_[np.asarray(p, complex), rest]
