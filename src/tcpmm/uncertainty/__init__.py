"""How far a prediction may be wrong: what the identification data leave open, each
predicted figure's 90 % interval, and a verdict a user can act on."""

from .figures import (
    PROGRAM_FIGURES,
    CircleTest,
    ProgramTest,
    circle_figures,
    figure_changes,
    figures,
    program_figures,
    reference_tests,
)
from .ranges import open_ranges
from .verdict import CALIBRATION, FigureVerdict, Verdict, prediction_verdict, target

__all__ = ["CALIBRATION", "PROGRAM_FIGURES", "CircleTest", "FigureVerdict", "ProgramTest",
           "Verdict", "circle_figures", "figure_changes", "figures", "open_ranges",
           "prediction_verdict", "program_figures", "reference_tests", "target"]
