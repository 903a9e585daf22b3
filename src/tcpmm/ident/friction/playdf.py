"""The nut's lost motion as a sweep sees it: an amplitude-dependent nut stiffness.

With lost motion ``b`` the nut is a dead-zone spring: no force while the screw's contact
point moves inside the play, ``K_t`` times the overtravel beyond it. A sweep drives the
nut deflection ``delta`` at the swept frequency; the first harmonic of the nut force is
then ``N K_t`` times that of ``delta`` (the describing function of the dead zone), with

    N(a) = (1 / (pi a)) int_0^{2 pi} dz(delta_0 + a sin th) sin th dth

for the amplitude ``a`` of ``delta`` and its mean ``delta_0``. The sweep travels slowly, so
the guideway friction ``F_g`` keeps the nut on one flank on average: ``delta_0`` is the
offset at which the mean force of the dead zone is ``F_g``. ``N = 1`` while
``K_t a < F_g`` (the nut never leaves its flank) and tends to 1 again when ``a >> b``; in
between the nut is softer, which a linear fit of the FRFs would read as a heavier table.

:func:`nut_deflection_amplitude` takes ``a`` per frequency from the record itself
(:func:`sweep_motion`): the screw's contact point, ``R theta_L`` with ``theta_L`` the motor
angle through the screw's torsion, minus the scale. :func:`play_gain` combines both into the
``nut_gain`` of :func:`tcpmm.ident.physical.greybox.fit_physical`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mechanics.lumped import AxisMechanics
from ..frf._spectral import sample_rate_hz
from ..frf.response import frf_against_reference
from ..physical.greybox import nut_path

__all__ = ["dead_zone_gain", "nut_deflection_amplitude", "play_gain", "sweep_motion"]

#: Bisection steps for the mean offset (2^-60 of the bracket: far below any play).
_N_BISECT = 60


def _ramp_harmonics(y, a):
    """Mean and first sine harmonic of ``max(y + a sin th, 0)`` over a period.

    In closed form: the ramp is active where ``sin th > beta = -y/a``, i.e. on
    ``(asin beta, pi - asin beta)``, beta clipped to [-1, 1].

    Parameters
    ----------
    y : numpy.ndarray
        Offset beyond the ramp's corner [m].
    a : numpy.ndarray
        Amplitude, positive [m].

    Returns
    -------
    tuple of numpy.ndarray
        The mean and ``(1/pi) int max(...) sin th dth`` [m].
    """
    beta = np.clip(-y / a, -1.0, 1.0)
    arc = np.pi - 2.0 * np.arcsin(beta)
    root = np.sqrt(1.0 - beta**2)
    mean = (y * arc + 2.0 * a * root) / (2.0 * np.pi)
    first = (2.0 * y * root + a * (0.5 * arc + beta * root)) / np.pi
    return mean, first


def _dead_zone_harmonics(x0, a, half):
    """Mean and first sine harmonic of the dead zone of half-width ``half`` driven by
    ``x0 + a sin th`` [m]: the ramp above ``half`` less the mirrored one below ``-half``."""
    m_up, f_up = _ramp_harmonics(x0 - half, a)
    m_lo, f_lo = _ramp_harmonics(-x0 - half, a)
    return m_up - m_lo, f_up + f_lo


def dead_zone_gain(amplitude, play: float, bias: float) -> np.ndarray:
    """Describing function of a dead-zone spring held on one flank by a bias force.

    Mean force and first harmonic in closed form; the offset at which the mean force
    equals the bias by bisection (the mean is monotone in the offset).

    Parameters
    ----------
    amplitude : array_like
        Amplitude ``a`` of the deflection across the element [m].
    play : float
        Total free play of the element, the lost motion; the dead zone spans
        ``+/- play/2`` [m].
    bias : float
        Mean force over the contact stiffness, ``F_g / K_t`` [m].

    Returns
    -------
    numpy.ndarray
        First-harmonic gain relative to the contact stiffness, in [0, 1] [-].
    """
    a = np.atleast_1d(np.asarray(amplitude, dtype=float))
    half = 0.5 * max(float(play), 0.0)
    fb = abs(float(bias))
    a_pos = np.where(a > 0, a, 1.0)
    reach = half + fb + a + 1e-15
    lo, hi = -reach, reach.copy()
    for _ in range(_N_BISECT):
        mid = 0.5 * (lo + hi)
        over = _dead_zone_harmonics(mid, a_pos, half)[0] > fb
        hi = np.where(over, mid, hi)
        lo = np.where(over, lo, mid)
    first = _dead_zone_harmonics(0.5 * (lo + hi), a_pos, half)[1]
    gain = np.where(a > 0, first / a_pos, 1.0)
    return np.clip(gain, 0.0, 1.0)


def sweep_motion(sweep, fmin_hz: float, fmax_hz: float | None = None):
    """Motor angle and scale per frequency while a sweep passes it.

    Both against the injected excitation, scaled by its amplitude.

    Parameters
    ----------
    sweep : SweepRecord
        Servo-excitation record (SI) [-].
    fmin_hz : float
        Lowest frequency [Hz].
    fmax_hz : float, optional
        Highest frequency [Hz].

    Returns
    -------
    tuple of numpy.ndarray
        Frequencies [Hz], complex amplitudes of the motor angle [rad] and of the scale [m].
    """
    fs = sample_rate_hz(sweep.time_s, file=sweep.source)
    f = frf_against_reference(
        sweep.excitation_A, {"theta": sweep.motor_angle_rad, "x": sweep.scale_m}, fs,
        fmin_hz=fmin_hz, fmax_hz=fmax_hz, reference="excitation_A", file=sweep.source)
    amp = float(np.max(np.abs(sweep.excitation_A)))
    return f["theta"].freq_hz, amp * f["theta"].H, amp * f["x"].H


def nut_deflection_amplitude(freq_hz, theta_m, scale_m, mech: AxisMechanics) -> np.ndarray:
    """Amplitude of the nut deflection per frequency of a sweep.

    ``delta = R theta_L - X_LS`` with ``theta_L = theta_m K_L / (Z_L + K_L)``, the motor
    angle through the screw's torsion.

    Parameters
    ----------
    freq_hz : numpy.ndarray
        Frequencies [Hz].
    theta_m : numpy.ndarray
        Complex amplitude of the motor angle (:func:`sweep_motion`) [rad].
    scale_m : numpy.ndarray
        Complex amplitude of the scale [m].
    mech : AxisMechanics
        Mechanics for the torsion between motor and nut [SI].

    Returns
    -------
    numpy.ndarray
        Deflection amplitudes [m].
    """
    m = mech
    _, _, ZL = nut_path(m, 2j * np.pi * np.asarray(freq_hz, dtype=float))
    theta_L = theta_m * m.K_L / (ZL + m.K_L)
    return np.abs(m.R_L * theta_L - scale_m)


def play_gain(freq_hz, amplitude_m, backlash_m: float, bias_force_N: float,
              stiffness_N_per_m: float):
    """Nut-stiffness factor per frequency for the physical fit.

    Parameters
    ----------
    freq_hz : array_like
        Frequencies of the amplitudes [Hz].
    amplitude_m : array_like
        Nut deflection amplitude per frequency [m].
    backlash_m : float
        Lost motion of the nut, its total free play [m].
    bias_force_N : float
        Guideway force holding the nut on one flank during the sweep [N].
    stiffness_N_per_m : float
        Nut stiffness in contact [N/m].

    Returns
    -------
    PlayGain
        ``gain(f)``: the factor at frequencies ``f`` [Hz], interpolated in log frequency
        (1 outside the record's band) [-].
    """
    lf = np.log(np.asarray(freq_hz, dtype=float))
    return PlayGain(lf, dead_zone_gain(amplitude_m, backlash_m, bias_force_N / stiffness_N_per_m))


@dataclass(frozen=True, eq=False)
class PlayGain:
    """The nut-stiffness factor of :func:`play_gain`, a value that can be pickled (an
    axis's identification goes from the process that made it to the one that writes it);
    compared as the function it stands for, by identity.

    Parameters
    ----------
    log_freq : ndarray
        Natural logarithm of the frequencies of the factors [log Hz].
    factor : ndarray
        The factor at each [-].
    """

    log_freq: np.ndarray
    factor: np.ndarray

    def __call__(self, f):
        """The factor at frequencies ``f`` [Hz], 1 outside the band [-]."""
        return np.interp(np.log(np.asarray(f, dtype=float)), self.log_freq, self.factor,
                         left=1.0, right=1.0)
