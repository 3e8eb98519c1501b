"""``python -m ngc2py``: the same as the ``ngc2py`` command."""

import sys

from ngc2py.cli import main

sys.exit(main())
