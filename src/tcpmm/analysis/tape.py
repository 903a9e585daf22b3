"""Rows of numbers appended in time order (the first column the time), held in memory up to
:data:`SPILL_ROWS` and beyond that in a temporary file: a long stretch of a run costs disk,
not memory, and is read back a block at a time."""

from __future__ import annotations

import tempfile

import numpy as np

#: rows held in memory before they go to the file [-]
SPILL_ROWS = 1 << 20


class Tape:
    """Rows appended in time order; :meth:`rows` reads any of them back."""

    def __init__(self, spill_rows: int | None = None):
        self.spill_rows = spill_rows or SPILL_ROWS
        self.mem, self.in_mem = [], 0
        self.file, self.in_file = None, 0
        self.width = None
        self.chunks = []  # per block appended: its first row, first and last time

    @property
    def n(self) -> int:
        """Rows so far [-]."""
        return self.in_file + self.in_mem

    def add(self, rows) -> None:
        """Append rows, shape (n, width); the first column in time order [-]."""
        if not rows.shape[0]:
            return
        self.width = rows.shape[1]
        self.chunks.append((self.n, float(rows[0, 0]), float(rows[-1, 0])))
        self.mem.append(np.ascontiguousarray(rows, dtype=float))
        self.in_mem += rows.shape[0]
        if self.in_mem > self.spill_rows:
            if self.file is None:
                self.file = tempfile.TemporaryFile(prefix="tcpmm-tape-")
            self.file.seek(0, 2)
            for r in self.mem:
                self.file.write(r.tobytes())
            self.in_file, self.mem, self.in_mem = self.n, [], 0

    def rows(self, a: int, b: int) -> np.ndarray:
        """Rows ``a:b``, shape (b - a, width) [-]."""
        parts = []
        if a < self.in_file:
            self.file.seek(a * self.width * 8)
            k = min(b, self.in_file) - a
            raw = self.file.read(k * self.width * 8)
            parts.append(np.frombuffer(raw, float).reshape(k, self.width))
        if b > self.in_file:
            mem = np.concatenate(self.mem) if len(self.mem) > 1 else self.mem[0]
            parts.append(mem[max(a - self.in_file, 0):b - self.in_file])
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def column(self, a: int, b: int, col: int, block: int = 1 << 18) -> np.ndarray:
        """Column ``col`` of rows ``a:b``, read ``block`` rows at a time so the other
        columns of a long stretch are never all in memory [-]."""
        return np.concatenate([self.rows(lo, min(lo + block, b))[:, col]
                               for lo in range(a, b, block)] or [np.empty(0)])

    def count(self, x: float, side: str) -> int:
        """Rows whose time is before ``x`` (``"left"``) or not after it (``"right"``)
        [-]."""
        starts = [c[1] for c in self.chunks]
        k = int(np.searchsorted(starts, x, side=side)) - 1
        if k < 0:
            return 0
        first, _, last = self.chunks[k]
        end = self.chunks[k + 1][0] if k + 1 < len(self.chunks) else self.n
        if last < x or (side == "right" and last == x):
            return end
        return first + int(np.searchsorted(self.rows(first, end)[:, 0], x, side=side))

    def close(self) -> None:
        """Let go of the rows and the file."""
        if self.file is not None:
            self.file.close()
        self.file, self.mem, self.in_mem, self.in_file = None, [], 0, 0
