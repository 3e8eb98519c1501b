"""ngc2py/bytecode.py: a generated module compiled with its long literals
stood in for is the very code ``compile`` makes of it.

Code objects compare their bytecode, constants, names, line and column
tables: equal code runs alike and reports the same lines. Every property
runs with the length limit lowered to one character, so every literal the
module stands in for is taken, not only those of CAM-sized programs."""

from __future__ import annotations

import os
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import cam_strategies
import strategies
import test_cycles
from test_differential import PROFILE

from ngc2py import bytecode, cache
from ngc2py.compiler import compile_text

#: A module-level literal the module stands in for.
LITERAL = re.compile(r'^\w+ = b?"""\\?\n', re.M)


@pytest.fixture(autouse=True)
def every_literal(monkeypatch):
    monkeypatch.setattr(bytecode, "LONG", 1)


def same_code(text: str, taken: bool = True) -> None:
    expected = compile(text, "prog.py", "exec", dont_inherit=True)
    assert bytecode.compile_module(text, "prog.py") == expected
    if taken:
        skeleton, values = bytecode._stand_in(text)
        assert values and skeleton != text  # (the quick way was taken)


@settings(PROFILE, max_examples=PROFILE.max_examples // 2)
@given(
    st.one_of(
        cam_strategies.cam_programs(),
        cam_strategies.arc_programs(),
        test_cycles.cycle_tables(),
    )
)
def test_modules_with_tables_compile_to_the_same_code(program):
    text = compile_text(program, "prog.ngc")
    # (a program of a few rows has no table, and its G-code text is short)
    same_code(text, taken=LITERAL.search(text) is not None)


@settings(PROFILE, max_examples=PROFILE.max_examples // 2)
@given(strategies.valid_programs())
def test_other_modules_compile_to_the_same_code(program):
    same_code(compile_text(program, "prog.ngc"), taken=False)


def test_a_cam_sized_module_with_its_g_code_text_as_bytes():
    rows = "\n".join("G1 X%d.5 Y%d" % (k, k % 7) for k in range(8000))
    text = compile_text("G21 F100\n" + rows + "\nM2\n", "big.ngc")
    assert ' = b"""\\\n' in text  # (the compressed G-code text)
    same_code(text)


@pytest.mark.parametrize(
    "text",
    [
        'T = """\nrows\n"""\nU = """\nrows\n"""\n',  # equal: one constant
        'T = """\na\\tb\n"""\n',  # an escape: its value is not its text
        'T = """\nsaid "hi"\n"""\n',
        'T = b"""\\\nabc\ndef\n"""\n',
        'T = """\\\nabc\n"""\nx = len(T)\n',
        'def f():\n    """A = """\n    return 1\n',  # not an assignment
        '"""doc\nX = """\nY = """\nrows\n"""\n',  # inside another literal
        'T = """\nrows\n"""  # a comment\n',  # closing quotes not alone
        'T = """\n\u00e9t\u00e9\n"""\n',
        # a marker's look-alike
        'T = """\nrows\n"""\nS = "\\nngc2py stand-in 0\\n"\n',
        'T = """\nrows\n"""\n# ngc2py stand-in\n',
    ],
)
def test_odd_literals_compile_to_the_same_code(text):
    same_code(text, taken=False)


@pytest.mark.parametrize(
    "text",
    [
        'T = """\nrows\n"""\nx = (\n',
        'T = """\nrows\n"""\n\0\n',
        'T = """\nrows\n',
        'T = b"""\n\u00e9t\u00e9\n"""\n',  # bytes are ASCII
    ],
)
def test_errors_are_compile_s_own(text):
    with pytest.raises((SyntaxError, ValueError)) as expected:
        compile(text, "prog.py", "exec", dont_inherit=True)
    with pytest.raises(type(expected.value)) as found:
        bytecode.compile_module(text, "prog.py")
    assert str(found.value) == str(expected.value)


def test_a_new_cache_entry_is_imported_from_the_bytecode_written_with_it(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    program = tmp_path / "prog.ngc"
    program.write_text(
        "G21 F100\n" + "\n".join("G1 X%d Y1" % k for k in range(200)) + "\nM2\n"
    )
    module = cache.cached_module(str(program))
    from importlib.util import cache_from_source

    assert os.path.isfile(cache_from_source(module))
    # another process's import reads it (this one's has the code at hand:
    # the next test): compiling would call the loader's source_to_code
    monkeypatch.setattr(cache, "_COMPILED", {})
    monkeypatch.setattr(
        cache._KeepingLoader,
        "source_to_code",
        lambda *args, **kw: pytest.fail("compiled again"),
    )
    loaded = cache.load_cached(module, str(program))
    with open(module, encoding="utf-8") as handle:
        expected = compile(handle.read(), module, "exec", dont_inherit=True)
    assert loaded.main.__code__ == next(
        c for c in expected.co_consts if getattr(c, "co_name", "") == "main"
    )


def test_the_process_that_compiles_an_entry_imports_its_code_as_compiled(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    program = tmp_path / "prog.ngc"
    program.write_text(
        "G21 F100\n"
        + "\n".join("G1 X%d Y%d" % (k, k % 7) for k in range(300))
        + "\nM2\n"
    )
    read = []
    original = cache._KeepingLoader.get_data
    monkeypatch.setattr(
        cache._KeepingLoader,
        "get_data",
        lambda self, path: read.append(path) or original(self, path),
    )
    module = cache.cached_module(str(program))
    first = cache.load_cached(module, str(program))
    # neither the bytecode just written nor the source was read back
    assert read == []
    second = cache.load_cached(module, str(program))
    from importlib.util import cache_from_source

    assert read == [cache_from_source(module)]  # a hit reads the bytecode
    assert first.main.__code__ == second.main.__code__
    assert first.__ngc__.files == second.__ngc__.files == (str(program),)


def test_a_loader_s_module_is_the_one_importlib_util_makes(tmp_path):
    import importlib.util

    path = tmp_path / "prog.py"
    path.write_text("X = 1\n")
    ours = bytecode.QuickLoader("ngc2py_program", str(path)).load()
    loader = bytecode.QuickLoader("ngc2py_program", str(path))
    spec = importlib.util.spec_from_file_location(
        "ngc2py_program", str(path), loader=loader
    )
    theirs = importlib.util.module_from_spec(spec)
    loader.exec_module(theirs)
    names = ("__name__", "__file__", "__cached__", "__package__", "__doc__", "X")
    assert [getattr(ours, n) for n in names] == [getattr(theirs, n) for n in names]
    assert set(vars(ours)) == set(vars(theirs))
    fields = ("name", "origin", "cached", "has_location", "parent", "loader_state")
    assert [getattr(ours.__spec__, f) for f in fields] == [
        getattr(theirs.__spec__, f) for f in fields
    ]
    assert ours.__spec__.submodule_search_locations is None
    assert ours.__loader__ is ours.__spec__.loader


def test_a_module_loaded_without_bytecode_is_compiled_the_quick_way(monkeypatch):
    # a program read from stdin, a cache that cannot be written
    from ngc2py import loading

    rows = "\n".join("G1 X%d Y1" % k for k in range(300))
    text = compile_text("G21 F100\n" + rows + "\nM2\n", "prog.ngc")
    taken = []
    monkeypatch.setattr(
        bytecode,
        "compile_module",
        lambda text, path: taken.append(path) or compile(text, path, "exec"),
    )
    module = loading.load_text(text)
    assert len(taken) == 1 and module.__ngc__.files == ("prog.ngc",)
