"""Golden checks at library scale: compiled modules are reused across the
scratch copies checks run in (the cache is keyed by content and options,
not by folder), a scratch copy holds only what a run can read, and nothing
stale is ever served."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest

from ngc2py import cache, golden

MAIN = "o<helper> call [2]\nG1 X#<_value> F100\nM2\n"
HELPER = "o<helper> sub\n  G0 Y[#1 * 3]\n  o<helper> return [#1 + 1]\no<helper> endsub\n"


@pytest.fixture
def library(tmp_path, monkeypatch):
    folder = tmp_path / "lib"
    folder.mkdir()
    (folder / "main.ngc").write_text(MAIN)
    (folder / "helper.ngc").write_text(HELPER)
    (folder / "tools.tbl").write_text("T1 P1 Z0.5 D1 ;one\n")
    for k in range(30):  # other programs and their recordings: not copied
        (folder / f"other{k}.ngc").write_text(f"G0 X{k}\nM2\n")
        (folder / f"other{k}.out").write_text("x" * 1000)
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    return folder


def test_copies_of_a_folder_share_one_compiled_module(library, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(library, copy)
    here = os.getcwd()
    try:
        os.chdir(library)
        first = cache.cached_module("main.ngc")
        stamp = os.stat(first).st_mtime_ns
        os.chdir(copy)
        assert cache.cached_module("main.ngc") == first
        assert os.stat(first).st_mtime_ns == stamp  # served, not written again
        # a copy whose subroutine file differs gets a module of its own
        (copy / "helper.ngc").write_text(HELPER.replace("* 3", "* 4"))
        changed = cache.cached_module("main.ngc")
        assert "* 4" in Path(changed).read_text() or "4.0" in Path(changed).read_text()
        assert "helper.ngc" in Path(changed).read_text()
    finally:
        os.chdir(here)


def test_a_run_copies_only_what_it_can_read(library):
    inputs = golden.run_inputs(library / "main.ngc", ["-t", "tools.tbl"])
    assert sorted(inputs) == ["helper.ngc", "main.ngc", "tools.tbl"]
    # an ini can name more files: the whole folder is copied then
    assert golden.run_inputs(library / "main.ngc", ["-i", "x.ini"]) is None


def test_check_sees_a_changed_subroutine_file(library):
    golden.record(library / "main.ngc", [])
    assert golden.check(library / "main.ngc") == []
    (library / "helper.ngc").write_text(HELPER.replace("* 3", "* 5"))
    problems = golden.check(library / "main.ngc")
    assert problems and "stdout differs" in problems[-1]
    (library / "helper.ngc").write_text(HELPER)
    assert golden.check(library / "main.ngc") == []


def test_check_sees_a_changed_tool_table(library):
    (library / "t.ngc").write_text("T1 M6\nG43\nG0 Z1\nM2\n")
    golden.record(library / "t.ngc", ["-t", "tools.tbl"])
    assert golden.check(library / "t.ngc") == []
    (library / "tools.tbl").write_text("T1 P1 Z0.75 D1 ;one\n")
    assert golden.check(library / "t.ngc")
