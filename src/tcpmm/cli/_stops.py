"""A stop (Ctrl-C, SIGTERM's exit) that lands where Python ignores exceptions is raised
again where the command is."""

from __future__ import annotations


def stop_not_ignored(previous):
    """A hook for the exceptions Python ignores, raised in a collector's callback, a
    finaliser or a weak reference's callback (with a traceback on stderr): a Ctrl-C, or
    SIGTERM's exit, that lands there was lost, and the command ran on to its end (a sweep
    of a minute, exit 0). Such a stop is raised again, where the command is, as the signal
    it came from; anything else goes to ``previous`` [-]."""

    def hook(unraisable) -> None:
        import _thread
        import signal
        import threading

        exc = unraisable.exc_value
        if isinstance(exc, KeyboardInterrupt):
            signum = signal.SIGINT
        elif isinstance(exc, SystemExit) and isinstance(exc.code, int) and exc.code > 128:
            signum = exc.code - 128
        else:
            previous(unraisable)
            return
        # tripped by a thread of its own once this hook has returned: tripped here, the
        # handler would run inside the hook, whose exception Python ignores in turn
        left = threading.Event()
        _thread.start_new_thread(lambda: (left.wait(), _thread.interrupt_main(signum)), ())
        left.set()

    return hook
