"""The results folder of a sweep: what was studied, the rows as they arrive, the summary.

::

    OUT_DIR/study.json              model, program, sensor, draws (hashes): what the rows are of
    OUT_DIR/results/part-*.parquet  rows, one file per batch, each written whole
    OUT_DIR/summary.csv             the design's rows in its order, written at the end
    OUT_DIR/intervals.csv           a draws design's intervals (:mod:`.intervals`)

A row holds the variant's id, its parameters (in the unit of each name), its draw, its
metrics in um (``*_um``), a circle's feed as run (``feed_run_mm_per_min``), its warning,
its fault (an axis that ran away or saturated its current) and its error. Every file is
written to a temporary name and renamed, so a stopped sweep leaves only whole files; a
rerun reads the ids of the rows present and runs the others.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import time
import uuid
from pathlib import Path

from ...errors import InputError
from ...io.atomic import atomic_path, output_folder, write_table_atomic, write_text_atomic

STUDY_FILE, PARTS_DIR, SUMMARY_FILE = "study.json", "results", "summary.csv"
LOCK_FILE = ".writing"
#: Columns of a row that are text, not metrics [-].
TEXT_COLUMNS = ("variant", "warning", "fault", "error")
#: Column of a circle's feed as run, in mm/min: less than asked where the circle caps it [-].
FEED_RUN = "feed_run_mm_per_min"


def _digest(obj) -> str:
    """The SHA-256 of a JSON-ready object's JSON, in hex digits [-]."""
    text = json.dumps(obj, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def study_record(machine, program, sensor: str, floors=None) -> dict:
    """What a sweep's rows belong to, with its hash (``key``) and that of each part
    (``parts``), by which a folder of another study says what differs [-]."""
    body = {"model": machine.model_dump(mode="json"), "program": program.to_dict(),
            "sensor": sensor, "floors": floors}
    parts = {"model": _digest(body["model"])[:16], "program": body["program"],
             "sensor": sensor, "floors": None if floors is None else _digest(floors)[:16]}
    return {"key": _digest(body), "machine": machine.name, "program": body["program"],
            "sensor": sensor, "parts": parts}


def _floors_said(digest) -> str:
    return ("none (a grid, an lhs, or draws with --fit-only)" if digest is None
            else "the model error's floors (draws without --fit-only)")


def _what_differs(had: dict, record: dict) -> str:
    """What of the study in a folder differs from this one, said part by part; a folder
    written before the parts were recorded cannot say which [-]."""
    there, here = had.get("parts"), record["parts"]
    if not isinstance(there, dict):
        return "the model, program, sensor or draws' floors differ"
    sides = [(had, there), (record, here)]
    said = [("model", "model", [f"{r.get('machine')!r} (content hash {p['model']})"
                                for r, p in sides]),
            ("program", "program", [json.dumps(p["program"]) for _, p in sides]),
            ("sensor", "sensor", [str(p["sensor"]) for _, p in sides]),
            ("draws' floors", "floors", [_floors_said(p["floors"]) for _, p in sides])]
    diffs = [f"{label}: {a} there, {b} here" for label, key, (a, b) in said
             if there.get(key) != here[key]]
    return ("what differs: " + "; ".join(diffs) if diffs
            else "the model, program, sensor or draws' floors differ")


def run_file_name(variant_id: str, study_key: str) -> str:
    """The name of a variant's run file in a ``--keep-runs`` folder: its id and its study's
    (:func:`study_record`'s key: the model, program, sensor and draws), so that studies
    sharing the folder neither overwrite nor take each other's runs [-]."""
    return f"{variant_id}-{study_key[:12]}.csv"


@contextlib.contextmanager
def writing(out_dir):
    """Hold the results folder for one sweep at a time: a second sweep into it while one
    runs would compute and write the same variants again (POSIX; elsewhere not held).

    Parameters
    ----------
    out_dir : Path
        Results folder, existing [-].
    """
    try:
        import fcntl
    except ImportError:  # not POSIX
        yield
        return
    with open(Path(out_dir) / LOCK_FILE, "a+", encoding="utf-8") as fh:
        try:
            fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            raise InputError("another sweep is writing into this folder; wait for it to "
                             "finish (running the same command afterwards adds nothing "
                             "twice), or choose another -o folder", file=out_dir) from None
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def open_study(out_dir, record: dict) -> Path:
    """Create the results folder, or check that the one there holds the same study.

    Parameters
    ----------
    out_dir : str or Path
        Results folder [-].
    record : dict
        :func:`study_record` of the sweep [-].

    Returns
    -------
    Path
        The folder [-].
    """
    out = output_folder(out_dir)
    path = out / STUDY_FILE
    if path.exists():
        try:
            had = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            raise InputError("cannot read the study of the results there; remove the folder "
                             "or choose another -o", file=path) from None
        if had.get("key") != record["key"]:
            raise InputError(f"the folder holds the results of another study ("
                             f"{_what_differs(had, record)}); choose another -o folder, or "
                             "remove this one to start again", file=out)
    else:
        write_text_atomic(path, json.dumps(record, indent=2))
    output_folder(out / PARTS_DIR)
    return out


def part_files(out_dir) -> list[Path]:
    """The result parts present, in the order they were written [-]."""
    return sorted(Path(out_dir, PARTS_DIR).glob("part-*.parquet"))


def done_variants(out_dir) -> set[str]:
    """Ids of the variants whose rows are in the folder [-]."""
    import pyarrow.parquet as pq

    done = set()
    for f in part_files(out_dir):
        done.update(pq.read_table(f, columns=["variant"]).column("variant").to_pylist())
    return done


def read_results(out_dir):
    """Every row in the folder as one table (a variant present twice: its last row).

    Parameters
    ----------
    out_dir : str or Path
        Results folder [-].

    Returns
    -------
    pandas.DataFrame
        The rows, in file units (um, and each parameter's own) [-].
    """
    import pandas as pd

    frames = [pd.read_parquet(f) for f in part_files(out_dir)]
    frames = [f for f in frames if len(f)]
    if not frames:
        return pd.DataFrame({"variant": pd.Series(dtype=str)})
    table = pd.concat(frames, ignore_index=True)
    return table.drop_duplicates("variant", keep="last").reset_index(drop=True)


def to_row(variant, result: dict) -> dict:
    """The table row of a variant's result: metrics from m to um (``*_um``) [-]."""
    row = {"variant": variant.id, **variant.params}
    if variant.draw is not None:
        row.update(draw=int(variant.draw), seed=int(variant.seed or 0))
    for k, v in result.items():
        if k == FEED_RUN:
            row[k] = float(v)
        elif k not in TEXT_COLUMNS:
            row[f"{k}_um"] = float(v) * 1e6
    row.update({k: result.get(k, "") for k in TEXT_COLUMNS[1:]})
    return row


class PartWriter:
    """Collects rows and writes them as one Parquet part per batch.

    A batch is written when it holds ``batch`` rows, when ``seconds`` have passed since
    the last part, and on :meth:`flush`; the first row at once, so that a run stopped
    early keeps what it computed and the folder shows the rows arriving.

    Parameters
    ----------
    out_dir : str or Path
        Results folder [-].
    batch : int
        Rows per part [-].
    seconds : float
        Longest time a row waits to be written [s].
    """

    def __init__(self, out_dir, batch: int = 64, seconds: float = 10.0):
        self.folder = Path(out_dir, PARTS_DIR)
        self.batch, self.seconds = max(1, int(batch)), seconds
        self.rows: list[dict] = []
        self.written = 0
        self._last = time.monotonic()

    def add(self, row: dict) -> None:
        """Keep a row; write the batch when it is due."""
        self.rows.append(row)
        if (not self.written or len(self.rows) >= self.batch
                or time.monotonic() - self._last >= self.seconds):
            self.flush()

    def flush(self) -> None:
        """Write the rows kept as one part, atomically."""
        if not self.rows:
            return
        import pandas as pd
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pa.Table.from_pandas(pd.DataFrame(self.rows), preserve_index=False)
        name = f"part-{time.time_ns():020d}-{uuid.uuid4().hex[:8]}.parquet"
        with atomic_path(self.folder / name) as tmp:
            pq.write_table(table, tmp)
        self.written += len(self.rows)
        self.rows = []
        self._last = time.monotonic()


def forget_summary(out_dir, also=()) -> None:
    """Remove the summary (and the files ``also``) a design that finished wrote: one that
    runs now writes its own at the end, and stopped before, it would leave the other's
    beside its rows, unmarked [-]."""
    for name in (SUMMARY_FILE, *also):
        Path(out_dir, name).unlink(missing_ok=True)


def write_summary(out_dir, variants) -> Path:
    """The design's rows in its order, with their index, as ``summary.csv``.

    Parameters
    ----------
    out_dir : str or Path
        Results folder [-].
    variants : list of Variant
        The design [-].

    Returns
    -------
    Path
        The file written [-].
    """
    import pandas as pd

    table = read_results(out_dir).set_index("variant")
    kept = [c for c in table.columns
            if c.endswith("_um") or c in TEXT_COLUMNS[1:] or c == FEED_RUN]
    design = pd.DataFrame([{"index": i, **{k: x for k, x in to_row(v, {}).items()
                                           if k not in kept}}
                           for i, v in enumerate(variants)])
    # one join, not a row lookup per variant (0.4 ms each: 4 s of a 10 000-variant sweep)
    frame = design[design["variant"].isin(table.index)].join(table[kept], on="variant")
    path = Path(out_dir, SUMMARY_FILE)
    write_table_atomic(frame, path, "%.10g")
    return path
