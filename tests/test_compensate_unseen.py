"""A compensation judged by its draws, run on a true machine the model only approximates.

Machine 4 of the unseen-machine population of seed 91 (``studies.unseen``, with lost
motion) is identified from its own bundle; its model has Y's guideway share 0.63 against
0.70 and the structure behind Y's table (``M_b``, ``K_b``) at half the truth's. On bench
C's R 35 mm circle at F5000 the spike at the Y reversal after the correction stands 27 um
from the model's, which only a draw past a threshold shows: over eight draws (the former
default) the correction kept made the true machine's contour error 24.30 -> 24.96 um and
its G 33.84 -> 27.94 um; over the default's sixteen nothing is made worse
(``python -m studies.compensation_population --seed 91 --machines 4``).
"""

import numpy as np
import pytest

from conftest import bench_path
from studies.compensation import one
from studies.compensation_population import identified
from tcpmm.compensate.robust import DRAWS
from tcpmm.path import read_command_csv


# the bundle's identification says what its FRFs do not determine: that is its output, not
# what this test looks at
# The circle the draws judge is the one the command runs, as tcpmm compensate takes it
# without --radius (R 34.9968 mm, centred within 0.1 um: the same shares and figures as
# R 35 mm given, on this machine and the other 19 circles of the study). Judged as a path
# alone, the correction kept made the true machine's spikes at B and D worse.
@pytest.mark.filterwarnings("ignore::tcpmm.errors.InputWarning")
def test_a_machine_whose_friction_differs_in_form_is_made_no_worse():
    truth, model = identified(91, 4)
    cmd = read_command_csv(bench_path("c") / "circle_ccw_cmd.csv")
    r = one("m4", model, truth, "circle F5000", (cmd, cmd), 0.035, DRAWS, judged="command")
    worse = {k: (r[f"{k}_before"], r[f"{k}_after"]) for k in ("ce", "spike", "g")
             if r[f"{k}_after"] > r[f"{k}_before"] + 0.1}
    assert not worse and not r["spikes_grown"], (worse, r["spikes_grown"])
    assert np.all(np.isfinite([r[f"{k}_{when}"] for k in ("ce", "spike", "g")
                               for when in ("before", "after")]))
