"""Errors raised by generated programs, and how they are reported.

A GCodeError carries rs274's message text. Where it happened (file, line,
subroutine call stack) is attached when the error leaves the program, by
mapping the traceback's generated-module frames back to G-code lines.
"""


class GCodeError(Exception):
    """An error rs274 would report; ``message`` is rs274's exact wording."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message
