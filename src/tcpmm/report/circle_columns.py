"""The circle tables' columns named for a reader."""

from __future__ import annotations

from ..analysis.circle_spike_sigma import U95_COLUMNS

SENSOR_NAMES = {"cmd": "command", "motor": "motor encoder", "scale": "linear scale",
                "tcp": "TCP"}


def um_columns(frame):
    """A circle table with its µm columns named for a reader: ``spike A [µm]`` [-]."""
    names = {f"spike_after_terms_{q}_um": f"spike {q} after the terms [µm]" for q in "ABCD"}
    names.update({f"spike_{q}_um": f"raw spike {q} [µm]" for q in "ABCD"})
    names.update(U95_COLUMNS)
    names.update(contour_error_um="contour error [µm]", circular_deviation_um="G [µm]",
                 command_radial_deviation_um="command radius - nominal [µm]",
                 radial_rms_um="radial rms [µm]", radial_max_um="radial max [µm]")
    frame = frame.rename(columns=names)
    if "direction" in frame:
        frame["direction"] = frame["direction"].str.upper()
    if "sensor" in frame:
        frame["sensor"] = frame["sensor"].map(lambda s: SENSOR_NAMES.get(s, s))
    return frame
