"""Identification of a machine from a measurement bundle, under the names its importers
use: the chain of steps is :mod:`tcpmm.ident.chain`, the results
:mod:`tcpmm.ident.identification`, the steps :mod:`tcpmm.ident.steps`."""

from .chain import identify_axis, identify_bundle
from .identification import AxisFit, AxisIdentification, Identification
from .options import MIN_COHERENCE
from .steps.axismodel import axis_config_to_sensors, axis_config_to_servo
from .steps.ltifits import TF_DELAY, TF_ORDERS

__all__ = ["MIN_COHERENCE", "TF_DELAY", "TF_ORDERS", "AxisFit", "AxisIdentification",
           "Identification", "axis_config_to_sensors", "axis_config_to_servo",
           "identify_axis", "identify_bundle"]
