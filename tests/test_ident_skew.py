"""Channel skew: the delays between the sweep's channels, fitted jointly with the
mechanics, and the channel they put out of step (:mod:`tcpmm.ident.physical.skew`)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from tcpmm.ident.physical.axisfrfs import model_frfs
from tcpmm.ident.physical.fitdata import FRFData
from tcpmm.ident.physical.greybox import fit_physical
from tcpmm.ident.physical.skew import ChannelSkew, fit_channel_skews, is_skew, skewed_channels
from tcpmm.machines.builtin import builtin_machine

FS = 10_000.0
T = 1.0 / FS


@pytest.mark.parametrize("tcp_late, scale_late", [(2.0, 0.0), (0.0, 1.0), (0.0, 0.0)])
def test_a_delay_put_into_exact_frfs_is_read_back(tcp_late, scale_late):
    """The built-in X axis's FRFs, exact, with the TCP or the scale a whole number of
    samples late: the fit without delays takes part of the lag for dynamics; fitted
    jointly from there, each delay comes back to 0.01 samples, and none where none was
    put in."""
    mech = builtin_machine().axes["X"].mechanics
    f = np.geomspace(2.0, 2000.0, 400)
    exact = model_frfs(mech, {k: f for k in ("G_M", "G_T", "G_tcp")})
    lag = {"G_T": scale_late, "G_tcp": tcp_late - scale_late}
    data = {k: FRFData(f, H * np.exp(-2j * np.pi * f * lag.get(k, 0.0) * T), np.ones_like(f))
            for k, H in exact.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        phys = fit_physical(data, mech.lead, mech.K_tc, initial=mech.model_dump())
    read = {k.frf: k.samples for k in fit_channel_skews(data, phys, mech.lead, mech.K_tc,
                                                         0.0, False, FS)}
    assert read == pytest.approx(lag, abs=0.01)


def test_no_delay_is_judged_where_the_sweep_crosses_a_play():
    """The play's lag reads as a delay of the table's channels (up to 3.8 samples on
    machines of ``studies.unseen`` with 2.7-7 um of play, recorded in step): with a lost
    motion of a micrometre or more, a delay put in is still read, but not called a skew;
    below it, it is."""
    mech = builtin_machine().axes["X"].mechanics
    f = np.geomspace(2.0, 2000.0, 400)
    exact = model_frfs(mech, {k: f for k in ("G_M", "G_T", "G_tcp")})
    exact["G_tcp"] = exact["G_tcp"] * np.exp(-2j * np.pi * f * 2.0 * T)
    data = {k: FRFData(f, H, np.ones_like(f)) for k, H in exact.items()}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        phys = fit_physical(data, mech.lead, mech.K_tc, initial=mech.model_dump())

    def read(play):
        return fit_channel_skews(data, phys, mech.lead, mech.K_tc, 0.0, False, FS, play)

    played = read(1e-6)
    assert [k.samples for k in played] == pytest.approx([0.0, 2.0], abs=0.02)
    assert all("play (1.00 um)" in k.not_judged and not k.skewed for k in played)
    assert skewed_channels(played) == []
    assert [k.skewed for k in read(0.9e-6)] == [False, True]


def skews(scale_vs_motor, tcp_vs_scale=None, u=0.1):
    out = [ChannelSkew("G_T", scale_vs_motor * T, u * T, T)]
    if tcp_vs_scale is not None:
        out.append(ChannelSkew("G_tcp", tcp_vs_scale * T, u * T, T))
    return tuple(out)


@pytest.mark.parametrize("read, channel, samples", [
    (skews(0.02, 1.0), "TCP", 1.0),         # motor and scale agree
    (skews(1.0, -1.0), "scale", 1.0),       # motor and TCP agree
    (skews(-1.0, 0.03), "motor encoder", 1.0),  # scale and TCP agree
    (skews(-2.0), "scale", -2.0),           # no TCP: the scale against the motor
])
def test_the_channel_out_of_step_is_the_one_the_other_two_agree_against(read, channel,
                                                                         samples):
    found = skewed_channels(read)
    assert [(k.channel, k.samples) for k in found] == [(channel, pytest.approx(samples))]


def test_three_channels_all_apart_are_told_pair_by_pair_and_none_in_step_is_told():
    assert [k.channel for k in skewed_channels(skews(1.0, 1.0))] == ["scale", "TCP"]
    assert skewed_channels(skews(0.3, -0.2)) == []


@pytest.mark.parametrize("samples, u, skew", [
    (0.45, 0.01, False),  # below half a sample: the model's error as likely
    (0.9, 0.31, False),   # within three uncertainties
    (0.9, 0.29, True),
    (-1.0, 0.1, True),
    (20.0, math.nan, True),  # held at the fit's bound: no uncertainty, beyond any
])
def test_a_skew_is_beyond_half_a_sample_and_three_uncertainties(samples, u, skew):
    assert is_skew(samples, u) is skew


def test_a_skew_says_its_shift_in_the_column_of_the_record():
    (k,) = skewed_channels(skews(0.01, 2.04))
    assert k.remedy() == "shift the tcp_mm column 2 samples earlier"
    assert "2.04 +- 0.10 samples (204 +- 10 us) late against the scale" in k.words()
    (k,) = skewed_channels(skews(0.9, -0.95))
    assert k.remedy() == "shift the scale_mm column 1 sample earlier"
