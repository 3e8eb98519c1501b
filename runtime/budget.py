"""The step budget: a runaway program becomes an error, not a hang.

rs274 runs ``o1 while [1]`` (or a lathe cycle it cannot finish) forever.
ngc2py counts *steps* -- loop iterations and subroutine calls, the only
ways a G-code program can run longer than its text -- and stops with a
GCodeError when the budget is spent; the error names the loop or call
line like any other. Nothing is counted per block, so straight-line code
pays nothing; a loop pays one decrement per iteration.

A mixin of :class:`runtime.machine.Machine`; ``max_steps`` comes from
``Machine(max_steps=...)``, ``--max-steps N`` on the command lines; 0
means no limit.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Iterator

from itertools import repeat
from operator import length_hint

from runtime.errors import GCodeError

#: Loop iterations plus calls allowed by default: far more than real
#: programs use (a hand-written program loops thousands of times; CAM output
#: has no loops), and reached in seconds by an empty endless loop.
DEFAULT_MAX_STEPS = 10_000_000


#: How the runaway error begins.
RUNAWAY = "Step limit reached"


def runaway_message(max_steps: int) -> str:
    return (
        "%s: more than %d loop iterations and subroutine calls"
        " (a program that never ends?); --max-steps raises the limit"
        % (RUNAWAY, max_steps)
    )


class StepBudgetMixin:
    """Loop iterations and calls, counted down (part of Machine)."""

    def _set_budget(self, max_steps: int) -> None:
        self.max_steps = max_steps
        # step() is the next() of an iterator over the steps allowed: a call
        # into C, where a Python method cost a tenth of a simple loop. When
        # it runs out, its StopIteration becomes the runaway error
        # (Machine.run, runaway(); a generator must convert it itself).
        self.step = (
            iter(range(max_steps - 1)).__next__
            if max_steps > 0
            else repeat(None).__next__  # no limit
        )

    def runaway(self) -> GCodeError:
        """The error for a spent budget (what step()'s StopIteration means)."""
        return GCodeError(runaway_message(self.max_steps))

    def budget_spent(self) -> bool:
        """Is the budget spent? A StopIteration that reached the program's
        top means so only then: a canon method may raise one too (a
        ``next()`` on an iterator of its own run out), and that one is the
        canon's error, raised as it is."""
        return self.max_steps > 0 and length_hint(self.step.__self__) == 0

    def repeat(self, n: float) -> Iterator[int]:
        """``o.. repeat [n]``: n rounded to the nearest integer times (none
        if negative), each iteration one step."""
        from runtime.blockcheck import round_to_int

        for index in range(round_to_int(n)):
            try:
                self.step()  # (one loop iteration: generated loops call it)
            except StopIteration:
                raise self.runaway() from None
            yield index


__all__ = ["DEFAULT_MAX_STEPS", "RUNAWAY", "StepBudgetMixin", "runaway_message"]
