"""``python -m cspace._cli`` (``python -m cspace`` is the same)."""

import sys

from .main import main

sys.exit(main())
