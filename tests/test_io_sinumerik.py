"""Sinumerik Operate XML and generic FRF files: the real trace, round trips, bad input."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import scipy.io as sio
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tcpmm.errors import InputError, InputWarning
from tcpmm.ident.frf import FRF
from tcpmm.io.frffile import read_frf, write_frf_csv
from tcpmm.io.sinumerik import read_sinumerik
from tcpmm.io.sinumerik_b85 import ALPHABET, decode_doubles, encode_doubles

TRACE = Path(__file__).parents[1] / ".." / "shared" / "data" / "sinumerik" / "freq_trace.XML"
needs_trace = pytest.mark.skipif(not TRACE.is_file(), reason="Sinumerik trace not available")


@needs_trace
def test_the_real_trace_reads_with_plausible_physical_values():
    with pytest.warns(InputWarning, match=r"steps by 3\.91389 Hz, but .* DFT of the "
                      r"2047-sample time series .* step by 3\.90816 Hz \(\+0\.147 %"):
        tr = read_sinumerik(TRACE)
    frf = tr.frf
    # 2047-sample PRBS at 8 kHz: the spectra stored are its DFT, whose bins step by
    # 8000/2047 Hz; the file's own vector labels the 1022 above 0 Hz 4000/1022 Hz apart
    assert frf.freq_hz.size == 1022
    np.testing.assert_allclose(frf.freq_hz, np.arange(1, 1023) * 8000 / 2047, rtol=1e-12)
    assert tr.meta["control_loop"] == "speed" and tr.meta["sample_time_s"] == 0.000125
    # a closed speed loop: unity at low frequency, lagging, -3 dB near 80 Hz, rolled off
    assert abs(frf.H[0]) == pytest.approx(1.0, abs=0.01)
    assert -10 < frf.phase_deg[0] < 0
    f3 = frf.freq_hz[np.argmax(frf.magnitude_db < -3)]
    assert 40 < f3 < 150
    assert np.median(np.abs(frf.H[frf.freq_hz > 500])) < 0.1
    assert np.all((frf.coherence >= 0) & (frf.coherence <= 1))
    assert np.median(frf.coherence[frf.freq_hz < 200]) > 0.99
    # time series: two runs of 2047 samples over 0.25575 s; the input is the excitation,
    # an offset of 0.419 rad/s (4 rpm) with a PRBS of +-0.209 rad/s (2 rpm)
    tin = tr.traces[frf.input]
    assert tin.values.shape == (2, 2047) and tin.unit == "rad/s"
    assert np.diff(tin.time_s) == pytest.approx(np.full(2046, 0.000125))
    assert np.unique(np.round(np.abs(tin.values), 4)).tolist() == [0.2094, 0.6283]


@needs_trace
def test_spectra_agree_with_the_time_series_they_were_made_from(tmp_path):
    """Without stored spectra the reader forms them from the runs, as the drive does."""
    import re

    text = TRACE.read_text(encoding="latin-1")
    stripped = re.sub(r"<SigNodeCrossSpectrumInfo .*?</SigNodeCrossSpectrumInfo>", "", text,
                      flags=re.S)
    p = tmp_path / "nospectra.xml"
    p.write_text(stripped, encoding="latin-1")
    a, b = read_sinumerik(TRACE).frf, read_sinumerik(p).frf
    assert b.freq_hz.size == a.freq_hz.size + 1 or b.freq_hz.size == a.freq_hz.size
    n = min(a.H.size, b.H.size)
    np.testing.assert_allclose(b.H[:n], a.H[:n], rtol=1e-9)
    # at the same frequencies: those of the DFT, not the file's label 0.147 % above them
    np.testing.assert_allclose(b.freq_hz[:n], a.freq_hz[:n], rtol=1e-12)


def _xml(tmp_path, raw: str, length: int = 2) -> Path:
    freq = encode_doubles([0.0, 1.0])
    spec = lambda v: (f'<CrossSpectrum name="m_avgCrossSpec"><NumericArray '  # noqa: E731
                      f'elementtype="ComplexNumber" name="m_ValueVector"><unsigned_int '
                      f'name="m_length">{length}</unsigned_int><raw name="m_pNumberArray">{v}'
                      f'</raw></NumericArray><NumericArray elementtype="double" '
                      f'name="m_FrequencyVector"><unsigned_int name="m_length">2</unsigned_int>'
                      f'<raw name="m_pNumberArray">{freq}</raw></NumericArray></CrossSpectrum>')
    ok = encode_doubles([1, 0, 1, 0])
    node = lambda i, inst, auto, cross: (  # noqa: E731
        f'<PlatformSignalNode name="n"><unsigned_int name="m_uNodeId">{i}</unsigned_int>'
        f'<integer name="m_iUniqueInstanceId">{inst}</integer>'
        f'<SigNodeCrossSpectrumInfo name="m_autospectrumInfo">{spec(auto)}'
        '</SigNodeCrossSpectrumInfo><LinkedList name="m_crossSpecInfoList">'
        + (f'<SigNodeCrossSpectrumInfo name="c"><unsigned_int name="m_uSignodeId">2'
           f'</unsigned_int>{spec(cross)}</SigNodeCrossSpectrumInfo>' if cross else "")
        + "</LinkedList></PlatformSignalNode>")
    text = ('<ResponseTestCustom><unsigned_int name="m_eControlLoopType">2</unsigned_int>'
            '<LinkedList name="m_MeasurementSignalNodeList">'
            + node(1, 0, ok, raw) + node(2, 1, ok, None)
            + '</LinkedList><PrimaryFreqRespSigNodeData><integer '
            'name="m_iInputSigNodeUniqueInstanceID">1</integer><integer '
            'name="m_iOutputSigNodeUniqueInstanceID">0</integer></PrimaryFreqRespSigNodeData>'
            '</ResponseTestCustom>')
    p = tmp_path / "t.xml"
    p.write_text(text)
    return p


def test_a_minimal_file_gives_the_conjugate_of_the_stored_cross_spectrum(tmp_path):
    p = _xml(tmp_path, encode_doubles([1, 0, 0.5, 0.25]))
    frf = read_sinumerik(p).frf
    assert frf.freq_hz.tolist() == [1.0]
    assert frf.H[0] == pytest.approx(0.5 - 0.25j)


@settings(max_examples=60, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), max_size=20))
def test_base85_round_trip(values):
    assert decode_doubles(encode_doubles(values)).tolist() == [float(v) for v in values]


@settings(max_examples=150, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_malformed_or_truncated_data_raise_input_error_only(tmp_path, data):
    good = encode_doubles([1.0, 0.0, 0.5, 0.25])
    how = data.draw(st.sampled_from(["cut", "noise", "splice"]))
    if how == "cut":
        raw = good[: data.draw(st.integers(0, len(good) - 1))]
    elif how == "noise":
        raw = data.draw(st.text(alphabet=ALPHABET + ".~ \n<>&\u00e9", max_size=40))
    else:
        i = data.draw(st.integers(0, len(good)))
        raw = good[:i] + data.draw(st.text(alphabet=ALPHABET + ".", min_size=1, max_size=7)) \
            + good[i:]
    p = _xml(tmp_path, raw.replace("<", "&lt;").replace("&", "&amp;")
             if "<" in raw or "&" in raw else raw)
    try:
        frf = read_sinumerik(p).frf
    except InputError as exc:
        assert "t.xml" in str(exc)
    else:
        assert isinstance(frf, FRF)


def test_broken_xml_is_named_at_its_line(tmp_path):
    p = tmp_path / "bad.xml"
    p.write_text("<ResponseTestCustom>\n<float name='x'>1</flo>\n")
    with pytest.raises(InputError, match="line 2"):
        read_sinumerik(p)


@needs_trace
def test_a_decimal_comma_is_named_with_file_line_and_element(tmp_path):
    text = TRACE.read_bytes()
    old = b'name="m_dProcessUpdateTime">0.000125<'
    assert old in text
    p = tmp_path / "comma.xml"
    p.write_bytes(text.replace(old, b'name="m_dProcessUpdateTime">0,000125<'))
    line = text[:text.index(old)].count(b"\n") + 1
    with pytest.raises(InputError) as exc:
        read_sinumerik(p)
    msg = str(exc.value)
    assert f"comma.xml, line {line}" in msg
    assert "element <m_dProcessUpdateTime> holds '0,000125', a decimal comma: write '.'" in msg
    assert "export" not in msg


finite = st.floats(-1e6, 1e6, allow_nan=False).filter(lambda v: abs(v) > 1e-9)


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(finite, finite, st.floats(0, 1)), min_size=1, max_size=30),
       st.booleans())
def test_csv_round_trip(tmp_path, rows, polar):
    f = np.cumsum(np.full(len(rows), 0.5)) + 0.1
    H = np.array([a + 1j * b for a, b, _ in rows])
    frf = FRF(freq_hz=f, H=H, coherence=np.array([c for *_, c in rows]), n_averages=10,
              rel_std=np.zeros(f.size))
    p = write_frf_csv(frf, tmp_path / "rt.csv", polar=polar)
    back = read_frf(p)
    np.testing.assert_allclose(back.freq_hz, f, rtol=1e-15)
    np.testing.assert_allclose(back.H, H, rtol=1e-12 if polar else 0, atol=0)
    np.testing.assert_array_equal(back.coherence, frf.coherence)


@pytest.mark.parametrize("text, where", [
    ("f,mag_db,phase_deg\n1,0,0\n2,-1,x\n", "line 3, column 'phase_deg'"),
    ("f,re,im\n1,1,0\n1,1,0\n", "line 3, column 'f'"),
    ("f,re\n1,1\n", "line 1"),
    ("hz,re,im\n1,1,0\n", "line 1"),
    ("f,re,im,coherence\n1,1,0,1.5\n", "line 2, column 'coherence'"),
])
def test_csv_errors_name_line_and_column(tmp_path, text, where):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(InputError, match=where):
        read_frf(p)


def test_mat_files_read_complex_or_re_im(tmp_path):
    f = np.array([1.0, 2.0, 4.0])
    H = np.array([1 + 1j, 0.5j, -0.25])
    sio.savemat(tmp_path / "a.mat", {"freq_hz": f, "H": H, "coherence": [1, 0.9, 0.8]})
    sio.savemat(tmp_path / "b.mat", {"f": f, "re": H.real, "im": H.imag})
    sio.savemat(tmp_path / "c.mat", {"f": f})
    for name in ("a.mat", "b.mat"):
        np.testing.assert_array_equal(read_frf(tmp_path / name).H, H)
    with pytest.raises(InputError, match="no response variable"):
        read_frf(tmp_path / "c.mat")


@pytest.mark.parametrize("extra, said", [
    ({"frf": 2 * np.array([1 + 1j, 0.5j, -0.25])}, "variables H and frf name one quantity"),
    ({"re": [1.0, 0.0, 0.0], "im": [0.0, 1.0, 0.0]}, "variables H and re name one quantity"),
    ({"H": np.abs(np.array([1 + 1j, 0.5j, -0.25]))}, "variable 'H' holds real numbers only")])
def test_a_mat_frf_given_twice_or_as_magnitudes_is_refused(tmp_path, extra, said):
    """H beside frf (or beside re and im) read H and dropped the other without a word;
    a real H (abs saved) read as a phase of 0 everywhere; an unknown variable is said."""
    f = np.array([1.0, 2.0, 4.0])
    sio.savemat(tmp_path / "a.mat", {"freq_hz": f, "H": np.array([1 + 1j, 0.5j, -0.25]),
                                     **extra})
    with pytest.raises(InputError, match=said):
        read_frf(tmp_path / "a.mat")
    sio.savemat(tmp_path / "b.mat", {"freq_hz": f, "H": np.array([1 + 1j, 0.5j, -0.25]),
                                     "note_x": [1.0]})
    with pytest.warns(InputWarning, match="variable 'note_x' is not read"):
        read_frf(tmp_path / "b.mat")


@needs_trace
def test_a_trace_written_as_csv_reads_and_fits_as_the_xml_to_the_bit(tmp_path, trace_fit):
    """The CSV lost the trace's 2 averages, and its coherence was read as of 10: a
    different noise, and 10 poles and a delay of 0.25 ms where the XML gives 8 and
    0.35 ms. The count is written and read back."""
    from tcpmm.ident.lti import fit_frf

    a = read_sinumerik(TRACE).frf
    b = read_frf(write_frf_csv(a, tmp_path / "sin.csv"))
    assert a.n_averages == b.n_averages == 2 and "averages_assumed" not in b.meta
    for k in ("freq_hz", "H", "coherence", "rel_std"):
        np.testing.assert_array_equal(getattr(b, k), getattr(a, k))
    labels = ("name", "input", "output", "unit")
    fa, fb = ({k: v for k, v in fit.to_dict().items() if k not in labels}
              for fit in (trace_fit, fit_frf(b)))  # trace_fit: the fit of ``a``, the XML's
    assert fa == fb and fa["n_poles"] == 8


def test_a_coherence_without_its_count_is_taken_as_of_10_averages_and_said_so(tmp_path):
    from tcpmm.io.frffile import AVERAGES

    p = tmp_path / "c.csv"
    p.write_text("freq_hz,re,im,coherence\n1,1,0,0.9\n2,0.9,-0.1,0.8\n")
    frf = read_frf(p)
    assert frf.n_averages == AVERAGES == 10 and frf.meta["averages_assumed"]
    two = read_frf(p, averages=2)
    assert two.n_averages == 2 and "averages_assumed" not in two.meta
    assert two.rel_std[0] == pytest.approx(np.sqrt(0.1 / (2 * 1 * 0.9)))
    # what was assumed is not written as if it had been measured
    assert "averages" not in write_frf_csv(frf, tmp_path / "w.csv").read_text()
    q = tmp_path / "n.csv"
    q.write_text("freq_hz,re,im,coherence,averages\n1,1,0,0.9,4\n2,0.9,-0.1,0.8,4\n")
    assert read_frf(q).n_averages == 4
    with pytest.raises(InputError, match="says 4 averages, not the 2 given"):
        read_frf(q, averages=2)
    q.write_text("freq_hz,re,im,coherence,averages\n1,1,0,0.9,4\n2,0.9,-0.1,0.8,5\n")
    with pytest.raises(InputError, match="line 3, column 'averages'"):
        read_frf(q)
    sio.savemat(tmp_path / "a.mat", {"f": [1.0, 2.0], "H": [1, 0.5j], "coherence": [1, 0.9],
                                     "averages": 3})
    assert read_frf(tmp_path / "a.mat").n_averages == 3


def test_frf_commands_say_the_count_they_assume_and_take_it(capsys, tmp_path):
    from conftest import run_cli

    p = tmp_path / "c.csv"
    p.write_text("freq_hz,re,im,coherence\n1,1,0,0.9\n2,0.9,-0.1,0.8\n3,0.7,-0.3,0.95\n")
    code, out, _ = run_cli(capsys, "frf", "show", p)
    assert code == 0 and "note: the file gives a coherence but not the number of averages " \
        "behind it: 10 are assumed; give the count with --averages N" in out
    code, out, _ = run_cli(capsys, "frf", "show", p, "--averages", "2", "--json")
    got = json.loads(out)
    assert code == 0 and got["averages"] == 2 and got["notes"] == []
    rows = [f"{f:g},{(1 / (1 + 1j * f / 20)).real!r},{(1 / (1 + 1j * f / 20)).imag!r},0.9"
            for f in range(1, 9)]
    p.write_text("freq_hz,re,im,coherence\n" + "\n".join(rows) + "\n")
    code, out, _ = run_cli(capsys, "frf", "fit", p, "--poles", "1", "--delay", "none",
                           "--json")
    assert code == 0 and json.loads(out)["notes"][0].startswith("the file gives a coherence")


@pytest.mark.parametrize("variables, said", [
    ({"H": [1 + 1j, 0.5j, -0.25]}, "(the response is read from H)"),
    ({"re": [1.0, 0.0, 0.0], "im": [0.0, 1.0, 0.0]}, "(the response is read from re and im)"),
    ({}, "(no variable holds a response: H (or frf, G, resp), or re and im)")])
def test_a_mat_variable_not_read_names_the_response_that_is(tmp_path, variables, said):
    """The warning said "the response is read from " and nothing after it in a file without
    a response, and "from freq_hz", the frequency, in a file that holds only it."""
    sio.savemat(tmp_path / "a.mat", {"freq_hz": [1.0, 2.0, 4.0], "note_x": [1.0],
                                     **variables})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            read_frf(tmp_path / "a.mat")
        except InputError:
            assert not variables
    text = [str(w.message) for w in caught if issubclass(w.category, InputWarning)]
    assert text == [f"{tmp_path / 'a.mat'}: variable 'note_x' is not read {said}"]
