"""``python -m cspace``: the ``cspace`` command."""

import sys

from cspace._cli.main import main

sys.exit(main())
