"""Sweeps meeting faults of the system: a full disk, a scheduler gone, an unstable
variant; each said, none taken for a result."""

import errno
import json

from tcpmm.cli import main
from tcpmm.sweep import read_results

ARGS = ["sweep", "builtin:vmc", "-p", "X.servo.position_gain=30,40", "--circle", "5,6000",
        "--workers", "1", "--json"]


def test_a_run_that_cannot_be_written_fails_its_variant_and_is_retried(tmp_path,
                                                                      monkeypatch, capsys):
    from tcpmm.io import runfile

    write = runfile.write_run_csv

    def full(run, path):
        raise OSError(errno.ENOSPC, "No space left on device")

    args = [*ARGS, "-o", str(tmp_path / "o"), "--keep-runs", str(tmp_path / "runs")]
    monkeypatch.setattr(runfile, "write_run_csv", full)
    assert main(args) != 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], len(got["failed"])) == (0, 2)
    assert "No space left on device" in got["failed"][0]["reason"]
    assert len(read_results(tmp_path / "o")) == 0
    monkeypatch.setattr(runfile, "write_run_csv", write)
    assert main(args) == 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], got["reused"], got["failed"]) == (2, 0, [])
    assert len(list((tmp_path / "runs").glob("*.csv"))) == 2
    assert read_results(tmp_path / "o")["spike_max_um"].notna().all()


def test_a_row_whose_run_file_is_gone_is_computed_again(tmp_path, capsys):
    args = [*ARGS, "-o", str(tmp_path / "o"), "--keep-runs", str(tmp_path / "runs")]
    assert main(args) == 0
    capsys.readouterr()
    next((tmp_path / "runs").glob("*.csv")).unlink()
    assert main(args) == 0
    got = json.loads(capsys.readouterr().out)
    assert (got["computed"], got["reused"]) == (1, 1)
