"""rs274's loop flags that outlive the loop that set them.

rs274 runs O-word loops by skipping forward to, and seeking back from, the
line with a label. Two global flags steer what a closing line does, and
neither is always cleared by the loop that set it:

* ``doing_break``, set by every ``break``, is cleared only at the closing
  ``while`` of a do-loop, which then does not loop back. A while-loop's
  break leaves it set, so the next do-loop ends after one pass. The
  generated code keeps it in ``m.doing_break`` when a program can be hit.
* ``doing_continue``, set by every ``continue``, is cleared only at an
  ``endwhile``/``endrepeat`` reached by skipping, which then loops back
  instead of ending the loop. A do-loop's continue skips to the do-loop's
  closing ``while`` and leaves it set: the next while-loop ``break``
  continues that loop once more instead, and the next ``repeat`` loop runs
  its count again after it ends (rs274 goes back to the ``repeat`` line and
  counts afresh). The generated code keeps it in ``m.doing_continue``.

A repeat loop's count also outlives the loop: rs274 keeps the count left
under the loop's label and computes a new one only after the loop has run
out. A repeat loop left early (a return from inside it, a break or continue
of an outer loop, a missing ``endrepeat``) resumes with the count it had
left the next time its ``repeat`` line is reached.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: start-up cost
if TYPE_CHECKING:
    from typing import Iterator


def repeat_with_stale_continue(machine, count: int) -> Iterator[int]:
    """``o.. repeat [n]`` in a program that may leave ``doing_continue`` set:
    the count again each time the loop ends with the flag set."""
    while True:
        yield from range(count)
        if not machine.doing_continue:
            return
        machine.doing_continue = False


def repeat_keeping_count(machine, key: str, count: int, again: bool = True) -> Iterator[int]:
    """``o.. repeat [n]`` that may be left early: the count left is kept
    under ``key`` (rs274's name of the label) for the next time. Without
    ``again`` the count never runs again (rs274 fails before it would)."""
    counts = machine._repeat_counts
    while True:
        if counts.get(key, -1) == -1:
            counts[key] = count
        if counts[key] > 0:
            counts[key] -= 1
            yield counts[key]
            continue
        counts[key] = -1
        if not again or not machine.doing_continue:
            return
        machine.doing_continue = False
