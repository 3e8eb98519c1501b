"""Regular expressions compiled at their first use.

Importing ``re`` costs a generated module's start-up several milliseconds,
and most runs never read a tool table, an INI file or an error's caret: the
modules that need a pattern declare it with :class:`Pattern` at import time
and pay for ``re`` only when the pattern is first used.
"""

from __future__ import annotations


class Pattern:
    """Stands for ``re.compile(source)``; flags go inline (``(?i)...``)."""

    __slots__ = ("source", "_compiled")

    def __init__(self, source: str):
        self.source = source
        self._compiled = None

    def __getattr__(self, name: str):
        # Only reached for names not in __slots__: the pattern's methods.
        compiled = self._compiled
        if compiled is None:
            import re

            compiled = self._compiled = re.compile(self.source)
        return getattr(compiled, name)
