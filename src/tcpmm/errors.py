"""Errors that tell the user what is wrong, where, and how to fix it."""

from __future__ import annotations

from pathlib import Path


class TcpmmError(Exception):
    """Base class of every error the package raises on purpose."""


class InputError(TcpmmError, ValueError):
    """Bad user input: a file, a column, a line of a program or a parameter.

    Parameters
    ----------
    message : str
        What is wrong and how to fix it [-].
    file : str or Path, optional
        The file the problem is in [-].
    line : int, optional
        1-based line number [-].
    column : int or str, optional
        1-based column number, or a column/field name [-].
    """

    def __init__(self, message, file=None, line=None, column=None):
        self.message = message
        self.file = None if file is None else str(file)
        self.line = line
        self.column = column
        super().__init__(self.format())

    def in_file(self, file) -> InputError:
        """This error, naming ``file`` where it names no file (a line of the file, found by
        code that has the content but not its name) [-]."""
        if self.file is not None or file is None:
            return self
        return InputError(self.message, file=file, line=self.line, column=self.column)

    def format(self) -> str:
        where = []
        if self.file is not None:
            where.append(str(Path(self.file)))
        if self.line is not None:
            where.append(f"line {self.line}")
        if self.column is not None:
            col = self.column
            # a YAML file's place is a key path (axes.X.servo.K_pp), not a column
            named = "key" if Path(str(self.file)).suffix.lower() in (".yaml", ".yml") else "column"
            where.append(f"column {col}" if isinstance(col, int) else f"{named} '{col}'")
        prefix = ", ".join(where)
        return f"{prefix}: {self.message}" if prefix else self.message


class InputWarning(UserWarning):
    """Input that can be used but probably is not what the user meant."""


class BuildNotice(UserWarning):
    """Work of minutes done once (the simulation kernel compiled for this CPU), said as it
    starts so that the wait is not taken for a hang; not a fault."""


class RunFaultWarning(InputWarning):
    """A simulated axis that ran away from its command or held its current at the limit:
    the run is a result to report, not a prediction (:mod:`tcpmm.analysis.runaway`)."""


class UnstableLoopWarning(RunFaultWarning):
    """A simulated axis whose sampled servo loop is unstable: its run diverges, and is no
    prediction either (:func:`tcpmm.sim.simulate.check_stability`)."""
