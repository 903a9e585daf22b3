"""Compensation on machines tcpmm did not generate: C, D, E, H, R05, R17 of the independent
simulator (docs/validation/compensation.md).

For each machine the model is identified from its bundle, the command is compensated on
that model (scaled back over draws of the model), and the compensated command is run on the
TRUE machine (its truth.yaml); the TCP figures before and after are printed as a table.

    .venv/bin/python -m studies.compensation [--machines c,d,e,h,r05,r17]
        [--programs "circle F10000,..."] [--accel-m-per-s2 4] [--jerk-m-per-s3 J]
        [--draws 6] [--headroom 0.25] [--cache DIR]
        [--out docs/validation/compensation_table.md]

Without --accel-m-per-s2 the correction keeps the models' interpolation settings (none of
the identified models has any, so 1 m/s^2); with it, every axis's limit for the correction,
and the rows are labelled with it. The programs themselves stay as interpolated.
"""

from __future__ import annotations

import argparse
import pickle
import warnings
from pathlib import Path

from tcpmm.analysis.circle_find import command_circle
from tcpmm.compensate import machine_bounds, predicted_scores
from tcpmm.compensate.candidates import compensate_within_draws
from tcpmm.compensate.headroom import DEFAULT_HEADROOM, on_the_program, program_with_headroom
from tcpmm.compensate.scores import (
    corner_rises,
    judge,
    judged_path,
    programmed_path,
    runs_before_after,
)
from tcpmm.io.bundle import read_bundle
from tcpmm.io.truthfile import machine_from_truth
from tcpmm.path import InterpolatorSettings, read_command_csv

from . import DATA

#: CAM-style square, 40 mm, continuous path with a contour tolerance [mm].
SQUARE = """G90 G17 G64 P0.01 F5000
G1 X40 Y0
G1 X40 Y40
G1 X0 Y40
G1 X0 Y0
"""
#: The square with the tool held half a second at two corners: a program whose hold the
#: correction must keep, run only where named in ``--programs`` [mm, s].
SQUARE_DWELLS = """G90 G17 G64 P0.01 F5000
G1 X40 Y0
G4 P0.5
G1 X40 Y40
G1 X0 Y40
G4 P0.5
G1 X0 Y0
"""
#: Programs run only where named
OPTIONAL = ("square G64 dwells",)


def spiral(turns: int = 3, r0_mm: float = 5.0, pitch_mm: float = 5.0, step_deg: float = 5.0,
           feed_mm_min: float = 5000.0) -> str:
    """An Archimedean spiral as a CAM posts it: short G1 blocks under G64 [-]."""
    import numpy as np

    th = np.deg2rad(np.arange(0.0, 360.0 * turns + step_deg, step_deg))
    r = r0_mm + pitch_mm * th / (2 * np.pi)
    lines = [f"G90 G17 G64 P0.005 F{feed_mm_min:g}", f"G1 X{r0_mm:.4f} Y0"]
    lines += [f"G1 X{ri * np.cos(t):.4f} Y{ri * np.sin(t):.4f}" for ri, t in
              zip(r, th, strict=True)]
    return "\n".join(lines) + "\n"


def model_of(name: str, cache: Path):
    """The model identified from the machine's bundle, cached [-]."""
    from tcpmm.ident.pipeline import identify_bundle

    f = cache / f"ident_{name}.pkl"
    if f.exists():
        return pickle.loads(f.read_bytes()).machine
    ident = identify_bundle(read_bundle(DATA / f"bench_{name}" / "bundle"))
    cache.mkdir(parents=True, exist_ok=True)
    f.write_bytes(pickle.dumps(ident))
    return ident.machine


def programs(name: str, model, headroom: float):
    """(label, command at the full limits, command the correction is learned on, circle
    radius or None) of the machine; the NC programs planned with ``headroom`` as
    ``tcpmm compensate --gcode`` plans them [-]."""
    d = DATA / f"bench_{name}"
    settings = InterpolatorSettings.model_validate(model.interpolation or {})
    for label, file in (("circle F5000", "circle_ccw_cmd.csv"),
                        ("circle F10000", "circle_ccw_fast_cmd.csv")):
        cmd = read_command_csv(d / file)
        yield label, cmd, cmd, 0.035
    for label, text in (("spiral G64", spiral()), ("square G64", SQUARE),
                        ("square G64 dwells", SQUARE_DWELLS)):
        full, planned = program_with_headroom(text, settings, headroom)
        yield label + (f" (headroom {headroom:g})" if headroom else ""), full, planned, None


def one(name: str, model, truth, label, commands, radius, draws: int, limits=(None, None),
        judged="given"):
    """Figures at the true machine's TCP before (the program at the full limits) and after,
    and the draws' verdict; the correction within the axes' ``limits`` (acceleration
    [m/s^2], jerk [m/s^3]); the circle the draws judge: the ``radius`` about the origin
    (``judged="given"``, ``--radius``), the one the command runs (``"command"``, as
    ``tcpmm compensate`` takes it without ``--radius``) or none (``"none"``) [-]."""
    full, _ = commands
    comp, planned = compensation_of(model, commands, *drawn_circle(judged, radius, full),
                                    draws, limits)
    before, after = runs_before_after(truth, comp, programmed=full)
    b = judge(before, programmed_path(comp, full), radius)
    a = judge(after, judged_path(comp), radius)
    rob = comp.robustness
    # the draws judge the compensation against the program they were given, uncompensated
    planned_run = before if planned is full else runs_before_after(truth, comp)[0]
    return {"machine": name.upper(), "program": label,
            "factors": rob["factors"], "by_region": rob.get("by_region", False),
            "trusted": rob["trusted_share"],
            "firm": rob["firm_share"],
            "firm_truth": truth_where_firm(comp, planned_run, after),
            "rises": truth_rises(comp, planned_run, after),
            "spike_verdict": rob.get("circle", {}).get("spike", {}).get("verdict", "-"),
            "ce_before": b["path"]["contour_error_um"], "ce_after": a["path"]["contour_error_um"],
            "rms_before": b["path"]["contour_rms_um"], "rms_after": a["path"]["contour_rms_um"],
            "spike_before": b.get("circle", {}).get("largest_spike_um"),
            "spike_after": a.get("circle", {}).get("largest_spike_um"),
            "g_before": b.get("circle", {}).get("circular_deviation_um"),
            "g_after": a.get("circle", {}).get("circular_deviation_um"),
            "co_before": b["path"]["corner_overshoot_um"],
            "co_after": a["path"]["corner_overshoot_um"],
            "co_rises": corner_rises({"before": b, "after": a}, 0.1),
            "spikes_grown": spikes_grown(b, a)}


def drawn_circle(judged: str, radius, full) -> tuple:
    """``(radius, centre)`` of the circle the draws judge (:func:`one`'s ``judged``), or
    ``(None, origin)``: the program judged as a path, as ``tcpmm compensate`` judges a
    command it finds no circle in [m]."""
    if radius is None or judged == "none":
        return None, (0.0, 0.0)
    if judged == "command":
        return command_circle(full.positions, ("X", "Y")) or (None, (0.0, 0.0))
    return radius, (0.0, 0.0)


def compensation_of(model, commands, radius, centre=(0.0, 0.0), draws: int = 16,
                    limits=(None, None)):
    """The compensation of ``commands`` (the program at the full limits, the command the
    correction is learned on) as ``tcpmm compensate`` makes it, judged on the circle of
    ``radius`` about ``centre`` where given, and the command it was learned on in the end
    (the program, where it was learned again on it) [-]."""
    full, planned = commands
    bounds = machine_bounds(model, *limits)

    def learned(on):
        comp = compensate_within_draws(model, on, n_draws=draws, bounds=bounds,
                                       radius_m=radius, centre_m=centre)
        comp.scores = predicted_scores(model, comp, radius, centre,
                                       programmed=full if on is not full else None)
        return comp

    comp = learned(planned)
    if planned is not full:  # as tcpmm compensate --gcode writes it
        circle = None if radius is None else (radius, centre, ("X", "Y"))
        comp, kept = on_the_program(model, full, comp, bounds, lambda: learned(full), circle)
        planned = planned if kept else full
    return comp, planned


def spikes_grown(before: dict, after: dict) -> list:
    """The quadrant points whose spike grew on the true machine by more than the
    sensors' resolution, 0.1 um, pass by pass (\"spike C\", ...) [-]."""
    out = []
    for pb, pa in zip(before.get("circle", {}).get("passes", []),
                      after.get("circle", {}).get("passes", []), strict=False):
        for k, v in pb["spikes_um"].items():
            w = pa["spikes_um"].get(k, float("nan"))
            if abs(w) > abs(v) + 0.1 and f"spike {k}" not in out:  # NaN: not crossed
                out.append(f"spike {k}")
    return out


def truth_errors(comp, before, after):
    """The true machine's distance from the path per sample before (the planned run, from
    its own command, as the draws judge it) and after (from the delayed path), on the
    compensation's samples; NaN where a run has none [m]."""
    import numpy as np

    from tcpmm.analysis.contour import contour_error

    n = comp.target.time_s.size
    e_b = np.abs(contour_error(before, command=comp.reference).errors["tcp"])
    e_a = np.abs(contour_error(after, command=judged_path(comp)).errors["tcp"])
    out = np.full((2, n), np.nan)
    out[0, :min(n, e_b.size)], out[1, :min(n, e_a.size)] = e_b[:n], e_a[:n]
    return out


def truth_where_firm(comp, before, after):
    """The true machine's largest contour error before / after over the samples of the
    regions the draws call firm, and the least of it region by region; ``None`` where
    none is [-]."""
    import numpy as np

    from tcpmm.compensate.robust import regions

    labels = regions(comp.target)
    # none where the program is written as programmed: its draws judged another plan
    firm = [r["region"] for r in comp.robustness.get("regions", []) if r["verdict"] == "firm"]
    if not firm:
        return None
    e_b, e_a = truth_errors(comp, before, after)

    def fall(keep):
        mask = np.isin(labels, keep)
        return float(np.nanmax(e_b[mask]) / max(np.nanmax(e_a[mask]), 1e-9))

    return fall(firm), min(fall([r]) for r in firm)


def truth_rises(comp, before, after) -> dict:
    """Where the true machine's error rises above its envelope before, as the draws judge
    it (:func:`tcpmm.compensate.trust.local_rises`): the share of the samples, the share
    of those the draws trusted, and the largest rise on a trusted sample, before and
    after [-, -, um]."""
    import numpy as np

    from tcpmm.compensate.robust import margin, regions
    from tcpmm.compensate.trust import local_rises

    e_b, e_a = np.nan_to_num(truth_errors(comp, before, after))
    mask, _ = local_rises(e_b[None], e_a[None], comp.target, margin)
    trusted, top = local_rises(e_b[None], np.where(comp.trusted, e_a, 0.0)[None],
                               comp.target, margin)
    # the regions' verdicts alone, as "trusted" was before samples were held to their own
    good = [r["region"] for r in comp.robustness.get("regions", [])
            if r["verdict"] != "uncertain"]
    by_region = mask & np.isin(regions(comp.target), good)
    return {"share": float(mask.mean()),
            "trusted": float(trusted.sum() / max(mask.sum(), 1)),
            "by_region": float(by_region.sum() / max(mask.sum(), 1)),
            "largest_trusted_um": (top["before_um"], top["after_um"]) if trusted.any()
            else None}


def corners_worse(rises: list) -> str:
    """The corners whose overshoot grew (:func:`tcpmm.compensate.scores.corner_rises`),
    in words: the one that grew most, before -> after, and how many did [um]."""
    _, b, a = max(rises, key=lambda r: r[2] - r[1])
    more = f"; {len(rises)} corners" if len(rises) > 1 else ""
    return f"corner overshoot ({b:.2f} -> {a:.2f}{more})"


def ratio(before, after) -> str:
    """Reduction ``before / after``, ``-`` where the figure is not judged [-]."""
    if before is None or after is None:
        return "-"
    return f"{before / max(after, 1e-3):.1f}x"


def table(rows: list) -> str:
    """The results as a Markdown table; "worse" names a figure that grew on the true
    machine by more than the sensors' resolution, 0.1 um (the contour error, the largest
    spike, G and each corner's overshoot, with the values before -> after of the one that
    grew most [um]), and
    each quadrant point whose spike did [-]."""
    def f(v):
        return "-" if v is None else f"{v:.2f}"

    # the rms over the run as :func:`tcpmm.compensate.scores.judge` takes it by default,
    # with the hold the TCP settles over (the console's is over the motion alone)
    out = ["| machine | program | factors X/Y | trusted | firm | contour error before -> after "
           "[µm] | rms over the run, settling hold included, before -> after [µm] "
           "| largest spike before -> after [µm] | G before -> after [µm] "
           "| reduction contour / spike / G | true reduction where firm | spike verdict "
           "| worse | true machine's samples that rise; of them trusted (largest such rise "
           "[µm]); by the regions alone |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        fx = "/".join(f"{v:.2g}" for v in r["factors"].values())
        fx += " (by region)" if r["by_region"] else ""
        red = " / ".join(ratio(r[f"{k}_before"], r[f"{k}_after"]) for k in ("ce", "spike", "g"))
        worse = [name for k, name in (("ce", "contour"), ("spike", "spike"), ("g", "G"))
                 if r[f"{k}_before"] is not None and r[f"{k}_after"] > r[f"{k}_before"] + 0.1]
        if r.get("co_rises"):  # not in another column
            worse.append(corners_worse(r["co_rises"]))
        worse += r.get("spikes_grown", [])
        firm = ("-" if r["firm_truth"] is None
                else "{:.1f}x (least region {:.1f}x)".format(*r["firm_truth"]))
        rises = r["rises"]
        rise = (f"{rises['share']:.1%}; trusted {rises['trusted']:.1%}"
                + (" ({:.2f} -> {:.2f})".format(*rises["largest_trusted_um"])
                   if rises["largest_trusted_um"] else "")
                + f"; by the regions alone {rises['by_region']:.1%}")
        out.append(f"| {r['machine']} | {r['program']} | {fx} | {r['trusted']:.0%} "
                   f"| {r['firm']:.0%} "
                   f"| {f(r['ce_before'])} -> {f(r['ce_after'])} "
                   f"| {f(r['rms_before'])} -> {f(r['rms_after'])} "
                   f"| {f(r['spike_before'])} -> {f(r['spike_after'])} "
                   f"| {f(r['g_before'])} -> {f(r['g_after'])} | {red} | {firm} "
                   f"| {r['spike_verdict']} | {', '.join(worse) or '-'} | {rise} |")
    return "\n".join(out) + "\n"


def limits_label(limits) -> str:
    """What a row's correction was allowed, where it is not the models' default [-]."""
    parts = [f"{v:g} {u}" for v, u in zip(limits, ("m/s²", "m/s³"), strict=True)
             if v is not None]
    return f" (correction ≤ {', '.join(parts)})" if parts else ""


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--machines", default="c,d,e,h,r05,r17")
    p.add_argument("--programs", default=None,
                   help="comma-separated program labels, e.g. 'circle F10000'")
    p.add_argument("--accel-m-per-s2", type=float, default=None)
    p.add_argument("--jerk-m-per-s3", type=float, default=None)
    p.add_argument("--draws", type=int, default=6)
    p.add_argument("--headroom", type=float, default=DEFAULT_HEADROOM,
                   help="share of the acceleration and jerk the NC programs leave to the "
                        "correction, as tcpmm compensate --gcode")
    p.add_argument("--cache", type=Path, default=Path("/tmp/compensate"))
    p.add_argument("--out", type=Path, default=None)
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    rows, limits = [], (args.accel_m_per_s2, args.jerk_m_per_s3)
    for name in args.machines.split(","):
        model = model_of(name, args.cache)
        truth = machine_from_truth(DATA / f"bench_{name}" / "truth.yaml")
        for label, full, planned, radius in programs(name, model, args.headroom):
            base = label.split(" (")[0]
            named = args.programs.split(",") if args.programs is not None else None
            if (base not in named) if named is not None else (base in OPTIONAL):
                continue
            label += limits_label(limits)
            try:
                rows.append(one(name, model, truth, label, (full, planned), radius,
                                args.draws, limits))
            except Exception as exc:  # one machine's refusal does not end the study
                print(f"{name.upper()} {label}: {exc}", flush=True)
                continue
            print(table(rows[-1:]).splitlines()[-1], flush=True)
    text = table(rows)
    print(text)
    if args.out is not None:
        from tcpmm.io.atomic import write_text_atomic

        write_text_atomic(args.out, text)


if __name__ == "__main__":
    main()
