"""Inputs that can be read only once (a shell's ``<(...)``) read as their files do."""

import os
import threading

import numpy as np
import pytest

from tcpmm.errors import InputError
from tcpmm.io.csvutil import read_numeric_csv
from tcpmm.io.runfile import read_run_csv

RUN = "time_s,x_cmd_mm,x_scale_mm\n0.000,1.0,1.0\n0.001,1.5,1.4\n"


def through_fifo(tmp_path, text, read):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)

    def write():
        with open(fifo, "w", encoding="utf-8") as fh:
            fh.write(text)

    writer = threading.Thread(target=write)
    writer.start()
    try:
        return read(fifo)
    finally:
        writer.join(timeout=10)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
def test_a_run_and_a_record_read_from_a_pipe(tmp_path):
    run = through_fifo(tmp_path, RUN, read_run_csv)
    assert np.allclose(run.axes["X"].scale, [1e-3, 1.4e-3])
    (tmp_path / "again").mkdir()
    cols = through_fifo(tmp_path / "again", RUN,
                        lambda p: read_numeric_csv(p, ["time_s"], ["x_cmd_mm", "x_scale_mm"]))
    assert cols["time_s"].tolist() == [0.0, 0.001]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
def test_a_broken_run_in_a_pipe_is_named_at_its_line(tmp_path):
    with pytest.raises(InputError, match="line 4, column 'x_cmd_mm'"):
        through_fifo(tmp_path, RUN + "0.002,oops,1.5\n", read_run_csv)


def test_an_output_that_is_a_pipe_is_written_into_not_replaced(tmp_path):
    """``-o`` onto a FIFO (as onto /dev/null, /dev/stdout or a device) writes into it; a
    temporary file renamed onto it replaced the node with a regular file (as root,
    ``-o /dev/full`` replaced the device)."""
    import stat

    from tcpmm.io.atomic import write_text_atomic

    fifo = tmp_path / "out"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_text()), daemon=True)
    reader.start()  # a daemon: where the pipe was replaced it waits on it for good
    write_text_atomic(fifo, "a,b\n1,2\n")
    reader.join(timeout=10)
    assert stat.S_ISFIFO(os.stat(fifo).st_mode)
    assert got == ["a,b\n1,2\n"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary file left


def test_a_model_and_a_truth_file_read_from_a_pipe(tmp_path, vmc):
    """`tcpmm tune <(cat model.yaml)` said 'machine model not found': a model read from a
    pipe (once: a truth file's format is looked at in the text read) reads as its file."""
    from tcpmm.io.modelfile import dumps_machine, read_machine

    assert through_fifo(tmp_path, dumps_machine(vmc), read_machine) == vmc
    from conftest import bench_path

    truth = bench_path("c") / "truth.yaml"
    fifo_dir = tmp_path / "truth"
    fifo_dir.mkdir()
    assert through_fifo(fifo_dir, truth.read_text(), read_machine) == read_machine(truth)


def test_a_device_is_no_model_file():
    from tcpmm.io.modelfile import read_machine

    with pytest.raises(InputError, match="this is a device, not a file"):
        read_machine("/dev/null")


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
@pytest.mark.parametrize("args", [["machine", "show", "builtin:vmc"],
                                  ["machine", "show", "builtin:vmc", "--json"]])
def test_a_full_standard_output_is_named_in_the_error(args):
    """`tcpmm ... > /dev/full` said "No space left on device" and not where: the message
    names standard output, as a file's names the file; no traceback."""
    import subprocess
    import sys

    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-c", "import sys; from tcpmm.cli import main; "
                               "sys.exit(main())", *args], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=120)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines()[-1] == (
        "error: No space left on device (standard output)")
    assert "Traceback" not in done.stderr


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_a_full_device_fails_where_it_is_written_within_together():
    """Within ``together`` a device was held back like a file and written at the end:
    ``tcpmm path PROG.nc -o /dev/full`` printed "wrote /dev/full ..." and then the error.
    The device's write is the step that fails, so it fails where the command writes it."""
    from tcpmm.io.atomic import together, write_text_atomic

    said = []
    with pytest.raises(InputError, match="No space left on device"), together():
        write_text_atomic("/dev/full", "time_s,x_mm\n0,0\n")
        said.append("wrote /dev/full")
    assert said == []


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
def test_path_to_a_full_device_says_no_wrote(capsys, tmp_path):
    from conftest import run_cli

    prog = tmp_path / "p.nc"
    prog.write_text("G21 G90\nG1 X10 F3000\nM30\n")
    code, out, err = run_cli(capsys, "path", prog, "-o", "/dev/full")
    assert code == 2
    assert "wrote" not in out
    assert err.startswith("error: /dev/full: cannot write the output (No space left on device)")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
def test_a_binary_stream_given_as_a_program_is_refused_from_its_start(tmp_path):
    """`tcpmm path /dev/zero` (or `simulate --gcode`) read the device whole before looking
    at its first bytes, until the memory ran out (MemoryError, or the kernel killed it):
    a stream of zero bytes is refused from its start, after its first few KiB."""
    from tcpmm.path import read_program

    fifo = tmp_path / "zeros"
    os.mkfifo(fifo)
    sent = [0]

    def write():
        block = b"\0" * 65536
        try:
            with open(fifo, "wb") as fh:
                for _ in range(256):  # 16 MiB, were it all read
                    fh.write(block)
                    sent[0] += len(block)
        except BrokenPipeError:  # the reader stopped: what is wanted
            pass

    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    with pytest.raises(InputError, match="not plain text"):
        read_program(fifo)
    writer.join(timeout=30)
    assert sent[0] < 4 * 2**20
