"""The ranking's claims about a term are no firmer than the circles behind them: where the
linear scale's circles leave a term open, the TCP's ranking does not place it past the
scale; where the spikes' ±95% leaves the largest short of the tolerance, it is marked ±
(tests/test_circle_diagnostics.py's circles, tests/test_circle_lingering.py's pulse)."""

import json

import numpy as np

import test_circle_diagnostics as gen
from tcpmm.analysis.circle_alias import ranking_marks
from tcpmm.analysis.circle_display import placed_terms
from tcpmm.analysis.circle_sigma import noise_line
from tcpmm.cli._circles import _placed
from test_circle_lingering import pair

ERR = {"b_x": 3e-6, "b_y": -3e-6, "eps_x": 20e-6, "spikes": gen.SPIKE_5}


def test_a_term_the_scale_leaves_open_is_not_placed_past_it():
    """The demo's scale circles leave the backlash X and every spike open (a transient
    lasting past the window); the TCP's ranking read them as 0.00 at the scale and "mostly
    past the linear scale: the structure between the table and the tool". Here the
    scale's circles carry a pulse peaking at 14 deg, which leaves the same open."""
    tcp = gen.diagnose(ERR)
    scale = pair(ERR, 14.0)
    assert np.isnan(scale["backlash_X"]) and np.isnan(scale["spike_B_ccw"])
    placed = placed_terms(tcp, scale, "linear scale")
    # the scale's scale mismatch reads -124 ppm (20 injected) and +231 with the wider
    # window: it moves by more than its value, so the scale's ranking leaves it out too
    for term in ("backlash_X", "backlash_Y", "reversal_spikes", "scale_mismatch"):
        g_ref, where = placed[term]
        assert np.isnan(g_ref) and where == "not determined at the linear scale", term
        assert json.dumps(_placed(term, placed), allow_nan=False)
    g_ref, where = placed["lateral_play_Y"]  # one the scale determines keeps its figure
    assert np.isfinite(g_ref)


def test_the_ranking_marks_spikes_their_pm_leaves_short_of_the_tolerance():
    """The demo's ranking led with reversal spikes of 7.21 um, unmarked, while their ±95%
    was 29.80 um. The spikes are marked ± where the largest given plus its ±95% may pass
    the one ranked by 0.1 um and 2 % of it, the terms' tolerance, and the line under the
    terms says how far; 50 um spikes over 0.05 um of noise are not."""
    noisy = gen.diagnose(ERR, noise=1e-6)
    marks, legend = ranking_marks(noisy)
    assert "±" in marks["reversal_spikes"]
    assert any(m.startswith("±: uncertain by what the terms leave") for m in legend)
    line = noise_line(noisy)
    assert "the largest reversal spike after the terms" in line and "within the spikes'" in line
    big = dict(ERR, spikes={(d, "B"): (50e-6, 6.0) for d in ("ccw", "cw")})
    marks, _ = ranking_marks(gen.diagnose(big))
    assert "±" not in marks["reversal_spikes"]


def test_a_term_is_placed_past_the_scale_only_where_both_pm_agree():
    """Bench C at F5000 (the independent simulator's): the TCP's spikes rank at 27.00 ±
    1.42 um of G, the scale's at 12.91 ± 0.97 um, and the ranking said "mostly past the
    linear scale" (under half), which their ±95% does not hold; the backlash X, 4.37 ±
    1.70 against 0.04 ± 0.08 um, it holds. A term is placed only where every G within the
    ±95% of both places it alike."""
    from conftest import bench_path
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.analysis.diagnostics import circle_diagnostics
    from tcpmm.io.runfile import read_run

    c = bench_path("c")
    res = [analyse_circle(read_run(c / f"circle_{w}_meas.csv"), 0.035) for w in ("ccw", "cw")]
    placed = placed_terms(circle_diagnostics(*res, sensor="tcp"),
                          circle_diagnostics(*res, sensor="scale"), "linear scale")
    assert placed["reversal_spikes"][1].startswith("not placed: within their ±95%")
    assert placed["backlash_X"][1].startswith("mostly past the linear scale")


def test_one_direction_s_spikes_of_no_pm_are_not_placed():
    """Bench C's CW circle alone: its spikes after its own terms carry no ±95%, which
    placed them as if exact, "mostly past the linear scale" on 12.92 < 13.45 um (half of
    26.90), where the pair of circles says "not placed". A term of no known ±95% is not
    placed, in the console's JSON and table (no "*") and in the report's Error sources."""
    from conftest import bench_path
    from tcpmm.analysis.circle_single import one_direction_diagnostics, scale_diagnostics
    from tcpmm.analysis.circular import analyse_circle
    from tcpmm.io.runfile import read_run
    from tcpmm.report.acceptance import ranked_sources

    res = analyse_circle(read_run(bench_path("c") / "circle_cw_meas.csv"), 0.035)
    tcp = one_direction_diagnostics(res, sensor="tcp")
    scale = scale_diagnostics(tcp, res)
    assert not tcp.spike_u95 and scale is not None
    g_ref, where = placed_terms(tcp, scale, "linear scale")["reversal_spikes"]
    assert 0 < g_ref < 0.5 * tcp.ranking[0]["g_alone_m"]  # half, were the spikes exact
    assert where.startswith("not placed: its ±95% is not known")
    assert not _placed("reversal_spikes", {"reversal_spikes": (g_ref, where)})[
        "where"].startswith("mostly")
    notes = {s.split(" ?")[0].split(" ~")[0]: n for s, _, n, _ in ranked_sources(tcp, scale)}
    assert notes["reversal spikes"].startswith("not placed: its ±95% is not known")


def test_a_term_whose_sign_the_tails_leave_open_is_not_ranked():
    """The demo's ranking listed a backlash X of 2.08 um that reads -12.92 with the wider
    window as its fourth error source, and a scale mismatch of -63 ppm that reads +42,
    while the page said a term that moves by more than its value is not determined. Circles
    with a pulse past the window (scale mismatch -124 ppm read for 20, +231 with the wider
    window) rank no such term and name it under the ranking; the same circles without the
    pulse rank it."""
    clean, pulsed = gen.diagnose(ERR), pair(ERR, 14.0)
    assert "scale_mismatch" in {r["term"] for r in clean.ranking}
    assert "scale_mismatch" not in {r["term"] for r in pulsed.ranking}
    from tcpmm.analysis.circle_tails import unranked_line

    assert unranked_line(clean) == ""
    line = unranked_line(pulsed)
    assert line.startswith("not ranked: scale mismatch") and "not even its sign" in line
    assert abs(sum(r["share"] for r in pulsed.ranking) - 1.0) < 1e-9


def test_the_report_s_key_figures_say_a_term_open_in_sign():
    """The demo's page gave 'scale mismatch -63.27 ± 20.42 ppm' among its key figures a few
    lines under the ranking that left it out as not determined, not even in sign. Where a
    term's value is shown there, it now says so; a determined one reads as before."""
    from tcpmm.analysis.diagnostics import display_terms
    from tcpmm.report.circles import _with_pm

    for d, open_ in ((gen.diagnose(ERR), False), (pair(ERR, 14.0), True)):
        shown = {k: (v, u) for k, v, u in display_terms(d)}
        text = _with_pm(d, "scale_mismatch", *shown["scale_mismatch"])
        assert ("not even its sign" in text) == open_, text


def test_spikes_of_noise_alone_are_not_ranked_and_a_spike_standing_out_is():
    """Circles of noise alone gave eight spikes after the terms, each within its 95 %
    bound or not by chance; the largest, the noise's extreme, was ranked first (1.24 um,
    52 % of G(b) at 0.3 um of noise) in every such pair. The spikes are ranked only where
    one stands out of its bound at the level that keeps all eight within theirs at 95 %:
    two of these ten pairs of noise alone (before, all ten; 4 of 40 such pairs, where 2
    are expected and 4 or more come one time in seven, docs/circle_diagnostics.md). A
    spike of six times the noise stands out and is ranked first."""
    noise = 0.3e-6
    ranked = []
    for seed in range(10):
        d = gen.diagnose_pair(gen.circle("ccw", {}, 2 * seed + 11, noise=noise),
                              gen.circle("cw", {}, 2 * seed + 12, noise=noise), gen.R,
                              (gen.W, gen.W))
        terms = [r["term"] for r in d.ranking]
        ranked.append("reversal_spikes" in terms)
        if not ranked[-1]:
            assert d.quiet_spikes.startswith("none of the 8 spikes after the terms stands out")
            assert d.to_dict()["spikes_in_noise"] == d.quiet_spikes
    assert sum(ranked) <= 3, ranked
    spikes = {("ccw", "B"): (1.8e-6, 3.0), ("cw", "D"): (1.8e-6, 3.0)}
    d = gen.diagnose({"spikes": spikes}, noise=noise)
    assert not d.quiet_spikes and d.ranking[0]["term"] == "reversal_spikes"


def test_a_ranked_term_within_its_pm_of_zero_is_marked_so():
    """A pair of noise alone ranked ten terms whose shares add to 100 % of the sum, each
    as an error source, most within their ±95% of zero; they are marked '0', in the JSON
    too, and a term injected well outside its ± is not."""
    from tcpmm.cli._circles import diagnostics_json

    noise = gen.diagnose({}, noise=0.3e-6)
    marks, legend = ranking_marks(noise)
    zero = [t for t, m in marks.items() if "0" in m.split()]
    assert zero and "0: within its ±95% of zero: not told from no error" in legend
    for t in zero:
        name = t if t in noise.sigma else f"{t}_angle"
        assert abs(noise.terms[name][0]) <= 2.0 * noise.sigma[name], t
    rows = {r["term"]: r["marks"] for r in diagnostics_json(noise)["ranking"]}
    assert all("0" in rows[t] for t in zero)
    marks, _ = ranking_marks(gen.diagnose({"b_x": 4e-6, "b_y": -3e-6}))
    assert "0" not in marks["backlash_X"].split() and "0" not in marks["backlash_Y"].split()
