"""Transfer-function fragments (``format: tcpmm-tf/1``): what ``tcpmm frf fit
--model-fragment`` writes, read back as transfer functions.

A fragment is no machine model (it holds no axes) and :func:`tcpmm.load_model` refuses it
with a pointer here. Layout, SI units throughout::

    format: tcpmm-tf/1
    transfer_functions:
      speed_loop:                       # one entry per fitted response
        source: freq_trace.XML          # the measurement fitted
        input: ..., output: ..., unit: ...
        num: [...]                      # H(s) = num(s) / den(s) * exp(-s delay),
        den: [...]                      #   highest power of s first
        delay: 0.000328                 # [s]
        poles: [[re, im], ...]          # [rad/s]
        zeros: [[re, im], ...]          # [rad/s]
        band_hz: [f0, f1]               # band the fit holds for [Hz]
        rel_rms: 0.63                   # relative RMS residual over the band [-]
        gain_determined: true           # false: the static gain num(0)/den(0) is an
                                        #   extrapolation the bins do not determine
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from ..pade import with_delay
from .yamlutil import read_yaml_model, validate_yaml

__all__ = ["FORMAT", "FittedTF", "dumps_tf_fragment", "loads_tf_fragment", "read_tf_fragment"]

FORMAT = "tcpmm-tf/1"
_HINT = "see the keys that `tcpmm frf fit --model-fragment` writes (docs/frf_files.md)"
_HEADER = ("# tcpmm transfer-function fragment (tcpmm-tf/1), fitted by tcpmm frf fit; read it\n"
           "# with tcpmm.read_tf_fragment. SI units: H(s) = num(s) / den(s) * exp(-s delay),\n"
           "# coefficients highest power of s first [s^k]; delay [s]; poles and zeros [rad/s]\n"
           "# as [real, imaginary]; band_hz [Hz]; rel_rms: relative RMS residual [-];\n"
           "# gain_determined false: the static gain num(0)/den(0) is not determined by\n"
           "# the bins (an extrapolation below the band); use the model within band_hz.\n")


class _Entry(BaseModel):
    model_config = ConfigDict(extra="forbid")

    source: str = ""
    input: str = ""
    output: str = ""
    unit: str = ""
    num: list[float] = Field(min_length=1)
    den: list[float] = Field(min_length=1)
    delay: float = Field(0.0, ge=0.0, allow_inf_nan=False)
    poles: list[tuple[float, float]] = []
    zeros: list[tuple[float, float]] = []
    band_hz: tuple[float, float]
    rel_rms: float | None = None
    gain_determined: bool | None = None

    @field_validator("num", "den")
    @classmethod
    def _finite(cls, v):
        if not np.all(np.isfinite(v)):
            raise ValueError("coefficients must be finite")
        return v

    @model_validator(mode="after")
    def _proper(self):
        den = np.trim_zeros(np.asarray(self.den), "f")
        if den.size == 0:
            raise ValueError("den is zero")
        if np.trim_zeros(np.asarray(self.num), "f").size > den.size:
            raise ValueError("num has a higher degree than den: an improper transfer function")
        return self


class _Fragment(BaseModel):
    model_config = ConfigDict(extra="forbid")

    format: Literal["tcpmm-tf/1"]
    transfer_functions: dict[str, _Entry] = Field(min_length=1)


@dataclass(frozen=True)
class FittedTF:
    """A transfer function read from a fragment.

    Parameters
    ----------
    name : str
        Key of the entry [-].
    num, den : ndarray
        Coefficients in s, highest power first [SI].
    delay_s : float
        Pure delay [s].
    band_hz : tuple of float
        Band the fit holds for [Hz].
    input, output, unit, source : str
        Labels of the measured response and the file fitted [-].
    rel_rms : float or None
        Relative RMS residual of the fit over its band [-].
    gain_determined : bool or None
        Whether the bins determine the static gain ``num(0) / den(0)``; None where the
        fragment does not say [-].
    """

    name: str
    num: np.ndarray
    den: np.ndarray
    delay_s: float
    band_hz: tuple[float, float]
    input: str = ""
    output: str = ""
    unit: str = ""
    source: str = ""
    rel_rms: float | None = None
    gain_determined: bool | None = None

    def freqresp(self, f_hz) -> np.ndarray:
        """Complex response at ``f_hz`` [Hz], delay included [unit]."""
        s = 2j * np.pi * np.asarray(f_hz, dtype=float)
        return np.polyval(self.num, s) / np.polyval(self.den, s) * np.exp(-s * self.delay_s)

    def to_control(self, pade_order="auto"):
        """The transfer function for python-control, its delay as a Pade approximant.

        Parameters
        ----------
        pade_order : int or "auto"
            As :meth:`tcpmm.ident.lti.TFFit.to_control`, over ``band_hz`` [-].

        Returns
        -------
        control.TransferFunction
            Continuous-time transfer function [SI].
        """
        import control  # python-control is slow to import and needed only here

        tf = control.TransferFunction(self.num, self.den)
        return with_delay(tf, self.delay_s, self.band_hz[1], pade_order)


def _to_tfs(frag: _Fragment) -> dict[str, FittedTF]:
    return {k: FittedTF(name=k, num=np.asarray(e.num), den=np.asarray(e.den),
                        delay_s=e.delay, band_hz=tuple(e.band_hz), input=e.input,
                        output=e.output, unit=e.unit, source=e.source, rel_rms=e.rel_rms,
                        gain_determined=e.gain_determined)
            for k, e in frag.transfer_functions.items()}


def loads_tf_fragment(text: str, file="<fragment>") -> dict[str, FittedTF]:
    """Parse fragment text; see :func:`read_tf_fragment`."""
    return _to_tfs(validate_yaml(text, _Fragment, file, "transfer-function fragment", _HINT,
                                 FORMAT))


def read_tf_fragment(path) -> dict[str, FittedTF]:
    """Read a transfer-function fragment written by ``tcpmm frf fit --model-fragment``.

    Parameters
    ----------
    path : str or Path
        Fragment file (YAML, ``format: tcpmm-tf/1``) [-].

    Returns
    -------
    dict of str to FittedTF
        The transfer functions by name [SI].
    """
    return _to_tfs(read_yaml_model(path, _Fragment, "transfer-function fragment", _HINT,
                                   FORMAT))


def dumps_tf_fragment(res, source) -> str:
    """Fragment text of a fit.

    Parameters
    ----------
    res : FRFFit
        The fit [-].
    source : str or Path
        The measurement fitted, recorded in the fragment [-].

    Returns
    -------
    str
        YAML text [-].
    """
    import yaml

    d = res.to_dict()
    key = "".join(c if c.isalnum() else "_" for c in (res.name or "response")).strip("_")
    body = {"format": FORMAT, "transfer_functions": {key or "response": {
        "source": str(source), "input": d["input"], "output": d["output"], "unit": d["unit"],
        "num": d["num"], "den": d["den"], "delay": d["delay_s"], "poles": d["poles"],
        "zeros": d["zeros"], "band_hz": d["band_hz"], "rel_rms": d["quality"]["rel_rms"],
        **({} if d.get("gain") is None else
           {"gain_determined": bool(d["gain"]["gain_determined"])})}}}
    return _HEADER + yaml.safe_dump(body, sort_keys=False, default_flow_style=None)
