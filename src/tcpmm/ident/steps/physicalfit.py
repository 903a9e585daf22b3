"""Physical step: the grey-box fit of the axis mechanics to its FRFs, as a linear axis
(:func:`~tcpmm.ident.physical.greybox.fit_physical`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..physical.greybox import PhysicalFit
from .fitcontext import physical_fit
from .frfs import fit_data

if TYPE_CHECKING:
    from ..chain import AxisRun
    from ..options import IdentifyOptions


@dataclass(frozen=True)
class LinearFit:
    """The physical fit of a linear axis to its FRFs.

    Parameters
    ----------
    data : dict
        The FRFs it was fitted to, :class:`~tcpmm.ident.physical.fitdata.FRFData` per
        name [SI].
    physical : PhysicalFit
        The fit, with standard deviations [SI].
    """

    data: dict
    physical: PhysicalFit


def fit_linear(run: AxisRun, options: IdentifyOptions) -> LinearFit:
    """Fit the mechanics of one axis to its FRFs, each bin weighed by its random error.

    Parameters
    ----------
    run : AxisRun
        The axis with its FRFs and its fit context [-].
    options : IdentifyOptions
        Not read by this step: the context carries what it needs [-].
    """
    data = fit_data(run.frfs.frfs)
    return LinearFit(data, physical_fit(run.context, data))
