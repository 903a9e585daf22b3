"""Model files: exact round trip, strict validation with key path and line."""

import pytest

from tcpmm.errors import InputError
from tcpmm.io.modelfile import (
    END_LINE,
    dumps_machine,
    loads_machine,
    read_machine,
    write_machine,
)


def test_round_trip_is_identical(vmc, tmp_path):
    write_machine(vmc, tmp_path / "m.yaml")
    m2 = read_machine(tmp_path / "m.yaml")
    assert m2 == vmc
    assert m2.axes["Y"].servo.K_vp == vmc.axes["Y"].servo.K_vp  # bit-identical floats
    assert not list(tmp_path.glob(".*"))  # no temp file left


def test_unknown_key_names_path_and_line(vmc):
    text = dumps_machine(vmc).replace("      K_t:", "      K_tt:", 1)
    with pytest.raises(InputError) as e:
        loads_machine(text, "m.yaml")
    msg = str(e.value)
    assert "axes.X.mechanics.K_tt" in msg and "unknown key" in msg
    line = next(i for i, s in enumerate(text.splitlines(), 1) if "K_tt" in s)
    assert f"line {line}" in msg
    # the typo is named with the key it most likely stands for, and its place as a key
    assert "did you mean 'K_t'?" in msg
    assert f"m.yaml, line {line}, key 'axes.X.mechanics.K_tt'" in msg


def test_an_unknown_key_like_no_known_one_gets_no_guess(vmc):
    text = dumps_machine(vmc).replace("      K_t:", "      spindle_colour:", 1)
    with pytest.raises(InputError) as e:
        loads_machine(text, "m.yaml")
    assert "unknown key" in str(e.value) and "did you mean" not in str(e.value)


@pytest.mark.parametrize(("old", "new", "needle"), [
    ("format: tcpmm-model/1", "format: tcpmm-model/9", "format"),
    ("      M_t: 150.0", "      M_t: -150.0", "M_t"),
    ("      lead: 0.01\n", "      lead: .nan\n", "lead"),
    ("      K_pp: 40.0\n", "      K_pp: fast\n", "K_pp"),
    # what the builder states: a positive deviation in metres, and nothing else
    ("  circular_deviation_m: 4.0e-05\n", "  circular_deviation_m: -4.0e-05\n",
     "circular_deviation_m"),
    ("  circular_deviation_m: 4.0e-05\n", "  circular_deviation_um: 40\n",
     "specification.circular_deviation_um"),
])
def test_bad_values(vmc, old, new, needle):
    text = dumps_machine(vmc)
    assert old in text
    with pytest.raises(InputError, match=needle):
        loads_machine(text.replace(old, new, 1))


@pytest.mark.parametrize(("old", "new", "key", "meant"), [
    ("  circular_deviation_m: 4.0e-05\n", "  circular_deviation_m: 40\n",
     "specification.circular_deviation_m", "40e-6 (40 µm)"),
    ("  circular_deviation_m: 4.0e-05\n", "  circular_deviation_m: 0.04\n",
     "specification.circular_deviation_m", "40e-6 (40 µm)"),
    ("  corner_tolerance_m: 1.0e-05\n", "  corner_tolerance_m: 10\n",
     "interpolation.corner_tolerance_m", "10e-6 (10 µm)"),
    ("  blend_tolerance_m: 0.0\n", "  blend_tolerance_m: 0.05\n",
     "interpolation.blend_tolerance_m", "50e-6 (50 µm)"),
])
def test_a_tolerance_written_in_um_or_mm_is_refused_at_its_line(vmc, old, new, key, meant):
    """A specification of 40 (meant in µm) was taken as 40 m: the verdict read PASS
    'within ... 40000000.00 µm'. A length no machine tool's specification or CNC's
    tolerance has is refused at its file, line and key, with the metres it may mean."""
    text = dumps_machine(vmc)
    assert old in text
    line = text[:text.index(old)].count("\n") + 1
    with pytest.raises(InputError) as e:
        loads_machine(text.replace(old, new, 1), "m.yaml")
    msg = str(e.value)
    assert f"m.yaml, line {line}, key '{key}'" in msg
    assert "in metres" in msg and f"did you mean {meant}?" in msg


@pytest.mark.parametrize(("old", "new", "unit", "metres"), [
    ("      lead: 0.01\n", "      lead: 10\n", "mm", "0.01"),
    ("      scale_resolution: 1.0e-06\n", "      scale_resolution: 0.005\n", "um", "5e-09"),
    ("      tcp_resolution: 7.8e-08\n", "      tcp_resolution: 0.001\n", "mm", "1e-06"),
    ("      K_t: 150000000.0\n", "      K_t: 150000.0\n", "N/mm", "1.5e+08"),
    ("      M_t: 150.0\n", "      M_t: 150000.0\n", "g", "150"),
    ("      K_tc: 0.73\n", "      K_tc: 730.0\n", "N mm/A", "0.73"),
    ("      T_p: 0.0005\n", "      T_p: 0.5\n", "ms", "0.0005"),
])
def test_a_number_written_in_mm_or_um_is_warned_of(vmc, tmp_path, old, new, unit, metres):
    """A lead of 10 (mm, in a field of metres) was read without a word, and the run then
    failed as an unstable servo loop, 'check the gains and periods'; a screw stiffness in
    N/mm, a mass in grams, a torque constant in N mm/A or a loop period in ms were read
    without a word, and tune proposed gains for them. The warning names the key and the
    number in SI units; the model is still read."""
    import warnings

    from tcpmm.errors import InputWarning

    text = dumps_machine(vmc)
    assert old in text
    (tmp_path / "m.yaml").write_text(text.replace(old, new, 1))
    with pytest.warns(InputWarning) as got:
        read_machine(tmp_path / "m.yaml")
    assert len(got) == 1
    msg = str(got[0].message)
    assert "m.yaml" in msg and "axis X" in msg and old.split(":")[0].strip() in msg
    assert f"if in {unit}, write {metres}" in msg
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loads_machine(text)  # the built-in machine's numbers raise nothing


def test_duplicate_key_and_syntax_error(vmc):
    dup = "      K_tc: 0.73\n      K_tc: 0.8\n"
    text = dumps_machine(vmc).replace("      K_tc: 0.73\n", dup, 1)
    with pytest.raises(InputError, match="appears twice"):
        loads_machine(text)
    with pytest.raises(InputError, match="line"):
        loads_machine("axes: [\n")


def test_builtin_reference_and_missing_file(tmp_path):
    assert "X" in read_machine("builtin:vmc").axes
    with pytest.raises(InputError, match="not found"):
        read_machine(tmp_path / "nope.yaml")
    with pytest.raises(InputError, match="unknown built-in"):
        read_machine("builtin:lathe")


def test_a_reference_machines_truth_file_reads_as_its_model(capsys):
    """A truth.yaml handed where a model goes failed with '138 problem(s)', the format
    buried at the end; it is the true machine, and reads as machine_from_truth gives it."""
    from conftest import bench_path
    from tcpmm.cli import main
    from tcpmm.io.truthfile import machine_from_truth

    path = bench_path("c") / "truth.yaml"
    assert read_machine(path) == machine_from_truth(path)
    assert main(["machine", "show", str(path)]) == 0
    assert "velocity loop: gain margin" in capsys.readouterr().out


def test_a_filter_above_the_loops_nyquist_names_the_filters_line(vmc):
    """A low-pass at 5 kHz in a servo of 8 kHz was refused naming the servo's line, a
    dozen lines above the filter: the filters' own line is named."""
    text = dumps_machine(vmc).replace(
        "      velocity_filter:\n      - 1.0\n",
        "      velocity_filter:\n      - 1.0\n      filters:\n      - type: lowpass\n"
        "        f_hz: 5000.0\n        zeta: 0.7\n", 1)
    line = text.splitlines().index("      filters:") + 1
    with pytest.raises(InputError, match="filter 1 \\(lowpass\\) at 5000 Hz") as got:
        loads_machine(text, "m.yaml")
    assert got.value.line == line and "servo.filters" in str(got.value)


def test_an_identified_axis_mechanics_are_not_taken_for_a_unit(vmc):
    """The mechanics of an identified axis (it has an uncertainty) come from its sweep, not
    from a drawing: a soft screw the identification accepted as suspect read 'if in N/mm,
    write 2.2e+09', which no user had typed. Its lead, which the user gives, still is."""
    import warnings

    from tcpmm.io.unitchecks import unit_suspects
    from tcpmm.model import AxisUncertainty

    x = vmc.axes["X"]
    soft = x.replace(mechanics=x.mechanics.model_copy(update={"K_t": 2.2e6, "lead": 10.0}))
    assert len(unit_suspects(vmc.with_axis("X", soft))) == 2
    known = soft.replace(uncertainty=AxisUncertainty(mechanics={"K_t": 1e5}))
    said = unit_suspects(vmc.with_axis("X", known))
    assert len(said) == 1 and "mechanics.lead" in said[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        unit_suspects(vmc)


def test_a_file_cut_short_at_any_line_is_refused_naming_where_it_ends(vmc):
    """A copy interrupted part way is valid YAML up to where it stops; the keys it lost
    were read as their defaults (a friction without its pre-sliding stiffness, an axis
    without its uncertainty) and the model simulated with no word."""
    lines = dumps_machine(vmc).splitlines(keepends=True)
    assert lines[-1] == END_LINE + "\n"
    for k in range(1, len(lines) - 1):
        with pytest.raises(InputError, match="cut short") as e:
            loads_machine("".join(lines[:k]), "m.yaml")
        last = max(i for i in range(k) if lines[i].strip()) + 1
        assert f"m.yaml: the model file ends at line {last} " in str(e.value)


def test_a_model_written_by_hand_needs_no_last_line(vmc):
    """A file without tcpmm's header is the user's own, held to its keys only; one that
    has the last line with keys added after it by hand is whole."""
    text = dumps_machine(vmc)
    body = text[text.index("format:"):].replace(END_LINE + "\n", "")
    assert loads_machine(body, "m.yaml") == vmc
    spec = text[text.index("specification:"):text.index(END_LINE)]
    moved = text.replace(spec, "") + spec  # the last block moved past the last line
    assert loads_machine(moved, "m.yaml") == vmc
