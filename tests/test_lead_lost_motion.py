"""A lead_mm 2 % off (19.6 for 20 on bench C's X): the lead mismatch was said, and beside it
a warning that the friction runs "would not find" a lost motion of up to 877 um, which
"would move the TCP spikes by up to 502 um", while the verdict's spikes were unchanged
and right. The bound was the lead's difference, read by the nut's fit as a deflection
growing with the travel; it is now said to be void until the lead is corrected."""

import dataclasses
import shutil
import warnings

from conftest import bench_path
from tcpmm.ident.pipeline import identify_bundle
from tcpmm.io.bundle import read_bundle


def test_a_lead_off_voids_the_bound_on_an_undetected_lost_motion(tmp_path):
    folder = tmp_path / "bundle"
    shutil.copytree(bench_path("c") / "bundle", folder)
    yaml_file = folder / "machine.yaml"
    text = yaml_file.read_text()
    assert "lead_mm: 20.0" in text
    yaml_file.write_text(text.replace("lead_mm: 20.0", "lead_mm: 19.6", 1))
    b = read_bundle(folder)
    b = dataclasses.replace(b, axes={"X": b.axes["X"]})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        idn = identify_bundle(b, verdict=False)
    said = [str(w.message) for w in caught]
    assert any("scale travels 1.02" in m and "lead_mm" in m for m in said), said
    assert not any("would not find one of up to" in m for m in said), said
    assert any("cannot bound one while their scale travels 1.02" in m
               and "Correct lead_mm" in m for m in said), said
    assert idn.axes["X"].lost_motion_sensitivity is None
