"""The circular tests of run files as the report and compare take them: each file's
plane said once, its analysis's warnings kept for the page's cautions."""

from __future__ import annotations

from pathlib import Path

from ._app import in_file
from ._plane import refuse_unmeasured, run_plane_said


def circle_of_file(path: Path, circle, run=None, settling: bool = True, shown=None):
    """The circular test of one run file (or of ``run``, read from it), the run's sample
    rate and what its analysis warned of, each after ``shown``, the file's name as a page
    gives it (default its name) [-, Hz, -]; the warnings are given on as well.
    ``settling``: say where a pass starts before the servo has settled (not of a
    prediction, whose transient is part of what it predicts, as ``tcpmm compare``) [-].
    ``circle`` holds the nominal radius [m], centre [m], ``--plane`` and the planes of the
    files met so far, by resolved path, which this one joins [-]."""
    import warnings

    import numpy as np

    from ..analysis.circular import analyse_circle
    from ..errors import InputWarning
    from ..io.runfile import read_run

    radius_m, centre_m, plane, planes = circle
    run = read_run(path) if run is None else run
    known = Path(path).resolve()
    if known not in planes:  # --plane, else the plane the command moves in
        planes[known] = run_plane_said(plane, run, path)
    axes = planes[known]
    refuse_unmeasured(run, axes, path)
    with in_file(path), warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", InputWarning)
        res = analyse_circle(run, radius_m, centre_m, plane=axes, settling=settling)
    said = [w for w in caught if issubclass(w.category, InputWarning)]
    for w in caught:
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    dt = np.diff(run.time_s)
    return (res, 1.0 / float(np.median(dt)) if dt.size else None,
            [f"{shown or path.name}: {w.message}" for w in said])


def analysed_pair(measured: Path, predicted: Path, circle, runs) -> tuple:
    """The circular tests of a measured and a predicted run (``runs``, read from the two
    files; the prediction cut alike, its transient not said: :func:`circle_of_file`), the
    measured run's sample rate and what its analysis warned of, for the report's
    cautions [-, -, Hz, -]."""
    from ..analysis.compare import cut_alike

    (rm, rate, said), (rp, _, _) = (circle_of_file(measured, circle, runs[0]),
                                    circle_of_file(predicted, circle, cut_alike(*runs), False))
    return rm, rp, rate, said


def compare_page(report: Path, cmp, files, rate, said, judged) -> None:
    """Write ``tcpmm compare``'s page, the one ``tcpmm report --measured --predicted``
    writes: the measured circle's verdict with the cautions ``said`` of its analysis, the
    circle, and the comparison ``cmp`` of the measured and predicted ``files`` (its TCP rows
    against the model's intervals, ``judged``, where given); ``rate`` the measured run's
    sample rate [-, -, -, Hz, -, -]."""
    from ..report import comparison_section, verdict_sections, write_report

    measured = files[0]
    write_report(report, [*verdict_sections(cmp.measured, "circle-measured",
                                            f"Circular test: {measured.name}", measured,
                                            sample_rate_hz=rate, cautions=said),
                          comparison_section(cmp, cmp.measured, cmp.predicted, files,
                                             judged=judged)],
                 "Measured against predicted", [("measured", files[0]),
                                                ("predicted", files[1])])
