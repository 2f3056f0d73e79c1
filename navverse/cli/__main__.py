"""``python -m navverse.cli``: the ``navverse`` command."""

import sys

from navverse.cli import main

if __name__ == "__main__":
    sys.exit(main())
