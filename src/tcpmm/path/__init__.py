"""Tool path: NC program or circle definition to the interpolated position command.

Entry points: :func:`circle_command`, :func:`parse_gcode`, :func:`program_to_command`,
:func:`interpolate` with :class:`InterpolatorSettings`, and the command file
:func:`read_command_csv` / :func:`write_command_csv`.
"""

from .circle import circle_command, circle_segments, circle_settings
from .command import Command
from .commandfile import read_command_csv, write_command_csv
from .gcode_stream import parse_gcode
from .interpolate import Interpolation, interpolate, interpolate_detailed
from .program import program_to_command, read_program
from .segments import Arc, Dwell, Line, Rapid
from .settings import InterpolatorSettings

__all__ = [
    "Arc",
    "Command",
    "Dwell",
    "Interpolation",
    "InterpolatorSettings",
    "Line",
    "Rapid",
    "circle_command",
    "circle_segments",
    "circle_settings",
    "interpolate",
    "interpolate_detailed",
    "parse_gcode",
    "program_to_command",
    "read_command_csv",
    "read_program",
    "write_command_csv",
]
