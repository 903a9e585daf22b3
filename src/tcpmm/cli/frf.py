"""Commands on measured frequency responses: frf show, frf fit."""

from __future__ import annotations

import json
from enum import StrEnum
from pathlib import Path

import numpy as np
import typer

from ._app import (
    app,
    checked_plot,
    emit_json,
    esc,
    in_file,
    out,
    parse_band,
)
from ._outputs import checked_json_output, checked_yaml_output, distinct_outputs, outputs_together
from ._tables import plain_table, print_plain

frf_app = typer.Typer(help="Measured frequency responses (CSV, MAT, Sinumerik XML): show "
                      "and fit.", rich_markup_mode=None)
app.add_typer(frf_app, name="frf")

_FILE = "Frequency response: .csv, .mat or Sinumerik Operate .xml (see docs/frf_files.md)."
_AVERAGES = ("Number of averages behind the coherence, for a file that does not say it "
             "(default 10).")


def _averages_note(frf) -> str | None:
    """Where the noise rests on a count of averages the file does not give, say so [-]."""
    if not frf.meta.get("averages_assumed") or frf.meta.get("coherence_assumed"):
        return None
    return (f"the file gives a coherence but not the number of averages behind it: "
            f"{frf.n_averages:g} are assumed; give the count with --averages N (or an "
            "averages column, see docs/frf_files.md)")


class Weight(StrEnum):
    """Error a fit minimises."""

    relative = "relative"
    absolute = "absolute"
    magnitude = "magnitude"


def _poles(text: str):
    if text.strip().lower() == "auto":
        return "auto"
    try:
        n = int(text)
    except ValueError:
        raise typer.BadParameter(f"--poles takes a number or 'auto', got {text!r}") from None
    if n < 0:
        raise typer.BadParameter(f"--poles must be >= 0, got {n}")
    return n


def _delay(text: str):
    t = text.strip().lower()
    if t in ("fit", "none"):
        return None if t == "none" else "fit"
    try:
        v = float(t)
    except ValueError:
        raise typer.BadParameter(f"--delay takes fit, none or seconds, got {text!r}") from None
    if not (np.isfinite(v) and v >= 0):
        raise typer.BadParameter(f"--delay must be >= 0 s, got {text}")
    return v


@frf_app.command("show")
def show(file: Path = typer.Argument(..., help=_FILE),
         band: str = typer.Option(None, "--band", help="F0,F1 shown [Hz]."),
         plot: Path = typer.Option(None, "--plot", help="Save a Bode plot (PNG/PDF/SVG)."),
         averages: float = typer.Option(None, "--averages", min=1.0, help=_AVERAGES),
         as_json: bool = typer.Option(False, "--json")):
    """Summary of a measured frequency response: band, coherence, noise, a few points."""
    from ..errors import InputError
    from ..ident.lti import noise_level
    from ..io.frffile import read_frf

    checked_plot(plot)
    f0, f1 = parse_band(band, "--band")
    frf = read_frf(file, averages).band(f0, f1)
    if not np.any(np.isfinite(frf.H) & (np.abs(frf.H) > 0)):
        raise InputError(f"every one of the {frf.freq_hz.size} bins shown has a response of "
                         "zero or not a number: check the re/im or magnitude columns",
                         file=file)
    # the complex relative noise |dH / H|, as frf fit gives it beside its residual: the
    # noise level is that of the real and of the imaginary part each, 1/sqrt(2) of it
    sigma = np.sqrt(2.0) * noise_level(frf.freq_hz, frf.H, frf.rel_std)
    summary = {"file": str(file), "name": frf.name, "input": frf.input, "output": frf.output,
               "bins": int(frf.freq_hz.size), "freq_min_hz": float(frf.freq_hz[0]),
               "freq_max_hz": float(frf.freq_hz[-1]),
               "coherence_median": float(np.median(frf.coherence)),
               "bins_coherence_0_5": int(np.count_nonzero(frf.coherence >= 0.5)),
               "noise_rel_median": float(np.median(sigma)),
               "averages": frf.n_averages, "notes": [n for n in [_averages_note(frf)] if n]}
    assumed = bool(frf.meta.get("coherence_assumed"))
    summary["coherence_in_file"] = not assumed
    if assumed:  # none in the file: not a measure, and not to be read as one
        summary.update(coherence_median=None, bins_coherence_0_5=None)
    if plot is not None:
        from ..plot.frf import plot_frf

        plot_frf(frf, path=plot)
    if as_json:
        emit_json(summary)
        return
    out.print(f"{esc(str(file))}: {esc(frf.name)}"
              + (f" ({esc(frf.output)} / {esc(frf.input)})" if frf.input else ""))
    coherence = ("no coherence in the file: every bin is taken as well measured, and its "
                 "noise is that of a coherence of 1" if assumed else
                 f"coherence median {summary['coherence_median']:.3f}, "
                 f"{summary['bins_coherence_0_5']} bins >= 0.5")
    out.print(f"{summary['bins']} bins, {summary['freq_min_hz']:.4g}-"
              f"{summary['freq_max_hz']:.4g} Hz; {coherence}; relative noise |dH/H| median "
              f"{summary['noise_rel_median']:.3g}")
    t = plain_table(("f [Hz]", "|H| [dB]", "phase [deg]", "coherence [-]", "noise [-]"))
    idx = np.unique(np.searchsorted(frf.freq_hz, np.geomspace(frf.freq_hz[0],
                                                               frf.freq_hz[-1], 12)))
    for i in idx[idx < frf.freq_hz.size]:
        t.add_row(f"{frf.freq_hz[i]:.4g}", f"{frf.magnitude_db[i]:.2f}",
                  f"{np.degrees(np.angle(frf.H[i])):.1f}",
                  "n/a" if assumed else f"{frf.coherence[i]:.3f}",
                  f"{sigma[i]:.3g}")
    print_plain(t, out)
    for note in summary["notes"]:
        out.print(f"note: {esc(note)}")
    if plot is not None:
        out.print(f"wrote {plot}")


@frf_app.command("fit")
@outputs_together()
def fit(file: Path = typer.Argument(..., help=_FILE),
        poles: str = typer.Option("auto", "--poles",
                                  help="Number of poles, or auto (chosen by the data)."),
        band: str = typer.Option(None, "--band", help="F0,F1 fitted [Hz]."),
        weight: Weight = typer.Option("relative", "--weight",
                                      help="Error minimised: relative (by each bin's noise), "
                                           "absolute, or magnitude (relative, weighted by |H|)."),
        delay: str = typer.Option("fit", "--delay", help="Pure delay: fit, none or seconds."),
        damping_floor: float = typer.Option(None, "--damping-floor", min=0.0, max=0.99,
                                            help="Least damping ratio of a pole pair [-]; "
                                                 "default 0.0001, or a half-power width of "
                                                 "one measured bin where that is more."),
        output: Path = typer.Option(None, "-o", "--output", help="Write the fit as FIT.json."),
        fragment: Path = typer.Option(None, "--model-fragment",
                                      help="Write the transfer function as a fragment "
                                           "FRAG.yaml (no model file: read it with "
                                           "tcpmm.read_tf_fragment)."),
        plot: Path = typer.Option(None, "--plot", help="Bode plot of data, fit and residual."),
        averages: float = typer.Option(None, "--averages", min=1.0, help=_AVERAGES),
        as_json: bool = typer.Option(False, "--json")):
    """Fit a transfer function (poles, zeros, delay) to a measured frequency response."""
    from ..ident.lti import DAMPING_FLOOR, fit_frf
    from ..io.atomic import write_text_atomic
    from ..io.frffile import read_frf
    from ..io.tffragment import dumps_tf_fragment

    n = _poles(poles)
    tau = _delay(delay)
    f0, f1 = parse_band(band, "--band")
    distinct_outputs(("-o", output), ("--model-fragment", fragment), ("--plot", plot))
    if output is not None:
        checked_json_output(output, file, what="the fit")
    if fragment is not None:
        checked_yaml_output(fragment, file, what="a transfer-function fragment")
    checked_plot(plot)
    frf = read_frf(file, averages)
    with in_file(file):
        res = fit_frf(frf, poles=n, band_hz=(f0, f1), weighting=weight.value, delay_s=tau,
                      damping_floor=DAMPING_FLOOR if damping_floor is None else damping_floor)
    res.notes[:0] = [n for n in [_averages_note(frf)] if n]
    d = {"file": str(file), **res.to_dict()}
    if output is not None:
        write_text_atomic(output, json.dumps(d, indent=1) + "\n")
    if fragment is not None:
        write_text_atomic(fragment, dumps_tf_fragment(res, file))
    if plot is not None:
        res.plot(path=plot, frf=frf)
    if as_json:
        emit_json(d)
        return
    _print_fit(res, file, n)
    for p in (output, fragment, plot):
        if p is not None:
            out.print(f"wrote {p}")


def _print_fit(res, file, asked="auto") -> None:
    tf = res.tf
    # a count asked for and not kept: the notes below say which pairs went and why
    kept = f" (of {asked} asked)" if isinstance(asked, int) and asked != tf.n_den else ""
    out.print(f"{esc(str(file))}: {esc(res.name)}: {tf.n_den} poles{kept}, {tf.n_num} zeros, "
              f"delay {tf.delay_s * 1e3:.4g} ms; band {res.band_hz[0]:.4g}-"
              f"{res.band_hz[1]:.4g} Hz, {tf.freq_hz.size} bins ({res.weighting} error)")
    out.print(f"residual: relative RMS {res.rel_rms:.3g} against a noise of "
              f"{res.noise_rms:.3g} (chi2 ratio {res.chi2_ratio:.3g}); "
              f"fit {tf.fit_percent:.1f} %")
    t = plain_table(("kind", "f [Hz]", "damping [-]", "real [rad/s]", "imag [rad/s]"),
                    left=("kind",))
    df = res.to_pandas()
    devs = res.deviations
    rows = devs.by_row(df["kind"]) if devs is not None else [(None, None)] * len(df)
    for (_, r), (fe, ze) in zip(df.iterrows(), rows, strict=True):
        t.add_row(r["kind"], f"{r['freq_hz']:.5g}" if fe is None else fe.text(".5g"),
                  f"{r['damping']:.4g}" if ze is None else ze.text(),
                  f"{r['real_rad_s']:.6g}", f"{r['imag_rad_s']:.6g}")
    print_plain(t, out)
    if devs is not None:
        _print_zeros(devs.zeros)
        _print_deviations(devs, res.unit)
    for note in res.notes:
        out.print(f"note: {esc(note)}")


def _print_zeros(zeros) -> None:
    """A table of the zeros as the poles': each pair's frequency and damping, each real
    zero's corner (damping 1, or -1 in the right half-plane), with their sds [-]."""
    if not zeros:
        return
    t = plain_table(("zero", "f [Hz]", "damping [-]", "real [rad/s]", "imag [rad/s]"),
                    left=("zero",))
    for z in zeros:
        damping = (f"{-np.sign(z.root.real):.4g}" if z.damping is None
                   else z.damping.text())
        t.add_row(z.kind, z.freq.text(".5g"), damping, f"{z.root.real:.6g}",
                  f"{z.root.imag:.6g}")
    print_plain(t, out)


def _print_deviations(devs, unit: str) -> None:
    """The delay and the static gain with their standard deviations, what the +- of the
    table means, and why values are undetermined beyond their sd [-]."""
    parts = [] if devs.delay is None else [f"delay {devs.delay.text(scale=1e3)} ms"]
    if devs.gain is not None:
        parts.append(f"static gain {devs.gain.text()}" + (f" [{esc(unit)}]" if unit else ""))
    if parts:
        out.print("; ".join(parts))
    out.print("+- one standard deviation (linearised fit, the noise the residual shows); "
              "undetermined: above half the value, or as said below")
    for note in devs.notes:
        out.print(f"undetermined: {esc(note)}")
