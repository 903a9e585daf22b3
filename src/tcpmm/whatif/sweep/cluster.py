"""The sweep's own Dask cluster on this machine, a client of it that closes it
quietly when a signal stops the sweep, and what a cluster's workers run that a local run
does not."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

from ...errors import InputError, TcpmmError

#: Dask's nanny starts each worker with glibc's malloc trimming memory back to the system
#: above 64 KiB; a variant allocates and frees its run's arrays, and that made it 17 %
#: slower in a worker than alone (19.5 against 16.6 ms). The sweep's workers keep glibc's
#: own threshold, and run without Dask's sampling profiler (3 % more variants per second).
NANNY_ENVIRON = {"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                 "distributed.worker.profile.enabled": False}


def local_cluster(workers: int):
    """A Dask cluster of ``workers`` processes of one thread on this machine [-].

    A terminal sends Ctrl-C to the whole process group, the workers too, and each printed
    its interpreter's traceback as it died. They are started with the interrupt ignored,
    which a new interpreter keeps, so they leave it to this process, which closes them.
    While they start (a second or two), this process ignores it too, and a watcher of the
    terminal's Ctrl-C (:func:`interrupt_watch`) stops the sweep once they have started: the
    interrupt was lost, and the sweep ran to its end. Their logs are held to the critical:
    a worker whose scheduler closed while its heartbeat was in flight logged that failure
    with its traceback, and the sweep says itself what it computed and what failed."""
    import logging
    import signal
    import threading

    import dask
    from distributed import LocalCluster

    main = threading.current_thread() is threading.main_thread()
    watch = interrupt_watch() if main else None
    before = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        with dask.config.set(NANNY_ENVIRON):
            cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", silence_logs=logging.CRITICAL)
    finally:
        if main:
            signal.signal(signal.SIGINT, before)
        interrupted = watch is not None and watch()
    if interrupted:
        cluster.close()
        raise KeyboardInterrupt
    return cluster


def interrupt_watch():
    """A process in this one's group that a terminal's Ctrl-C ends: started while this
    process still takes the interrupt (so it does too), it tells whether one came while
    this process ignored it. Returns a function that ends the watcher and says whether
    the interrupt ended it, or ``None`` where the interrupt is ignored already (a command
    in the background) or no ``sleep`` is at hand [-]."""
    import shutil
    import signal
    import subprocess

    sleep = shutil.which("sleep")
    if sleep is None or signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        return None
    proc = subprocess.Popen([sleep, "3600"], stdin=subprocess.DEVNULL,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    def ended_by_interrupt() -> bool:
        if proc.poll() is None:
            proc.kill()
        return proc.wait() == -signal.SIGINT

    return ended_by_interrupt


@contextmanager
def local_client(workers: int):
    """A client of a :func:`local_cluster` of ``workers`` processes [-]. Stopped by a
    signal, the scheduler and the event loop complained on stderr of the transfers the
    close cut short (the scheduler's KeyError, a task's exception never retrieved): their
    logs are held back while it closes."""
    import logging

    from distributed import Client

    levels = {}
    try:
        with local_cluster(workers) as cluster, Client(cluster) as client:
            try:
                yield client
            except BaseException:
                for name in ("distributed", "asyncio", "tornado"):
                    levels[name] = logging.getLogger(name).level
                    logging.getLogger(name).setLevel(logging.CRITICAL + 1)
                raise
    finally:
        for name, level in levels.items():
            logging.getLogger(name).setLevel(level)


def finished_within(futures, wait_s: float) -> list:
    """The futures of ``futures`` that are finished, or finish within ``wait_s`` [s]; a
    second interrupt ends the wait [-]."""
    from distributed import wait

    if not futures:
        return []
    try:
        wait(futures, timeout=wait_s)
    except TimeoutError:  # some still running: those finished are taken
        pass
    return [f for f in futures if f.status == "finished"]


class SchedulerLost(TcpmmError):
    """The Dask scheduler stopped mid-sweep: every task still out is lost with it, none of
    them a failure of its variant; the rows computed are kept and a rerun resumes.

    Parameters
    ----------
    client : distributed.Client
        The client that lost its scheduler [-].
    resumed : bool
        Whether the study resumes (a sweep of variants) or runs every task again (a study
        of programs, whose table is written at its end) [-].
    """

    def __init__(self, client, resumed: bool = True):
        address = getattr(getattr(client, "scheduler", None), "address", None) or "?"
        super().__init__(f"the Dask scheduler at {address} stopped: " + (
            "rerun to resume (the variants computed so far are kept)" if resumed else
            "run the same command again (a study of programs is not resumed: every pair "
            "runs again)"))


def scheduler_lost(client, exc: Exception) -> bool:
    """Whether a task's error is the loss of the scheduler rather than its own [-]."""
    from distributed.comm import CommClosedError

    return (isinstance(exc, CommClosedError) or "scheduler-connection-lost" in str(exc)
            or getattr(client, "status", "running") not in ("running", "newly-created"))


def refuse_unreadable_on_worker(path) -> None:
    """Refuse a program that this process, a Dask worker, cannot read: the command found
    it on its own machine, and "not found; check the path" sent the user to a path that
    is right there (a worker elsewhere, or without the shared folder) [-].

    Parameters
    ----------
    path : str or Path
        The program, as the command resolved it [-].
    """
    if Path(path).is_file():
        return
    try:
        from distributed import get_worker

        worker = get_worker()
    except (ImportError, ValueError):  # not on a worker: the reader says it
        return
    raise InputError(f"the Dask worker at {worker.address} cannot read {path}, which the "
                     "command found on its own machine: put the programs on a folder every "
                     "worker mounts at the same path", file=path)


#: Workers named one by one where their kernels differ from the command's; the rest are
#: counted [-].
SAID_WORKERS = 3


def _in_words(kernels) -> str:
    """A worker's :func:`tcpmm._blas_kernels.kernels` in words; ``unknown`` for ``None``."""
    if kernels is None:
        return "unknown: it did not answer"
    blas, avx512 = kernels
    loops = f"with AVX-512 ({' '.join(avx512)})" if avx512 else "without AVX-512"
    return f"{', '.join(blas) or 'no BLAS loaded'}, numpy's loops {loops}"


def workers_kernels(client, wait_s: float) -> dict:
    """Each worker's BLAS kernels and numpy loops (:func:`tcpmm._blas_kernels.kernels`) by
    its address; ``None`` for a worker that could not say within ``wait_s`` [s] [-]."""
    import threading

    from ..._blas_kernels import kernels

    got = {}

    def ask():
        try:
            got["run"] = client.run(kernels, on_error="return")
            got["workers"] = list(client.scheduler_info().get("workers", {}))
        except Exception:  # the scheduler's own trouble is said when the tasks go out
            pass

    asking = threading.Thread(target=ask, daemon=True)
    asking.start()
    asking.join(wait_s)
    said = dict(got.get("run", {}))  # an exception where a worker could not say
    return {w: (tuple(map(tuple, k)) if isinstance(k, (tuple, list)) else None)
            for w, k in {**dict.fromkeys(got.get("workers", [])), **said}.items()}


def differing_kernels(client, wait_s: float) -> str | None:
    """Which workers run other BLAS kernels or numpy loops than this process, in words with
    the fix, or ``None`` where none does [-]. A worker that ``dask worker`` started without
    the variables of ``docs/sweep.md`` loaded numpy first and runs the
    kernels its CPU chose: its figures differ from a local run's in their last digits.

    Parameters
    ----------
    client : distributed.Client
        The cluster's client [-].
    wait_s : float
        Longest wait for the workers' answers [s].
    """
    from ..._blas_kernels import kernels, pinned_variables

    here = kernels()
    odd = {w: k for w, k in workers_kernels(client, wait_s).items() if k != here}
    if not odd:
        return None
    said = [f"{w} ({_in_words(k)})" for w, k in list(odd.items())[:SAID_WORKERS]]
    more = f" and {len(odd) - SAID_WORKERS} more" if len(odd) > SAID_WORKERS else ""
    env = " ".join(f'{k}="{v}"' if " " in v else f"{k}={v}"
                   for k, v in pinned_variables().items())
    return (f"Dask workers {'; '.join(said)}{more} run other BLAS kernels or numpy loops "
            f"than this command ({_in_words(here)}): their figures may differ from a local "
            f"run's in their last digits. Start the workers with {env} in their environment "
            "(docs/sweep.md, On a cluster)")
