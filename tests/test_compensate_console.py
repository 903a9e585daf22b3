"""What tcpmm compensate says on the console and in its files about the program it was
given."""

import json

from tcpmm.cli import main

#: A circle of R 35 mm that starts and ends at quadrant point A (X35 Y0): it never
#: crosses A, so no reversal spike can be reported there.
CIRCLE_AT_A = "G21 G17 G90\nG0 X35 Y0\nG3 X35 Y0 I-35 J0 F3000\nM30\n"


def test_a_circle_starting_at_a_quadrant_point_is_said_once(tmp_path, capsys):
    """Without --report the console says that no spike is reported at A, once over the
    runs and draws judged, and --json stays one JSON document on stdout that carries
    it."""
    prog = tmp_path / "circle_at_a.nc"
    prog.write_text(CIRCLE_AT_A)
    args = ["compensate", "builtin:vmc", "--gcode", str(prog), "-o", str(tmp_path / "c.csv"),
            "--radius", "35", "--draws", "2", "--iterations", "3"]
    assert main(args) == 0
    err = capsys.readouterr().err
    said = [line for line in err.splitlines() if "no reversal spike is reported at A" in line]
    assert len(said) == 1, err
    assert main([*args, "--json"]) == 0
    got = capsys.readouterr()
    d = json.loads(got.out)
    assert any("no reversal spike is reported at A" in w for w in d["warnings"])
    assert got.err.count("no reversal spike is reported at A") == 1
