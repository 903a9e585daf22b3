"""The validation studies and the research code they share: kept in the repository but out
of the installed package, which carries only what a user's commands run.

Each study is a module run from the repository's root, ``.venv/bin/python -m studies.NAME``
(the commands are on the pages of docs/validation); the tests import the same modules, so
that the figures the documentation quotes still come out of them.
"""

from pathlib import Path

#: The shared data beside the checkout (``../shared/data``): the reference machines of an
#: independent simulator and the EMPS benchmark's records.
DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
