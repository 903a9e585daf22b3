"""Command-line interface: ``tcpmm --help``.

One module per command group; no logic beyond parsing and printing. A command's module
is imported when that command runs (:data:`COMMANDS`): a command does not pay for the
imports of the others (numpy, scipy, pydantic models); the list of commands (``tcpmm
--help``, a mistyped command) imports them all.
"""

from __future__ import annotations

import importlib
import os
import sys
import warnings

from .._threads import single_threaded_from_start
from ._collector import collect_late
from ._memory import keep_freed_memory
from ._stops import stop_not_ignored

collect_late()  # before the imports of typer, rich and the command's module
single_threaded_from_start()  # before the commands' modules load numpy
keep_freed_memory()  # before they load pyarrow
# pydantic's plugins are not looked for: the search reads the metadata of every installed
# distribution, some 10 ms of a short command (a value the user set is kept)
os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")

from ..errors import BuildNotice, InputWarning, TcpmmError  # noqa: E402
from ._app import INTERNAL_ERROR, READER_GONE, WARNED, app, console, esc  # noqa: E402
from ._encoding import fit_standard_streams  # noqa: E402

#: The module of this package that registers each command (or command group) on
#: :data:`tcpmm.cli._app.app` when it is imported.
COMMANDS = {
    "demo": "run", "machine": "machine", "excite": "ident", "identify": "ident",
    "frf": "frf", "bode": "machine", "path": "run", "simulate": "run", "circle": "run",
    "contour": "contour", "compare": "run", "spread": "ident", "sweep": "sweep",
    "tune": "tune", "report": "report", "compensate": "compensate",
}


#: Commands whose result is what they print (their tables), not files they write [-].
PRINTED = {"circle", "compare", "contour", "bode", "spread", "show"}
#: Commands that print their result where no file is given for it (-o) [-].
PRINTED_WITHOUT_FILE = {"tune", "fit"}


def refuse_closed_stdout(argv) -> None:
    """Refuse, before any work, a command whose result goes to a standard output that is
    closed (``>&-``: Python's ``sys.stdout`` is None), where it would go nowhere with
    exit 0; a command that writes its result to files runs [-]."""
    if sys.stdout is not None:
        return
    words = [a for a in argv if not a.startswith("-")]
    printed = ("--json" in argv or "--version" in argv or "--help" in argv or not argv
               or any(w in PRINTED for w in words[:2])
               or (any(w in PRINTED_WITHOUT_FILE for w in words[:2])
                   and not {"-o", "--output"} & set(argv)))
    if printed:
        raise TcpmmError("standard output is closed, so what this command prints would go "
                         "nowhere; run it with its standard output open (> FILE, or "
                         "> /dev/null to discard it)")


def register(argv) -> None:
    """Import the module of the command ``argv`` names (its first word that is no
    option; the root takes no option with a value); none for ``--version`` alone; every
    command's module where it names none or one unknown: the list of commands and
    click's suggestions need them."""
    name = next((a for a in argv if not a.startswith("-")), None)
    if name is None and argv and "--help" not in argv:
        return  # --version: the root's own option
    wanted = {COMMANDS[name]} if name in COMMANDS else set(COMMANDS.values())
    for module in sorted(wanted):
        importlib.import_module(f"{__name__}.{module}")


def main(argv=None) -> int:
    """Entry point of the ``tcpmm`` console script: the command's exit code, decided once
    what it wrote to the standard output is written."""
    return _flushed(_command(argv))


def _flushed(code: int) -> int:
    """``code``, or 2 where the rest of what the command wrote to the standard output
    cannot be written (a full disk), said in one line; :data:`READER_GONE` where the
    reader went away. The interpreter's own last flush would say it in a traceback, with
    a code of its own, after the command's had been decided."""
    try:
        if sys.stdout is not None:
            sys.stdout.flush()
    except OSError as exc:
        try:  # what is left in the buffer goes nowhere, not into a second error at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError):
            pass
        if isinstance(exc, BrokenPipeError):
            return code or READER_GONE
        if code == 0:
            console.print(f"[red]error:[/red] {esc(exc.strerror or str(exc))} "
                          "(standard output)")
            return 2
    return code


def _command(argv) -> int:
    """The command ``argv`` run, its errors said in one line; its exit code [-]."""
    fit_standard_streams()
    shown = warnings.showwarning
    told = set()

    def show(message, category, filename, lineno, file=None, line=None):
        """Print input warnings as the user's problem, not as a place in the package, each
        text once: Python's own once-per-place rule forgets what it showed whenever a
        filter changes on the way, and a warning's place says nothing to the user."""
        if issubclass(category, InputWarning):
            if str(message) not in told:
                told.add(str(message))
                WARNED.append(str(message))
                console.print(f"[yellow]warning:[/yellow] {esc(str(message))}")
        elif issubclass(category, BuildNotice):
            console.print(f"note: {esc(str(message))}")
        elif issubclass(category, RuntimeWarning) and not os.environ.get("TCPMM_TRACEBACK"):
            return  # numpy's note on a NaN or an empty mean: the user can do nothing with it
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show
    WARNED.clear()
    _warn_cache_fallback()
    handlers = _exit_on_signals()
    usage = _usage_error()
    usage_shown, usage.show = usage.show, _usage_line
    try:
        refuse_closed_stdout(sys.argv[1:] if argv is None else list(argv))
        register(sys.argv[1:] if argv is None else list(argv))
        app(args=argv, standalone_mode=True)
    except TcpmmError as exc:
        console.print(f"[red]error:[/red] {esc(str(exc))}")
        return 2
    except OSError as exc:  # the system refused a file or a folder the command used
        where = f" ({exc.filename})" if exc.filename else ""
        console.print(f"[red]error:[/red] {esc((exc.strerror or str(exc)) + where)}")
        return 2
    except SystemExit as exc:
        code = int(exc.code or 0) if not isinstance(exc.code, str) else 1
        return READER_GONE if code == 1 and _reader_gone() else _said_stopped(code)
    except KeyboardInterrupt:  # before or after the command, where typer does not see it
        return _said_stopped(130)
    except Exception as exc:  # a defect of tcpmm: one line, not a traceback, for the user
        if _said_no_cache(exc):
            return 2
        if os.environ.get("TCPMM_TRACEBACK"):
            raise
        console.print(f"[red]error:[/red] internal error, a defect of tcpmm "
                      f"({esc(type(exc).__name__)}: {esc(str(exc))}); please report it "
                      "with the command that met it (TCPMM_TRACEBACK=1 shows where)")
        return INTERNAL_ERROR
    finally:
        usage.show = usage_shown
        warnings.showwarning = shown
        WARNED.clear()
        _restore_signals(handlers)
    return 0


def _usage_error() -> type:
    """click's ``UsageError``, whichever click typer runs on (its own copy since 0.20,
    the installed one before): the base of typer's ``BadParameter``."""
    import typer

    return next(c for c in typer.BadParameter.__mro__ if c.__name__ == "UsageError")


def _usage_line(self, file=None) -> None:
    """A misused option or command in one line, as every other refusal: click's usage
    line, hint and blank line before its message split one error over four lines of a
    log. The message keeps click's suggestion ("Did you mean ...")."""
    where = self.ctx.command_path if self.ctx is not None else "tcpmm"
    text = " ".join(self.format_message().split())
    console.print(f"[red]error:[/red] {esc(text)} ('{esc(where)} --help' lists what it "
                  "takes)")


def run() -> int:
    """The ``tcpmm`` console script: :func:`main`, then an exit that does not collect.

    The command has finished and closed what it wrote; what is left is the interpreter's
    last collections over every object of the process (some 45 000 after a simulation,
    about a fifth of a short command's time). The objects are frozen out of those
    collections: the process ends as soon, with the same outputs and exit code.
    """
    import gc
    import threading

    try:
        code = main()
        gc.freeze()
    except KeyboardInterrupt:  # one the command's end outran (:func:`._stops.stop_not_ignored`)
        code = _said_stopped(130)
    if code >= 128 and threading.active_count() > 1:
        # stopped by a signal, its outputs removed: the axes' kernels still running in
        # worker threads would hold the exit until they end (minutes on a long command)
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(code)
    return code


def _reader_gone(fd: int | None = None) -> bool:
    """Whether the reader of the standard output (or of the pipe ``fd``) went away
    (``| head`` closed the pipe) during a write outside rich's console (which ends with
    ``READER_GONE`` itself): typer then ends the command with 1, the code of a failure.
    The pipe says so itself: its end that writes polls as an error once no one reads [-]."""
    import select

    try:
        poll = select.poll()
        poll.register(sys.__stdout__.fileno() if fd is None else fd, select.POLLOUT)
        return any(event & select.POLLERR for _, event in poll.poll(0))
    except (AttributeError, OSError, ValueError):  # no poll (Windows), no standard output
        return False


def _warn_cache_fallback() -> None:
    """One line when numba's compiled functions could be cached neither beside the package
    nor in the user's cache folder: they then compile again in every new temporary folder."""
    from .._numba_cache import FALLBACK

    if FALLBACK:
        console.print(f"[yellow]warning:[/yellow] neither the package's __pycache__ folders "
                      f"nor the user's cache folder can be written; numba's compiled "
                      f"functions are cached in {esc(FALLBACK[0])}")


def _said_no_cache(exc: Exception) -> bool:
    """Whether ``exc`` is numba's want of a cache folder, said in one line with the fix."""
    from .._numba_cache import no_cache_error

    message = no_cache_error(exc)
    if message is not None:
        console.print(f"[red]error:[/red] {esc(message)}")
    return message is not None


def _said_stopped(code: int) -> int:
    """``code``, said on stderr in one line where it is that of a stop by a signal
    (128 + SIGINT, SIGTERM or SIGHUP), unless the command said it itself: a stopped
    command's outputs are removed, and an exit in silence looks like a crash [-]."""
    import signal

    from ._outputs import STOP_SAID

    names = {128 + int(s): s.name for s in (signal.SIGINT, signal.SIGTERM,
                                            getattr(signal, "SIGHUP", signal.SIGTERM))}
    if code in names and not STOP_SAID:
        console.print(f"stopped ({names[code]}): nothing was written", highlight=False)
    STOP_SAID.clear()
    return code


def _exit_on_signals() -> dict:
    """Turn SIGTERM and SIGHUP into an orderly exit (128 + signal number), so that outputs
    being written are removed rather than left half-written; returns the handlers before.
    Only the main thread can set handlers; elsewhere nothing changes."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return {}

    def leave(signum, frame):
        raise SystemExit(128 + signum)

    before = {}
    for name in ("SIGTERM", "SIGHUP"):
        sig = getattr(signal, name, None)
        if sig is not None:
            before[sig] = signal.signal(sig, leave)
    before["unraisable"] = sys.unraisablehook
    sys.unraisablehook = stop_not_ignored(sys.unraisablehook)
    return before


def _restore_signals(before: dict) -> None:
    import signal

    for sig, handler in before.items():
        if sig == "unraisable":
            sys.unraisablehook = handler
        else:
            signal.signal(sig, handler)



if __name__ == "__main__":
    sys.exit(main())
