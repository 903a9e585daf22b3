"""The interpolator over an NC program in chunks of blocks, with bounded memory.

:func:`stream_program` reads a chunk of lines, interprets it (the modal state carried,
:mod:`tcpmm.path.gcode_stream`), rounds its corners off (the last block waits for the
next chunk, :class:`~tcpmm.path.blend.CornerBlender`), plans what is final of the
look-ahead (the rest held back, :mod:`tcpmm.path.stream_plan`), samples it and runs the
post-interpolation filter with its delay line carried. The command comes out in pieces
that, put end to end, are the command of :func:`tcpmm.path.program.program_to_command`
to the bit, whatever the chunk size: all three axes, the axes the program does not move
standing where they started.
"""

from __future__ import annotations

import codecs
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.text import file_lines
from .blend import CornerBlender
from .blocktrack import BlockTrack
from .filters import filter_shape
from .gcode_stream import interpret_chunks
from .geometry import evaluate
from .interpolate import used_axes
from .program import check_program_file, is_path, read_program
from .runs import ArcRun, blocks, drop_blocks
from .segments import AXES, Arc
from .settings import InterpolatorSettings
from .stream_parts import parts
from .stream_plan import PlanState, Samples, plan_piece

#: blocks (lines) read and interpolated at a time, at most [-]
CHUNK_BLOCKS = 100_000
#: samples a chunk is sized to give, at the samples a block gave in the last chunk: a
#: program of long blocks is read fewer blocks at a time, and a chunk whose blocks would
#: give many more at their feeds is planned in parts of about as many
#: (:mod:`tcpmm.path.stream_parts`), so that a piece's command stays within memory and
#: within :data:`~tcpmm.path.interpolate.MAX_SAMPLES`. A piece's arrays (its
#: samples, the axes' records, the run's columns) of this size are reused by the memory
#: allocator from piece to piece; more than twice as large, they are mapped and faulted
#: in afresh, which cost a zig-zag of 4.7 samples a block some 0.5 s of system time per
#: million blocks and 200 MB more at its peak (docs/performance.md) [-]
CHUNK_SAMPLES = 200_000
#: command samples taken at a time within a piece where the work is followed on a
#: progress bar (an axis simulating them, a command file written): a dozen a chunk of
#: :data:`CHUNK_SAMPLES`, so that the bar moves within a chunk, each long enough that the
#: calls cost nothing beside the work [-]
PART_SAMPLES = 16_384
#: blocks of the first chunk at most, before the blocks' durations are known [-]
FIRST_CHUNK = 2_000
#: fewest blocks a chunk is sized to [-]
LEAST_CHUNK = 500
#: characters read from the file at a time [-]
_READ_CHARS = 1 << 22


@dataclass
class CommandChunk:
    """A piece of the position command.

    Parameters
    ----------
    first : int
        Index of its first sample in the whole command [-].
    time_s : ndarray
        Sample times [s].
    positions : dict of str to ndarray
        Position of X, Y and Z [m].
    path_s_m : ndarray
        Distance along the path, before the filter [m].
    lines_read : int
        Lines of the program read so far [-].
    nc_line, rapid : ndarray, optional
        Per sample, the source line of its block and 1 in a rapid
        (:class:`~tcpmm.path.blocktrack.BlockTrack`) [-].
    """

    first: int
    time_s: np.ndarray
    positions: dict
    path_s_m: np.ndarray
    lines_read: int = 0
    nc_line: np.ndarray | None = None
    rapid: np.ndarray | None = None


class StreamInterpolator:
    """The interpolator fed the path's segments a piece at a time (module docstring).

    Parameters
    ----------
    settings : InterpolatorSettings, optional
        Interpolator settings; defaults when omitted [-].
    """

    def __init__(self, settings: InterpolatorSettings | None = None):
        self.settings = settings = settings or InterpolatorSettings()
        self.filt = filter_shape(settings.filter_kind, settings.filter_time_s,
                                 settings.period_s, settings.corner_tolerance_m)
        self.blender = CornerBlender(settings.blend_tolerance_m)
        self.pending: list = []
        self.state = PlanState()
        m = self.filt.kernel.size
        self.delay_line = np.zeros((3, m - 1))  # the filter's last inputs, less x0
        self.blocks = BlockTrack(m)
        self.x0 = self.x_last = None
        self.plane_axes = None
        self.segments_in = 0
        #: the axes the path moves (X and Y always), as the whole command has them [-]
        self.used_axes: set = {"X", "Y"}
        #: most segments held back at once, the look-ahead's carried tail [-]
        self.most_held = 0

    def push(self, segments, final: bool = False) -> CommandChunk | None:
        """The command as far as it is final after ``segments`` (``None`` if none is).

        Parameters
        ----------
        segments : sequence of Line, Rapid, Arc, Dwell, LineRun
            The next segments of the path [-].
        final : bool
            The path ends with them [-].
        """
        segments = list(segments)
        self.segments_in += blocks(segments)
        if self.plane_axes is None:
            self.plane_axes = next((s.plane_axes for s in segments
                                    if type(s) is Arc or type(s) is ArcRun), None)
        if final and not self.segments_in:
            raise InputError("the path is empty: give at least one motion or dwell")
        self.pending.extend(self.blender.push(segments, final))
        smp, k = plan_piece(self.pending, self.settings, self.filt, self.state, final)
        self.pending = drop_blocks(self.pending, k)
        self.most_held = max(self.most_held, blocks(self.pending))
        if smp is None:
            return None
        self.used_axes.update(AXES[a] for a in used_axes(smp.path))
        return self._filtered(smp)

    def _filtered(self, smp: Samples) -> CommandChunk:
        """The samples as positions through the filter; at the end, its settling [-]."""
        pos = evaluate(smp.path, smp.seg, smp.s)
        if pos.shape[0]:
            self.x0 = pos[0].copy() if self.x0 is None else self.x0
            self.x_last = pos[-1].copy()
        h = self.filt.kernel
        m = h.size
        out = {}
        for a, name in enumerate(AXES):
            x = pos[:, a]
            if m == 1:
                out[name] = np.array(x, dtype=float)
                continue
            parts = []
            if x.size:
                buf = np.concatenate([self.delay_line[a], x - self.x0[a]])
                parts.append(np.convolve(buf, h, mode="valid") + self.x0[a])
                self.delay_line[a] = buf[-(m - 1):]
            if smp.last:
                rest = np.full(m - 1, self.x_last[a] - self.x0[a])
                buf = np.concatenate([self.delay_line[a], rest])
                parts.append(np.convolve(buf, h, mode="valid") + self.x0[a])
            out[name] = np.concatenate(parts) if parts else np.zeros(0)
        n_out = out["X"].size
        path_s = smp.path_s
        if n_out > path_s.size:
            path_s = np.concatenate([path_s, np.full(n_out - path_s.size, path_s[-1])])
        time_s = np.arange(smp.first, smp.first + n_out) * self.settings.period_s
        line, rapid = self.blocks.push(smp.path, smp.seg, smp.last)
        return CommandChunk(smp.first, time_s, out, path_s, nc_line=line, rapid=rapid)


def stream_program(program, settings: InterpolatorSettings | None = None,
                   chunk_blocks: int = CHUNK_BLOCKS, start_position_m=(0.0, 0.0, 0.0),
                   interpolator: StreamInterpolator | None = None) -> Iterator[CommandChunk]:
    """Interpret and interpolate an NC program a chunk of blocks at a time.

    Parameters
    ----------
    program : str or Path
        A program file, or the program text (as :func:`~tcpmm.path.program_to_command`) [-].
    settings : InterpolatorSettings, optional
        Interpolator settings; defaults when omitted [-].
    chunk_blocks : int
        Lines read and interpolated at a time [-].
    start_position_m : sequence of float
        Position of X, Y, Z before the program starts [m].
    interpolator : StreamInterpolator, optional
        The interpolator to feed (to read its state afterwards); a new one by default [-].

    Yields
    ------
    CommandChunk
        The command, piece by piece; pieces without samples are skipped [-].
    """
    if chunk_blocks < 1:
        raise InputError(f"chunk_blocks must be at least 1, got {chunk_blocks}")
    file = Path(program) if is_path(program) else None
    if file is None and not isinstance(program, str):
        raise InputError(f"expected an NC program file or its text, got "
                         f"{type(program).__name__}")
    size = ChunkSize(chunk_blocks)
    chunks = _program_chunks(program, file, size)
    ip = interpolator or StreamInterpolator(settings)
    read = [0]

    def counted():
        for c in chunks:
            read[0] += len(c)
            yield c

    it = None
    try:
        for it in interpret_chunks(counted(), file, start_position_m, runs=True):
            segs, it.segments = it.segments, []
            for part in parts(segs, ip.settings, CHUNK_SAMPLES):
                piece = ip.push(part)
                if piece is not None and piece.time_s.size:
                    piece.lines_read = read[0]
                    yield piece
            size.seen(read[0], ip.state.next_k)
        if it is not None:
            it.emit_warnings()
        if not ip.segments_in:
            raise InputError("the program has no motion and no dwell; nothing to "
                             "interpolate", file=file)
        piece = ip.push([], final=True)
    except InputError as exc:  # the interpolator knows the line, not the file
        raise exc.in_file(file) from None
    piece.lines_read = read[0]
    yield piece


class ChunkSize:
    """Blocks of the next chunk: at most ``most``; :data:`FIRST_CHUNK` at first, then as
    many as give about :data:`CHUNK_SAMPLES` samples at the samples a block gave in the
    last chunk that gave any, at most twice as many as the chunk before: an average over
    the whole program so far would keep the short blocks of its start in mind long after
    its blocks turned long (the chunks do not change the command,
    :mod:`tcpmm.path.stream`; a chunk whose blocks outrun its size is planned in parts,
    :mod:`tcpmm.path.stream_parts`) [-]."""

    def __init__(self, most: int):
        self.most = int(most)
        self.n = min(self.most, FIRST_CHUNK)
        self.lines = self.samples = 0  # when the size was last set

    def __call__(self) -> int:
        return self.n

    def seen(self, lines: int, samples: int) -> None:
        """``samples`` given out after ``lines`` lines read [-]."""
        new_lines, new_samples = lines - self.lines, samples - self.samples
        if new_lines > 0 and new_samples > 0:
            fit = max(LEAST_CHUNK, int(CHUNK_SAMPLES * new_lines / new_samples))
            self.n = min(self.most, 2 * self.n, fit)
            self.lines, self.samples = lines, samples


def _program_chunks(program, file, size) -> Iterator[list[str]]:
    """The lines of the program file ``file``, else of the text ``program``, ``size()`` at
    a time. A pipe (a shell's <(...), /dev/stdin) is read once: its text is held, as a
    program read whole is, where a file is read again for its encoding and its lines."""
    if file is not None and file.is_fifo():
        return _text_chunks(read_program(file), size)
    return line_chunks(file, size) if file else _text_chunks(program, size)


def _text_chunks(text: str, size) -> Iterator[list[str]]:
    """The lines of a program's text, ``size()`` at a time [-]."""
    lines = file_lines(text)
    i = 0
    while True:
        n = size()
        yield lines[i:i + n]
        i += n
        if i >= len(lines):
            return


def _encoding(path: Path) -> str:
    """UTF-8 (a byte-order mark allowed) where the whole file decodes as such, else
    latin-1, as :func:`~tcpmm.path.program.read_program` decides [-]."""
    dec = codecs.getincrementaldecoder("utf-8")()
    try:
        with open(path, "rb") as f:
            while block := f.read(1 << 24):
                dec.decode(block)
            dec.decode(b"", final=True)
    except UnicodeDecodeError:
        return "latin-1"  # controllers often write latin-1 comments
    return "utf-8-sig"


def line_chunks(path, size) -> Iterator[list[str]]:
    """The lines of a program file, ``size()`` at a time (asked before each chunk),
    without their line breaks (``\\n``, ``\\r\\n`` or ``\\r``, as
    :func:`~tcpmm.io.text.file_lines` counts them).

    Parameters
    ----------
    path : str or Path
        The program file [-].
    size : callable
        Lines of the next chunk, asked before each (:class:`ChunkSize`) [-].
    """
    path = check_program_file(Path(path))
    lines: list[str] = []
    rest = ""
    with open(path, encoding=_encoding(path), newline=None) as f:
        while block := f.read(_READ_CHARS):
            parts = (rest + block).split("\n")
            rest = parts.pop()
            lines.extend(parts)
            while len(lines) >= (n := size()):
                yield lines[:n]
                del lines[:n]
    if rest:
        lines.append(rest)
    while lines:
        n = size()
        yield lines[:n]
        del lines[:n]
