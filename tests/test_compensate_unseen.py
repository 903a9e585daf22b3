"""A compensation judged by its draws, run on a true machine the model only approximates.

Machine 4 of the unseen-machine population of seed 91 (``studies.unseen``, with lost
motion) is identified from its own bundle; its friction differs from the model's in form
(Stribeck with viscous contacts against the identified LuGre) and in its split. On bench
C's R 35 mm circle at F5000 the spike at the Y reversal after the correction stands 27 um
from the model's, which only a draw past a threshold shows: over eight draws (the former
default) the correction kept made the true machine's contour error 24.30 -> 24.96 um and
its G 33.84 -> 27.94 um; over the default's sixteen nothing is made worse
(``python -m studies.compensation_population --seed 91 --machines 4``).
"""

import numpy as np
import pytest

from conftest import bench_path
from studies.compensation_population import identified
from tcpmm.compensate import compensate, machine_bounds, robust_factors
from tcpmm.compensate.scores import judge, judged_path, programmed_path, runs_before_after
from tcpmm.path import read_command_csv


# the bundle's identification says what its FRFs do not determine: that is its output, not
# what this test looks at
@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_a_machine_whose_friction_differs_in_form_is_made_no_worse():
    truth, model = identified(91, 4)
    cmd = read_command_csv(bench_path("c") / "circle_ccw_cmd.csv")
    comp = compensate(model, cmd, bounds=machine_bounds(model))
    robust_factors(model, comp, radius_m=0.035)
    before, after = runs_before_after(truth, comp, programmed=cmd)
    b = judge(before, programmed_path(comp, cmd), 0.035)
    a = judge(after, judged_path(comp), 0.035)
    pairs = {"contour error": (b["path"]["contour_error_um"], a["path"]["contour_error_um"]),
             "largest spike": (b["circle"]["largest_spike_um"], a["circle"]["largest_spike_um"]),
             "G": (b["circle"]["circular_deviation_um"], a["circle"]["circular_deviation_um"])}
    worse = {k: v for k, v in pairs.items() if v[1] > v[0] + 0.1}
    assert not worse, worse
    assert np.all(np.isfinite([v for p in pairs.values() for v in p]))
