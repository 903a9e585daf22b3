"""The kernel's inputs by name (tcpmm.sim.inputs) and the layout of its parameter vectors
(tcpmm.sim.layout): every entry named once, every field packed where the kernel reads it,
and the arguments of the kinds the compiled module was built for."""

import re
from pathlib import Path

import numpy as np
import pytest

from tcpmm import _compiled, builtin_machine
from tcpmm.sim import layout
from tcpmm.sim.inputs import kernel_inputs

SIM = Path(__file__).resolve().parents[1] / "src" / "tcpmm" / "sim"


def _entries(prefix):
    return {k: v for k, v in vars(layout).items() if k.startswith(prefix)}


@pytest.mark.parametrize(("prefix", "size"), [("FP_", layout.N_FP), ("IP_", layout.N_IP)])
def test_every_entry_is_named_once(prefix, size):
    assert sorted(_entries(prefix).values()) == list(range(size))


def _inputs(axis_name="X", **kw):
    axis = builtin_machine().axes[axis_name]
    t = np.arange(0.0, 0.01, 1e-3)
    return axis, kernel_inputs(axis, 1e-3 * t, np.zeros(t.size), 1e-3, 80, **kw)


def test_the_vectors_carry_the_fields_at_their_entries():
    axis, k = _inputs(rec_every=8)
    fp, ip = k.float_params(), k.int_params()
    s = axis.servo
    assert fp[layout.FP_K_PP] == s.K_pp and fp[layout.FP_K_VI] == s.K_vi
    assert fp[layout.FP_T_V] == s.T_v and fp[layout.FP_K_NUT] == axis.mechanics.K_t
    assert fp[layout.FP_CMD_PER_STEP] == s.T_v / 1e-3
    assert fp[layout.FP_CARRIAGE_FORCE] == axis.mechanics.load_force
    assert ip[layout.IP_N_STEPS] == 80 and ip[layout.IP_REC_EVERY] == 8
    assert ip[layout.IP_N_POS] == s.n_pos and ip[layout.IP_CLOSED] == 1
    assert ip[layout.IP_SHORTCUTS] == 1 and ip[layout.IP_GUIDEWAY_REF] == -1
    assert k.n_records == 10 and k.empty_record().shape == (len(layout.REC_COLUMNS), 10)
    fields = {f: getattr(k, f) for f in ("K_pp", "K_vp", "K_vi", "k_ff", "R_L",
                                         "current_limit", "T_v", "encoder_quantum",
                                         "scale_quantum", "integrator0", "motor_torque",
                                         "screw_torque", "carriage_force", "cmd_per_step",
                                         "half_play", "K_t")}
    assert sorted(fp.tolist()) == sorted(float(v) for v in fields.values())


def test_open_loop_and_unquantised_feedback_reach_the_vectors():
    _, k = _inputs(open_loop=True, quantise_feedback=False)
    fp, ip = k.float_params(), k.int_params()
    assert ip[layout.IP_CLOSED] == 0 and fp[layout.FP_INTEGRATOR0] == 0.0
    assert fp[layout.FP_Q_ENCODER] == 0.0 and fp[layout.FP_Q_SCALE] == 0.0


def test_the_arguments_are_of_the_kinds_the_module_was_built_for():
    """A mismatch would send every run to numba's kernel, silently and more slowly."""
    _, k = _inputs()
    assert _compiled._fits(_compiled.FUNCTIONS["run_axis"][3], k.as_args(k.empty_record()))


def test_no_literal_index_into_the_parameter_vectors():
    """The kernel and its callers read ``fp`` and ``ip`` by the names of the layout."""
    literal = re.compile(r"\b[fi]p\[\s*-?\d")
    found = {p.name: n + 1 for p in sorted(SIM.glob("*.py"))
             for n, line in enumerate(p.read_text(encoding="utf-8").splitlines())
             if literal.search(line)}
    assert not found, f"literal indices into fp/ip: {found}"
