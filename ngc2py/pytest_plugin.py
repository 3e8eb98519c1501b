"""pytest plugin: every recorded G-code program is a test.

Installed with ngc2py (a ``pytest11`` entry point), so ``pytest`` in a folder
of programs collects each ``PROG.ngc`` that has a recording (``PROG.rc``
and friends, written by ``ngc2py golden record``; see
:mod:`ngc2py.golden`) as one test item: it runs the program in a scratch
copy of its folder and fails, with a unified diff, when the trace, the
error message or the exit status changed.

``pytest --ngc-record`` records instead of checking: every collected
program (also those without a recording yet, except external subroutine
files) gets its recording rewritten, and the item passes. Folders marked as
holding rs274's recordings (``.golden-from-rs274``) are never re-recorded.

Items touch nothing but their own program's recording files, so they run
in parallel under pytest-xdist; each run is deterministic.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from ngc2py import golden


def pytest_addoption(parser) -> None:
    group = parser.getgroup("ngc2py", "golden tests of G-code programs (ngc2py)")
    group.addoption(
        "--ngc-record",
        action="store_true",
        default=False,
        help="record the trace of every collected .ngc program instead of checking it",
    )
    group.addoption(
        "--ngc-timeout",
        type=float,
        default=None,
        metavar="SECONDS",
        help="fail a G-code program that runs longer than this",
    )
    parser.addini(
        "ngc_golden",
        type="bool",
        default=True,
        help="collect recorded .ngc programs as tests (set false to turn off)",
    )


def pytest_collect_file(file_path: Path, parent):
    if file_path.suffix != ".ngc" or not parent.config.getini("ngc_golden"):
        return None
    if golden.has_recording(file_path):
        return NgcFile.from_parent(parent, path=file_path)
    if parent.config.getoption("ngc_record") and not golden.is_subroutine_file(file_path):
        if golden.reference_folder(file_path) is None:
            return NgcFile.from_parent(parent, path=file_path)
    return None


class NgcFile(pytest.File):
    """A G-code program: one test item."""

    def collect(self):
        yield NgcItem.from_parent(self, name=self.path.name)


class ChangedError(Exception):
    """The program no longer does what its recording says."""


class NotRecordedError(Exception):
    """--ngc-record could not record the program."""


class NgcItem(pytest.Item):
    def runtest(self) -> None:
        config = self.config
        timeout = config.getoption("ngc_timeout")
        if config.getoption("ngc_record"):
            try:
                golden.record(self.path, None, timeout)
            except golden.GoldenError as error:
                raise NotRecordedError(str(error)) from None
            return
        problems = golden.check(self.path, None, timeout)
        if problems:
            raise ChangedError("\n".join(problems))

    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, ChangedError):
            return (
                f"{self.path.name} changed against its recording "
                f"(re-record with `pytest --ngc-record` if that is intended):\n"
                f"{excinfo.value}"
            )
        if isinstance(excinfo.value, (NotRecordedError, golden.GoldenError)):
            return str(excinfo.value)
        return super().repr_failure(excinfo, style)

    def reportinfo(self):
        return self.path, None, f"ngc2py golden: {self.path.name}"
