"""``python -m ptpcert.cli``: the ``ptpcert`` program."""

import sys

from ptpcert.cli import main

sys.exit(main())
