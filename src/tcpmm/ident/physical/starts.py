"""Starting points of the physical fit, from the measured FRFs and their rational fits.

The rigid-body inertia comes from the low-frequency slope of G_M, the structural modes from
the poles of G_tcp (whose denominator is ``(M_b+M_t) s^2 + ... + K_b`` times
``M_h s^2 + C_h s + K_h``), and the drive modes from the resonances of G_T; several splits
of the inertia are tried (:func:`tcpmm.ident.physical.greybox.fit_physical` keeps the best).
"""

from __future__ import annotations

import itertools
import math

import numpy as np

#: The band must reach this factor above G_M's highest resolved mode before further
#: torsion frequencies are tried as starting points [-].
TORSION_SPREAD = 2.0


def _peaks(f, H, k=3):
    """Frequencies of the ``k`` largest local maxima of |H| (above the trend) [Hz]."""
    a = np.log(np.abs(H) + 1e-300)
    # the trend over 31 bins, or all a narrow band holds: a window longer than the FRF
    # would give a trend of the window's length
    n = min(31, a.size - (1 - a.size % 2))
    if n < 5:
        return []
    trend = np.convolve(a, np.ones(n) / n, mode="same")
    r = a - trend
    idx = [i for i in range(2, len(a) - 2) if r[i] == r[i - 2:i + 3].max() and r[i] > 0.1]
    idx = sorted(idx, key=lambda i: -r[i])[:k]
    return sorted(f[i] for i in idx)


def initial_guesses(data: dict, lead: float, K_tc: float) -> list[dict]:
    """Physically reasoned starting points from the measured FRFs (see module docs)."""
    R = lead / (2 * math.pi)
    gm = data["G_M"]
    lo = gm.freq_hz < gm.freq_hz.min() * 3
    w = 2 * np.pi * gm.freq_hz[lo]
    J_total = float(np.median(K_tc / (np.abs(gm.H[lo]) * w)))
    guesses = []
    f_tcp = _peaks(data["G_tcp"].freq_hz, data["G_tcp"].H) if "G_tcp" in data else []
    f_t = _peaks(data["G_T"].freq_hz, data["G_T"].H) if "G_T" in data else []
    f_h = f_tcp[0] if f_tcp else 50.0
    f_b = f_tcp[-1] if len(f_tcp) > 1 else 4 * f_h
    for share_m, share_t in ((0.2, 0.5), (0.35, 0.35), (0.15, 0.7), (0.5, 0.25)):
        J_m = share_m * J_total
        M_t = share_t * J_total / R**2
        J_L = J_total - J_m - M_t * R**2
        f_ax = f_t[-1] if f_t else 200.0
        f_tor = f_t[0] if len(f_t) > 1 else 0.7 * f_ax
        M_h, M_b = 2.5 * M_t, 5 * M_t
        K_h = M_h * (2 * np.pi * f_h) ** 2
        K_b = (M_b + M_t) * (2 * np.pi * f_b) ** 2
        K_t = M_t * (2 * np.pi * f_ax) ** 2
        K_L = (J_L * J_m / (J_L + J_m)) * (2 * np.pi * max(f_tor, 1.0)) ** 2
        g = dict(J_m=J_m, J_L=J_L, M_t=M_t, M_h=M_h, M_b=M_b, K_h=K_h, K_b=K_b, K_t=K_t,
                 K_L=K_L)
        g["B_m"] = 0.02 * J_m * 2 * np.pi * 10
        g["B_L"] = 0.02 * J_L * 2 * np.pi * 10
        g["C_t"] = 0.05 * M_t * 2 * np.pi * 10
        g["C_h"] = 2 * 0.03 * math.sqrt(K_h * M_h)
        g["C_b"] = 2 * 0.05 * math.sqrt(K_b * M_b)
        guesses.append(g)
    return guesses


def _pairs_hz(roots):
    """(natural frequency [Hz], damping) of the upper-half-plane roots, ascending."""
    r = np.asarray(roots)
    r = r[r.imag > 1e-9 * np.abs(r)]
    order = np.argsort(np.abs(r))
    return [(abs(x) / (2 * np.pi), -x.real / abs(x)) for x in r[order]]


def _tcp_assignments(tcp_p: list, tcp_z) -> list:
    """``(f_h, zeta_h, f_b, zeta_b, M_b/M_t, M_h/M_t)`` per way of reading the poles
    ``tcp_p`` [(Hz, -)] and zeros ``tcp_z`` [Hz] of G_tcp as TCP and bed modes: each pole
    taken as the bed's, its zero the next above; a fixed guess when G_tcp shows too
    little [-]."""
    assignments = []
    if len(tcp_p) >= 2 and len(tcp_z) >= 2:
        for (fh, zh), (fb, zb) in ((tcp_p[0], tcp_p[1]), (tcp_p[1], tcp_p[0])):
            above = [z for z in tcp_z if z > fb * 1.0001]
            if not above:
                continue
            fzb = min(above, key=lambda z: z - fb)
            rest = [z for z in tcp_z if z != fzb]
            fzh = rest[0] if rest else 2 * fh
            rb = 1.0 / ((fzb / fb) ** 2 - 1.0)
            rh_den = 1.0 - (fh / fzh) ** 2
            rh = 1.0 / rh_den if rh_den > 0.01 else 2.5
            assignments.append((fh, zh, fb, zb, min(max(rb, 0.05), 50), min(max(rh, 0.05), 50)))
    if not assignments:
        assignments.append((50.0, 0.03, 200.0, 0.05, 5.0, 2.5))
    return assignments


def guesses_from_tf(tf_fits: dict, lead: float, K_tc: float, J_total: float,
                    f_top_hz: float | None = None) -> list[dict]:
    """Starting points from rational fits of the FRFs (their poles and zeros).

    G_tcp = (den_h - den_t) den_b / (den_h (den_b + den_t)): its poles are the TCP
    structure mode sqrt(K_h/M_h) and the bed-with-carriage mode sqrt(K_b/(M_b+M_t)); its
    zeros sqrt(K_b/M_b) and sqrt(K_h/(M_h-M_t)). That fixes M_b/M_t and M_h/M_t; which
    pole is which is tried both ways, and the carriage's share of the rigid-body inertia
    four ways, from a light carriage on a heavy screw (18 %) to a heavy one (70 %).

    The torsion mode of motor and screw is put on the highest mode of G_M, and, when the
    band ``f_top_hz`` reaches further, also at two frequencies log-spaced between that mode
    and the band's top: a stiff coupling whose mode the rational fit of G_M did not resolve
    (or a play that makes an axial mode look like it) must not leave every start with a
    coupling many times too soft, in whose basin the fit then stays.
    """
    R = lead / (2 * math.pi)
    gm = _pairs_hz(tf_fits["G_M"].poles) if "G_M" in tf_fits else []
    gt = _pairs_hz(tf_fits["G_T"].poles) if "G_T" in tf_fits else []
    tcp_p = _pairs_hz(tf_fits["G_tcp"].poles) if "G_tcp" in tf_fits else []
    tcp_z = np.sort(np.abs(tf_fits["G_tcp"].zeros)) / (2 * np.pi) if "G_tcp" in tf_fits else []
    f_modes = [f for f, _ in gm] or [150.0, 220.0, 700.0]
    f_anti = [f for f, _ in gt] or [0.8 * f for f in f_modes]
    f_torsion = [f_modes[-1]]  # the stiff, light mode
    if f_top_hz is not None and f_top_hz > TORSION_SPREAD * f_modes[-1]:
        f_torsion += list(np.geomspace(f_modes[-1], f_top_hz, 4)[1:3])
    assignments = _tcp_assignments(tcp_p, tcp_z)
    out = []
    for share_t, share_m in ((0.5, 0.2), (0.3, 0.3), (0.7, 0.12), (0.18, 0.25)):
        M_t = share_t * J_total / R**2
        J_m = share_m * J_total
        J_L = max(J_total - J_m - M_t * R**2, 0.05 * J_total)
        for fh, zh, fb, zb, rb, rh in assignments:
            M_b, M_h = rb * M_t, rh * M_t
            K_b = (M_b + M_t) * (2 * np.pi * fb) ** 2
            K_h = M_h * (2 * np.pi * fh) ** 2
            J_red = J_m * J_L / (J_m + J_L)
            for f_ax, f_tor in itertools.product(sorted({f_modes[0], f_anti[0]}), f_torsion):
                K_L = J_red * (2 * np.pi * f_tor) ** 2
                K_t = M_t * (2 * np.pi * f_ax) ** 2
                out.append(dict(
                    J_m=J_m, J_L=J_L, M_t=M_t, M_b=M_b, M_h=M_h, K_b=K_b, K_h=K_h, K_t=K_t,
                    K_L=K_L, B_m=0.02 * J_m * 2 * np.pi * 10, B_L=0.02 * J_L * 2 * np.pi * 10,
                    C_t=0.05 * M_t * 2 * np.pi * 10, C_h=2 * zh * math.sqrt(K_h * M_h),
                    C_b=max(2 * zb * math.sqrt(K_b * (M_b + M_t))
                            - 0.05 * M_t * 2 * np.pi * 10, 1e-3 * math.sqrt(K_b * M_b))))
    return out


def j_total_from_g_m(frf, K_tc: float) -> float:
    """Rigid-body inertia from the low-frequency asymptote |G_M| = K_tc/(J w) [kg m^2]."""
    good = frf.weight > 0
    f, H = frf.freq_hz[good], frf.H[good]
    lo = f < f.min() * 3
    return float(np.median(K_tc / (np.abs(H[lo]) * 2 * np.pi * f[lo])))
