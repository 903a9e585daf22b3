"""Model files: every bad input is one clear error with file, line and key."""

import pytest

from tcpmm.errors import InputError
from tcpmm.io.modelfile import dumps_machine, loads_machine, read_machine, write_machine
from tcpmm.mechanics.friction import LuGreFriction
from tcpmm.model import Machine


def _line(text, needle):
    return next(i for i, s in enumerate(text.splitlines(), 1) if needle in s)


def _error(text):
    with pytest.raises(InputError) as e:
        loads_machine(text, "m.yaml")
    return e.value


def _with_interpolation(vmc, section):
    """The model file of ``vmc`` without its interpolation settings, and ``section`` as
    them [-]."""
    bare = vmc.model_copy(update={"interpolation": None})
    return dumps_machine(bare).replace("axes:\n", f"interpolation:\n{section}axes:\n", 1)


def test_interpolation_unknown_key_names_key_and_line(vmc):
    text = _with_interpolation(vmc, "  period: 0.001\n")
    err = _error(text)
    assert err.column == "interpolation.period" and err.line == _line(text, "period:")
    assert f"interpolation.period (line {err.line}): unknown key" in err.message


@pytest.mark.parametrize(("section", "key", "needle"), [
    ("  profile: sine\n", "interpolation.profile", "'trapezoid' or 'scurve'"),
    ("  rapid_m_per_s: {}\n", "interpolation.rapid_m_per_s", "at least one axis"),
    ("  axis_velocity_m_per_s: {X: -1}\n", "interpolation.axis_velocity_m_per_s.X", "positive"),
    ("  rapid_m_per_s: {X: 1, x: 2}\n", "interpolation.rapid_m_per_s.x", "duplicates 'X'"),
    ("  filter_time_s: 20\n", "interpolation.filter_time_s", "less than or equal to 10"),
])
def test_interpolation_bad_values(vmc, section, key, needle):
    err = _error(_with_interpolation(vmc, section))
    assert err.column == key and needle in err.message and err.line is not None


def test_machine_checks_interpolation(vmc):
    with pytest.raises(ValueError, match=r"interpolation\.period"):
        Machine(axes=vmc.axes, interpolation={"period": 1e-3})


def test_interpolation_round_trip_keeps_its_keys(vmc, tmp_path):
    m = Machine(name="m", axes=vmc.axes, interpolation={"period_s": 5e-4, "profile": "scurve"})
    write_machine(m, tmp_path / "m.yaml")
    m2 = read_machine(tmp_path / "m.yaml")
    assert m2 == m and m2.interpolation == {"period_s": 5e-4, "profile": "scurve"}


def test_axis_names_differing_in_case_are_an_error(vmc):
    text = dumps_machine(vmc).replace("\n  Z:\n", "\n  x:\n", 1)
    err = _error(text)
    assert "axis 'x' duplicates 'X' (axis names are case-insensitive)" in err.message
    assert err.column == "axes.x" and err.line == _line(text, "  x:")
    with pytest.raises(ValueError, match="duplicates 'X'"):
        Machine(axes={"X": vmc.axes["X"], "x": vmc.axes["Y"]})


def test_file_that_is_not_utf8(tmp_path):
    path = tmp_path / "m.yaml"
    path.write_bytes(b"\xff\xfef\x00o\x00")
    with pytest.raises(InputError, match="not a UTF-8 text file") as e:
        read_machine(path)
    assert e.value.file == str(path)


def test_no_axes_and_bad_axis_name(vmc):
    err = _error("format: tcpmm-model/1\nname: m\naxes: {}\n")
    assert "axes (line 3): a machine needs at least one axis" in err.message
    text = dumps_machine(vmc).replace("\n  Y:\n", "\n  X1:\n", 1)
    err = _error(text)
    assert err.column == "axes.X1" and err.line == _line(text, "X1:")
    assert "one or two letters" in err.message


def test_friction_errors_name_the_key(vmc):
    text = dumps_machine(vmc).replace("        fc_pos: 25.0", "        fc_pos: -25.0", 1)
    err = _error(text)
    line = _line(text, "fc_pos: -25.0")
    assert f"axes.X.friction.screw.fc_pos (line {line}): Input should be greater" in err.message
    assert "1 problem(s)" in err.message and "sigma0" not in err.message
    text = dumps_machine(vmc).replace("        v_stick:", "        vstick:", 1)
    err = _error(text)
    assert err.column == "axes.X.friction.screw.vstick" and err.line == _line(text, "vstick:")
    assert "unknown key" in err.message


def test_friction_with_sigma0_is_lugre(vmc):
    text = dumps_machine(vmc).replace("        v_stick: 1.0e-06\n",
                                      "        v_stick: 1.0e-06\n        sigma0: 1.0e+7\n", 1)
    assert isinstance(loads_machine(text).axes["X"].friction.screw, LuGreFriction)


def test_validator_error_names_key_without_dump(vmc):
    text = dumps_machine(vmc).replace("      K_L: 4000.0", "      K_L: true", 1)
    err = _error(text)
    assert err.column == "axes.X.mechanics.K_L" and err.line == _line(text, "K_L: true")
    assert "K_L must be a number, not a boolean" in err.message and "J_m" not in err.message


def test_other_format_is_named_in_one_line(vmc):
    err = _error("format: tcpmm-bundle/1\nname: m\naxes:\n  X:\n    lead_mm: 10\n")
    assert err.message == ("this is a measurement-bundle description (format tcpmm-bundle/1), "
                           "not a machine model; run `tcpmm identify` on its folder")
    assert err.line == 1
    text = dumps_machine(vmc).replace("tcpmm-model/1\n", "tcpmm-model/9\n", 1)
    err = _error(text)
    line = _line(text, "format: tcpmm-model/9")
    assert (f"format (line {line}): Input should be 'tcpmm-model/1' (got 'tcpmm-model/9')"
            in err.message)


def test_tab_in_indentation(vmc):
    text = dumps_machine(vmc).replace("      K_L: 4000.0", "\tK_L: 4000.0", 1)
    err = _error(text)
    assert err.message == "tab character in the indentation; YAML indents with spaces"
    assert err.line == _line(text, "\tK_L")


@pytest.mark.parametrize(("indent", "column"), [("\t", 1), ("    \t", 5)])
def test_tab_in_indentation_names_its_column(vmc, indent, column):
    """The tab's line was named but not where in it the tab is, which an editor that
    shows a tab as spaces does not tell."""
    text = dumps_machine(vmc).replace("      K_L: 4000.0", f"{indent}K_L: 4000.0", 1)
    err = _error(text)
    assert (err.line, err.column) == (_line(text, "\tK_L"), column)
    assert f"line {err.line}, column {column}: tab character" in str(err)


def test_directory_instead_of_model(tmp_path):
    with pytest.raises(InputError, match="is a directory; give the path of the machine model"):
        read_machine(tmp_path)


@pytest.mark.parametrize(("old", "new", "key"), [
    ("      K_h: 40000000.0", "      K_h: 1.0e+300", "axes.X.mechanics.K_h"),
    ("      K_t: 150000000.0", "      K_t: 1.0e+300", "axes.X.mechanics.K_t"),
    ("      M_h: 400.0", "      M_h: 1.0e-300", "axes.X.mechanics.M_h"),
    ("      current_bandwidth_hz: null", "      current_bandwidth_hz: 1.0e+300",
     "axes.X.servo.current_bandwidth_hz"),
    ("      K_vp: 0.9260929279788198", "      K_vp: 1.0e+300", "axes.X.servo.K_vp"),
    ("        fc_pos: 25.0", "        fc_pos: .inf", "axes.X.friction.screw.fc_pos"),
    ("      scale_resolution: 1.0e-06", "      scale_resolution: 1.0e+300",
     "axes.X.sensors.scale_resolution"),
])
def test_implausible_numbers_name_the_key(vmc, old, new, key):
    """A stiffness of 1e300 (a typo, a wrong unit) overflowed the plant's matrices: the
    matrix exponential's balancing hung, other commands ended in a LinAlgError traceback
    or printed nonsense. Every physical parameter has a range decades wide around real
    machines'."""
    text = dumps_machine(vmc)
    assert old in text
    text = text.replace(old, new, 1)
    err = _error(text)
    assert err.column == key and err.line == _line(text, new.strip())
    assert "outside the plausible range" in err.message



@pytest.mark.parametrize("value", ["{}", "[tcpmm-model/1]", "1"])
def test_format_that_is_not_text(vmc, value):
    """A mapping for ``format:`` was looked up among the known formats and raised a
    TypeError (unhashable dict) instead of naming the key."""
    text = dumps_machine(vmc).replace("format: tcpmm-model/1\n", f"format: {value}\n", 1)
    err = _error(text)
    assert err.column == "format" and err.line == _line(text, "format:")
    assert "tcpmm-model/1" in err.message


def test_every_problem_on_one_line(vmc):
    """An error is one line on stderr; the problems of a model file were listed one a
    line, under a heading."""
    text = (dumps_machine(vmc).replace("      K_L: 4000.0", "      K_L: -1.0", 1)
            .replace("      K_pp: 40.0", "      Kpp: 40.0", 1))
    err = _error(text)
    assert "\n" not in str(err)
    assert err.message.startswith("3 problem(s) in machine model: axes.X.servo.Kpp (line ")
    assert "; axes.X.mechanics.K_L (line " in err.message


@pytest.mark.parametrize(("old", "new", "key"), [
    ("current_limit: 20.0", "current_limit: true", "axes.X.servo.current_limit"),
    ("M_t: ", "M_t: false #", "axes.X.mechanics.M_t"),
    ("encoder_counts_per_rev: ", "encoder_counts_per_rev: yes #",
     "axes.X.sensors.encoder_counts_per_rev"),
    ("delay_samples: 0", "delay_samples: true", "axes.X.servo.delay_samples"),
])
def test_a_boolean_for_a_number_is_refused_with_its_key(vmc, old, new, key):
    """pydantic reads ``true`` as 1: a current limit of 1 A nobody wrote."""
    text = dumps_machine(vmc)
    assert old in text
    text = text.replace(old, new, 1)
    err = _error(text)
    assert err.column == key and err.line == _line(text, new.split(":")[0] + ":")
    assert "must be a number, not a boolean" in err.message and "\n" not in str(err)


def test_booleans_where_the_schema_takes_them_still_load(vmc):
    text = dumps_machine(vmc)
    assert loads_machine(text, "m.yaml") == vmc


def test_a_key_in_a_list_item_names_its_own_line(vmc):
    """A misspelt key of a servo filter (an item of the filters list, a union tagged by its
    type) was placed on the line of the list, three lines above it."""
    text = dumps_machine(vmc)
    at = text.index("\n", text.index("feedforward:", text.index("axes:")))
    line = text[text.rindex("\n", 0, at) + 1:at]  # the servo's feedforward key
    indent = line[:len(line) - len(line.lstrip())]
    item = (f"\n{indent}filters:\n{indent}- type: notch\n{indent}  f_hz: 500\n"
            f"{indent}  bandwith_hz: 100\n{indent}  depth_db: -20")
    err = _error(text[:at] + item + text[at:])
    assert err.column.endswith("filters.0.notch.bandwith_hz")
    assert err.line == _line(text[:at] + item + text[at:], "bandwith_hz:")


@pytest.mark.parametrize("typo", ["K_p", "K_pq", "k_pp", "Kpp"])
def test_a_misspelt_key_is_matched_to_the_key_it_leaves_missing(vmc, typo):
    """``K_p`` for ``K_pp`` was asked "did you mean 'K_vp'?", a key the servo has already,
    where ``K_pp``, missing beside it, is as close (a tie broken alphabetically)."""
    text = dumps_machine(vmc).replace("      K_pp: 40.0", f"      {typo}: 40.0", 1)
    err = _error(text)
    assert err.column == f"axes.X.servo.{typo}" and err.line == _line(text, f"{typo}: 40.0")
    assert f"axes.X.servo.{typo} (line {err.line}): unknown key" in err.message
    assert "did you mean 'K_pp'?" in err.message and "'K_vp'" not in err.message


def test_a_misspelt_optional_key_is_matched_among_the_keys_not_given(vmc):
    text = dumps_machine(vmc).replace("current_limit:", "current_limt:", 1)
    assert "did you mean 'current_limit'?" in _error(text).message


@pytest.mark.parametrize(("old", "new", "fix"), [
    ("      J_m: 0.000265", "      J_m: 0.000265 kg m^2",
     "write the number alone, in SI units (the file's header, docs/formats.md section 5)"),
    ("      J_m: 0.000265", "      J_m: [0.000265]",
     "write the number alone, in SI units (the file's header, docs/formats.md section 5)"),
    ("      current_bandwidth_hz: null", "      current_bandwidth_hz: 2 kHz",
     "write the number alone, in Hz (the unit its name ends with)"),
])
def test_a_number_written_with_its_unit_says_the_fix(vmc, old, new, fix):
    """``J_m: 0.000265 kg m^2`` was refused with pydantic's "unable to parse string as a
    number" and no word of what to write; ``J_m``'s ``m`` is no unit, ``_hz`` is."""
    text = dumps_machine(vmc)
    assert old in text
    text = text.replace(old, new, 1)
    err = _error(text)
    key = "axes.X." + ("mechanics.J_m" if "J_m" in new else "servo.current_bandwidth_hz")
    assert err.column == key and err.line == _line(text, new.strip())
    assert f"{key} (line {err.line}): not a number (got " in err.message
    assert err.message.endswith(fix)


def test_a_run_file_given_as_a_model_is_named_for_what_it_reads_as(tmp_path):
    """A run file given where a model is asked for said only 'expected a mapping: machine
    model': it named the file but not what was wrong with it nor where the right keys are."""
    run = tmp_path / "run.csv"
    run.write_text("time_s,x_cmd_mm,x_tcp_mm\n0,0,0\n0.001,0.1,0.1\n", encoding="utf-8")
    with pytest.raises(InputError) as e:
        read_machine(run)
    msg = str(e.value)
    assert "run.csv" in msg and "expected a mapping: machine model" in msg
    assert "a table such as a CSV file" in msg and "tcpmm machine export" in msg


def test_a_number_in_quotes_is_text_as_in_machine_yaml(vmc):
    """``K_pp: '30.0'`` read as 30 in a model file, where machine.yaml refuses it: a
    value in quotes is text, and a number meant as such is written without them."""
    text = dumps_machine(vmc).replace("      K_pp: 40.0", "      K_pp: '30.0'", 1)
    err = _error(text)
    assert err.column == "axes.X.servo.K_pp" and err.line == _line(text, "K_pp: '30.0'")
    assert "K_pp must be a number, not text ('30.0'); write it without quotes" in err.message


def test_a_boolean_for_a_symbol_ending_in_a_letter_asks_for_si_units(vmc):
    """``J_m: true`` was told to write the number in m: the ``m`` of ``J_m`` names the
    motor, not a unit (the check of the key's last word beside tcpmm.io.keyunits's)."""
    text = dumps_machine(vmc).replace("      J_m: 0.000265", "      J_m: true", 1)
    err = _error(text)
    assert err.message.endswith("write the number, in SI units"), err.message
