"""Shared pytest configuration.

* ``@pytest.mark.rs274``: the test compares against a live rs274. Without
  rs274 on PATH such tests are skipped with :data:`NO_RS274_REASON`, and the
  session summary says how many were skipped for that reason (never silent).
* ``rs274`` fixture: the path of the rs274 executable (skips the same way).
* Under CI (``CI`` set, as .ci/run does) every property test draws the same
  examples on every run (hypothesis' ``derandomize``): a red CI then means
  the change, not a new random draw. Runs elsewhere draw fresh examples and
  keep finding new cases; one found is kept as an explicit test.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest
from hypothesis import settings

if os.environ.get("CI"):
    settings.register_profile("same-every-run", derandomize=True, database=None)
    settings.load_profile("same-every-run")

sys.path.insert(0, str(Path(__file__).resolve().parent))

import rs274 as harness  # noqa: E402

NO_RS274_REASON = (
    "rs274 not on PATH: differential test needs LinuxCNC's rs274 "
    "(apt-get install --no-install-recommends linuxcnc-uspace)"
)


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "rs274: compares against a live rs274 (skipped, and reported, when rs274 is not installed)",
    )


def pytest_collection_modifyitems(config, items):
    if harness.rs274_path() is not None:
        return
    skip = pytest.mark.skip(reason=NO_RS274_REASON)
    for item in items:
        if "rs274" in item.keywords:
            item.add_marker(skip)


@pytest.fixture(scope="session")
def rs274():
    path = harness.rs274_path()
    if path is None:
        pytest.skip(NO_RS274_REASON)
    return path


@pytest.fixture
def batch_rows(monkeypatch):
    """``batch_rows(name)`` patches the protocol's default batch method
    ``name`` (``runtime.canon.Canon.hole_moves``, ``contour_moves``...) to
    note how many rows each of its calls takes, and returns the list they
    go to: a test then knows the batch path was taken."""
    import inspect

    from runtime.canon import Canon

    def watch(name: str) -> list:
        default = getattr(Canon, name)
        # (where ``lines`` comes among the arguments, self apart)
        at = list(inspect.signature(default).parameters).index("lines") - 1
        rows: list = []

        def noted(self, *args, **keywords):
            rows.append(len(args[at]))
            return default(self, *args, **keywords)

        monkeypatch.setattr(Canon, name, noted)
        return rows

    return watch


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    skipped = terminalreporter.stats.get("skipped", [])
    n = 0
    for rep in skipped:
        longrepr = getattr(rep, "longrepr", None)
        text = str(longrepr[2]) if isinstance(longrepr, tuple) and len(longrepr) == 3 else str(longrepr)
        if "rs274 not on PATH" in text:
            n += 1
    if n:
        terminalreporter.write_sep(
            "=",
            f"{n} differential test(s) SKIPPED because rs274 is not installed",
            yellow=True,
            bold=True,
        )
    elif harness.rs274_path() is not None:
        terminalreporter.write_line(f"differential tests ran against {harness.rs274_path()}")
