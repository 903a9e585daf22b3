"""The commissioning report: one self-contained HTML file (docs/report.md).

Plain functions build its sections from what was given, each returning
``(key, title, html)``; :func:`write_report` puts them on one page and writes it
atomically. The page needs no network: figures are PNG ``data:`` URIs, the style sheet is
inline and every table downloads as CSV from a ``data:`` link under it.
"""

from __future__ import annotations

import warnings
from pathlib import Path

from ..analysis.circle_single import one_direction_diagnostics, scale_diagnostics
from ..analysis.diagnostics import circle_diagnostics
from ..errors import InputError, InputWarning
from ..io.atomic import write_text_atomic
from .acceptance import acceptance_section
from .circles import circle_section, comparison_section, result_section
from .html import page, para, section
from .machine import (
    identification_result_section,
    identification_section,
    model_section,
    read_identification_folder,
)
from .spread_page import spread_section

__all__ = ["acceptance_section", "circle_section", "circle_test_section", "comparison_section",
           "contour_section", "faults_section", "identification_result_section",
           "identification_section", "model_section", "read_identification_folder",
           "report_file", "result_section", "spread_section", "verdict_sections",
           "write_report"]


def report_file(path) -> Path:
    """Check that a report file name ends in .html (or .htm); return it as a Path [-]."""
    path = Path(path)
    if path.suffix.lower() not in (".html", ".htm"):
        raise InputError("a report file needs the extension .html (or .htm)", file=path)
    return path


def write_report(path, sections, title: str = "Commissioning report", inputs=()) -> Path:
    """Write the report page atomically.

    Parameters
    ----------
    path : str or Path
        The HTML file [-].
    sections : list of tuple
        ``(key, title, html)`` from the section functions, in the order shown [-].
    title : str
        Page title [-].
    inputs : list of tuple
        ``(what, file)`` named in the page header, or ``(what, file, shown)`` for a file
        staged to be moved to ``shown`` [-].

    Returns
    -------
    Path
        The file written [-].
    """
    path = report_file(path)
    if not sections:
        raise InputError("nothing to report: give a model, an identification, runs or a "
                         "spread", file=path)
    write_text_atomic(path, page(title, list(sections), inputs))
    return path


def circle_test_section(result, key: str = "circle", title: str = "Circular test",
                        source=None, sensor: str | None = None):
    """A circular test with its diagnostics: of the pair when it holds a CCW and a CW
    circle, else of the one direction it holds.

    Diagnostics that cannot be made (too short a circle, a sensor not in both) are left
    out with an :class:`InputWarning` saying why.

    Parameters
    ----------
    result : CircleResult
        The analysis [-].
    key, title : str
        Section anchor and title [-].
    source : str or list of str, optional
        The run file or files, for the record [-].
    sensor : str, optional
        Sensor of the diagnostics; default tcp, else scale, motor [-].
    """
    diag = _diagnostics(result, title, sensor)
    return circle_section(result, key, title, diagnostics=diag, source=source)


def verdict_sections(result, key: str = "circle", title: str = "Circular test", source=None,
                     tolerance_m=None, sample_rate_hz=None, cautions=(), measured_on=None,
                     specified=False):
    """The circle verdict (:func:`~tcpmm.report.acceptance.acceptance_section`), to open
    the page, and the circular test with its diagnostics.

    Parameters
    ----------
    result : CircleResult
        The circular test judged [-].
    key, title : str
        Anchor and title of the circular-test section [-].
    source : str or list of str, optional
        The run file or files [-].
    tolerance_m : float, optional
        Largest circular deviation accepted [m].
    sample_rate_hz : float, optional
        Sample rate of the run [Hz].
    cautions : sequence of str
        What the circle's analysis warned of; the verdict is then not firm [-].
    measured_on : datetime.date or str, optional
        Date of the test [-].
    specified : bool
        Whether ``tolerance_m`` is the machine's specification rather than the user's [-].

    Returns
    -------
    list of tuple
        The two sections [-].
    """
    diag = _diagnostics(result, title, None)
    return [acceptance_section(result, diag, tolerance_m, sample_rate_hz, source,
                               scale_diagnostics(diag, result), cautions, measured_on,
                               specified),
            circle_section(result, key, title, diagnostics=diag, source=source)]


def _diagnostics(result, title, sensor):
    """Diagnostics of a CCW and a CW circle, or of the one direction a circle holds; None
    (with a warning) when they cannot be made."""
    dirs = {p.direction for p in result.passes}
    if not dirs:
        return None
    try:
        return (circle_diagnostics(result, sensor=sensor) if dirs == {"ccw", "cw"}
                else one_direction_diagnostics(result, sensor=sensor))
    except InputError as exc:
        warnings.warn(InputWarning(f"{title}: no circle diagnostics in the report: "
                                   f"{exc.message}"), stacklevel=3)
    return None


def contour_section(result, title: str = "Contour error of the program run"):
    """The contour error along a program run, from an analysis that offers ``to_pandas()``
    and ``plot(ax=None)`` (:func:`result_section`) [-]."""
    return result_section(result, "contour", title,
                          "Signed contour error: shortest distance from the actual to the "
                          "commanded path.")


def faults_section(faults, key: str = "faults"):
    """The axes of the runs that ran away from their command or held their current at the
    limit (:mod:`tcpmm.analysis.runaway`): their figures are no prediction of a machine.

    Parameters
    ----------
    faults : list of tuple
        ``(run file, AxisFault)`` [-].
    key : str
        Section anchor [-].
    """
    body = para("These runs are no prediction of a machine: an axis left its command or held "
                "its current at the drive's limit. The circular tests below show them as they "
                "are.", "lead")
    body += "".join(para(f"{Path(f).name}: {fault.text()}", "warn") for f, fault in faults)
    return section(key, "Runaway and saturation", body)
