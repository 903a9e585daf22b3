"""``python -m studies.emps``: the EMPS study from the command line."""

import sys

from tcpmm.errors import InputError

from .report import main

if __name__ == "__main__":
    try:
        main()
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        sys.exit(2)
