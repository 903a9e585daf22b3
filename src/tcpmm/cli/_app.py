"""The command-line application, its consoles and the parsing helpers every command shares.

Units at this edge: mm, mm/min, Hz, um, as the option names say.
"""

from __future__ import annotations

import errno
import io
import json
import math
import os
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path

import typer
from rich.console import Console, ConsoleDimensions

from ..errors import InputError
from ..result import json_ready
from ._encoding import unicode_stream
from ._group import Workflow
from ._jsonrow import flat_row_json


class Sensor(StrEnum):
    """Sensors a circular test is analysed for."""

    tcp = "tcp"
    scale = "scale"
    motor = "motor"
    cmd = "cmd"


# help texts carry units in brackets ([mm]); they are text, not rich markup
app = typer.Typer(cls=Workflow, add_completion=False, pretty_exceptions_enable=False,
                  rich_markup_mode=None,
                  help="Virtual machine tool: mechatronic model of the tool center point.")
machine_app = typer.Typer(help="Built-in machines and model files.", rich_markup_mode=None)
app.add_typer(machine_app, name="machine")

def on_screen(console: Console) -> bool:
    """Whether ``console`` writes to a terminal: rich's ``is_terminal`` where the stream is
    one itself, or the console was made to take it for one (``force_terminal``); a pipe or
    a file that only the environment calls a terminal (``FORCE_COLOR``, which CI systems
    set to keep their logs coloured) is none: JSON written there stays JSON, a table's
    row one line, and no progress bar is drawn into a log [-]."""
    if not console.is_terminal:
        return False
    if getattr(console, "_force_terminal", None) is not None:
        return True
    try:
        return os.isatty(console.file.fileno())
    except (AttributeError, OSError, ValueError):  # no descriptor: a stream in memory
        return False


class _Console(Console):
    """Wraps at the terminal's width on a terminal, and never in a pipe or a log: a table
    row or a message stays on one line whatever the path lengths in it (rich's default of
    80 columns for a file split cells and sentences across lines)."""

    UNWRAPPED = 1_000_000

    @property
    def size(self) -> ConsoleDimensions:
        dims = super().size
        return dims if on_screen(self) else ConsoleDimensions(self.UNWRAPPED, dims.height)

    @size.setter
    def size(self, new_size) -> None:
        Console.size.fset(self, new_size)

    def render_str(self, text: str, *, emoji: bool | None = None, **options):
        """rich's, but a text with fewer than two colons, which holds no emoji code
        (``:name:``), is said to have none: rich then does not load its table of emoji
        for a message without one (some 3 ms of a short command); the text is the same."""
        if emoji is None and text.count(":") < 2:
            emoji = False
        return super().render_str(text, emoji=emoji, **options)

    def _check_buffer(self) -> None:
        with named_stream(self.stderr):
            super()._check_buffer()

    def on_broken_pipe(self) -> None:
        """The reader went away (``| head``): nothing more is written to the stream, and
        the command ends with :data:`READER_GONE`, not rich's 1, the code of a failure."""
        self.quiet = True
        os.dup2(os.open(os.devnull, os.O_WRONLY), self.file.fileno())
        raise SystemExit(READER_GONE)


#: Exit code of a defect of tcpmm met by a command: a Python exception it did not expect
#: (1, as Python's own) [-].
INTERNAL_ERROR = 1

#: Exit code of a command whose reader went away: 128 + SIGPIPE, as a shell reports a
#: command the pipe's signal stopped [-].
READER_GONE = 128 + 13


@contextmanager
def named_stream(stderr: bool):
    """A write to standard output or error that the system refuses (a full disk, a closed
    pipe) names the stream in its error, as a file's error names the file."""
    try:
        yield
    except OSError as exc:
        if exc.filename is None:
            exc.filename = "standard error" if stderr else "standard output"
        raise


# No automatic highlighting of numbers and paths: its regular expressions took 20 ms of
# the first message (a third of a short command's work); colours come from markup.
console = _Console(stderr=True, highlight=False)
out = _Console(highlight=False)


def _print_version(value: bool) -> None:
    if value:
        from .. import __version__
        from .._blas_kernels import described
        from .._compiled import describe

        out.print(f"tcpmm {__version__}\nkernel: {describe()}\n{described()}", soft_wrap=True)
        raise typer.Exit()


@app.callback()
def _root(version: bool = typer.Option(False, "--version", callback=_print_version,
                                       is_eager=True, help="Print the version and exit.")):
    """Virtual machine tool: mechatronic model of the tool center point."""


@contextmanager
def progress_bar(total: int, description: str):
    """A progress bar on a terminal; nothing in a pipe or a log."""
    if not on_screen(console):
        yield lambda *_: None
        return
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as p:
        task = p.add_task(description, total=total)

        def advance(name=None, *_):
            p.update(task, advance=1, description=f"{description}: {name}" if name else None)

        yield advance


def floats(text: str | None, what: str, n: int | None = None) -> list[float] | None:
    if text is None:
        return None
    try:
        vals = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise typer.BadParameter(f"{what} must be numbers separated by commas, e.g. 1,2") from None
    if n is not None and len(vals) != n:
        raise typer.BadParameter(f"{what} needs {n} numbers separated by commas")
    if not vals:
        raise typer.BadParameter(f"{what} needs numbers separated by commas")
    return _finite(vals, what)


def _finite(vals, what):
    if any(not math.isfinite(v) for v in vals):
        raise typer.BadParameter(f"{what} must be finite numbers")
    return vals


def positive(value: float, what: str) -> float:
    if not (math.isfinite(value) and value > 0):
        raise typer.BadParameter(f"{what} must be a positive number, got {value:g}")
    return value


def parse_band(text: str | None, what: str) -> tuple[float, float] | tuple[None, None]:
    if text is None:
        return None, None
    f0, f1 = floats(text, what, 2)
    if not 0 <= f0 < f1:
        raise typer.BadParameter(f"{what} F0,F1 needs 0 <= F0 < F1 [Hz], got {text}")
    return f0, f1


def checked_output(output: Path, *inputs) -> Path:
    """Refuse an output that would replace one of the inputs, or whose folder cannot be
    written or made; the folder is made when the output is written."""
    from ..io.atomic import output_file

    target = output_file(output)
    for i in inputs:
        if i is not None and Path(i).exists() and Path(i).resolve() == target.resolve():
            raise typer.BadParameter(f"{output} is also an input; write the output elsewhere")
    return output


def checked_plot(plot: Path | None) -> Path | None:
    """Check a --plot file name before any work is done."""
    if plot is None:
        return None
    from ..plot import plot_file

    checked_output(plot)
    return plot_file(plot)


def checked_report_file(report: Path | None, *inputs) -> Path | None:
    """Check a --report HTML file name, and that it is none of the inputs, before any work
    is done."""
    if report is None:
        return None
    from ..report import report_file

    report_file(report)
    return checked_output(report, *inputs)


@contextmanager
def in_file(path):
    """Name ``path`` in an input error that names no file (the analysis of its content)."""
    try:
        yield
    except InputError as exc:
        if exc.file is not None:
            raise
        raise InputError(exc.message, file=path, line=exc.line, column=exc.column) from None


#: The warnings the command has said on stderr so far, each text once: ``--json`` carries
#: them too, under ``warnings``, for a program that reads only the standard output [-].
WARNED: list[str] = []


def with_warnings(data):
    """``data`` with the warnings said so far under ``warnings``, its first key, where it
    is a dict that has none of its own and there are any [-]."""
    if isinstance(data, dict) and WARNED and "warnings" not in data:
        return {"warnings": list(WARNED), **data}
    return data


def emit_json(data) -> None:
    """``data`` as JSON on stdout, indented by two: coloured on a terminal, written as it is
    elsewhere (rich's highlighter took seconds over the thousands of corners of a long
    run, for colours a pipe does not show). A number that is not finite (a figure not
    determined) is ``null``: JSON has no NaN, and a strict reader refuses it. The
    warnings said on stderr go with it (:func:`with_warnings`)."""
    text = _dumped(with_warnings(data), not unicode_stream(out.file))
    if on_screen(out):
        out.print_json(text)
    else:
        with named_stream(False):
            write_whole(out.file, text + "\n")


#: rows :func:`emit_json_rows` writes at a time, and the most it colours on a terminal [-]
JSON_BATCH_ROWS, JSON_COLOURED_ROWS = 1000, 5000


def emit_json_rows(head: dict, key: str, rows, count: int | None = None) -> None:
    """``head`` and, last, ``key`` the list of ``rows``, as :func:`emit_json` writes it;
    the rows are written as they come, a batch at a time, so that a run of millions of
    rows is never held as one text: coloured on a terminal only where they are few.

    Parameters
    ----------
    head : dict
        The leading keys [-].
    key : str
        The key of the rows, not one of ``head``'s [-].
    rows : iterable of dict
        The rows [-].
    count : int, optional
        How many rows there are, where known: on a terminal, more than
        :data:`JSON_COLOURED_ROWS` are written as they come, without colours [-].
    """
    if on_screen(out) and count is not None and count <= JSON_COLOURED_ROWS:
        emit_json({**head, key: list(rows)})
        return
    from itertools import islice

    ascii_only = not unicode_stream(out.file)
    text, rows, n = _dumped({**with_warnings(head), key: []}, ascii_only), iter(rows), 0
    with named_stream(False):
        write_whole(out.file, text[:text.rindex("[]")] + "[")
        while batch := [(flat_row_json(r, ascii_only) or _dumped(r, ascii_only))
                        .replace("\n", "\n    ") for r in islice(rows, JSON_BATCH_ROWS)]:
            write_whole(out.file, (",\n    " if n else "\n    ") + ",\n    ".join(batch))
            n += len(batch)
        write_whole(out.file, ("\n  ]" if n else "]") + "\n}\n")


def write_whole(stream, text: str) -> None:
    """``text`` written to ``stream`` whole and at once, or an OSError: Python's text
    stream over an unbuffered file (``PYTHONUNBUFFERED=1``, ``python -u``, as services and
    containers often run) drops the rest of a write the system takes only in part (a
    disk that fills), with no error; a stream over a file is therefore written to the file
    itself, each short write followed by one for the rest, which a full disk refuses [-]."""
    raw = getattr(stream, "buffer", None)
    raw = getattr(raw, "raw", raw)  # unbuffered (python -u), the buffer is the file's
    if not isinstance(raw, io.RawIOBase):  # a stream in memory
        stream.write(text)
        stream.flush()
        return
    stream.flush()
    data = memoryview(text.encode(stream.encoding or "utf-8", stream.errors or "strict"))
    while data:
        written = raw.write(data)
        if not written:  # nothing taken: none is an error of its own
            code = errno.EAGAIN if written is None else errno.ENOSPC
            raise OSError(code, os.strerror(code))
        data = data[written:]


def _dumped(data, ascii_only: bool = False) -> str:
    """``data`` as the JSON :func:`emit_json` writes: indented by two, text as it is (what
    is not ASCII escaped where ``ascii_only``), a number that is not finite ``null`` [-]."""
    return json.dumps(json_ready(data), indent=2, ensure_ascii=ascii_only, allow_nan=False)


def warn_suspect(machine, what: str) -> None:
    """Say loudly, on stderr, that a model carries the suspect marks of identification."""
    if not machine.suspect:
        return
    console.print(f"[bold red]WARNING: {esc(what)} is marked physically suspect[/bold red] "
                  "(written by tcpmm identify --accept-suspect); its predictions may be "
                  "meaningless:")
    for s in machine.suspect:
        console.print(f"[red]  - {esc(s)}[/red]")


def read_model(model: str):
    """Read a model file, warning when it carries suspect marks."""
    from ..io.modelfile import read_machine

    m = read_machine(model)
    warn_suspect(m, f"model {model}")
    return m


def refuse_unstable(machine, model: str, allowed: bool = True) -> None:
    """An error naming each axis whose sampled loop is unstable: its run would diverge;
    ``allowed``: the command takes ``--allow-unstable``, which the error then names."""
    from ..servo.sampled import is_stable_radius, radius_text, sampled_spectral_radius

    bad = {n: sampled_spectral_radius(a.mechanics, a.servo) for n, a in machine.axes.items()}
    bad = {n: r for n, r in bad.items() if not is_stable_radius(r)}
    if bad:
        axes = ", ".join(f"{n} (spectral radius {radius_text(r)})" for n, r in bad.items())
        anyway = ", or pass --allow-unstable to simulate it anyway" if allowed else ""
        raise InputError(f"the sampled servo loop of axis {axes} is unstable, so a run would "
                         "diverge rather than predict anything; check the gains and periods "
                         f"(tcpmm machine show){anyway}", file=model)


def warn_unstable(machine, what: str, axes=None) -> None:
    """A warning line per axis (of ``axes``, default all) whose sampled loop is unstable:
    what is computed from it describes no machine that holds still."""
    from ..servo.sampled import is_stable_radius, radius_text, sampled_spectral_radius

    for n in axes or machine.axes:
        a = machine.axes[n]
        r = sampled_spectral_radius(a.mechanics, a.servo)
        if not is_stable_radius(r):
            console.print(f"[yellow]warning:[/yellow] axis {esc(n)} of {esc(what)}: the "
                          f"sampled servo loop is unstable (spectral radius {radius_text(r)}); its "
                          "closed-loop responses and runs are no prediction: check the gains "
                          "and periods (tcpmm machine show)")


def load_command(command: Path | None, gcode: Path | None, machine):
    from ..path import program_to_command, read_command_csv

    if (command is None) == (gcode is None):
        raise typer.BadParameter("give exactly one of --command CMD.csv or --gcode PROG.nc")
    if command is not None:
        return read_command_csv(command)
    with in_file(gcode):
        return program_to_command(gcode, interp_settings(machine))


def interp_settings(machine):
    from ..path import InterpolatorSettings

    if machine is not None and machine.interpolation is not None:
        return InterpolatorSettings.model_validate(machine.interpolation)
    return InterpolatorSettings()


def esc(text: str) -> str:
    from rich.markup import escape

    return escape(text)
