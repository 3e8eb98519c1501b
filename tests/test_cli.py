"""The command lines: ``ngc2py convert|run``, ``python -m ngc2py`` and the
generated module's own (runtime.main.run_cli), plus the compile cache."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as hs

from ngc2py import cache, cli

import rs274 as harness

REPO = Path(__file__).resolve().parent.parent


def ngc2py(*args, cwd, env_extra=None, text=True):
    env = dict(os.environ, PYTHONPATH=str(REPO), NGC2PY_CACHE=str(Path(cwd) / "cache"))
    env.update(env_extra or {})
    return subprocess.run(
        [sys.executable, "-m", "ngc2py", *map(str, args)],
        cwd=cwd,
        env=env,
        capture_output=True,
        text=text,
        timeout=120,
    )


def one_line_error(proc):
    """Exit status 1, no traceback, and the problem stated in one line."""
    assert proc.returncode == 1
    assert "Traceback" not in proc.stderr
    lines = [l for l in proc.stderr.splitlines() if l != "executing"]
    assert len(lines) == 1
    return lines[0]


def test_help_describes_both_commands(tmp_path):
    proc = ngc2py("--help", cwd=tmp_path)
    assert proc.returncode == 0 and "convert" in proc.stdout and "run" in proc.stdout


def test_convert_writes_next_to_the_source_by_default(tmp_path):
    (tmp_path / "part.ngc").write_text("G0 X1\nM2\n")
    proc = ngc2py("convert", "part.ngc", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    text = (tmp_path / "part.py").read_text()
    assert text.startswith('"""part.ngc, compiled by ngc2py')
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".tmp-")]


def test_convert_to_stdout_and_to_a_chosen_file(tmp_path):
    (tmp_path / "part.ngc").write_text("G0 X1\nM2\n")
    out = ngc2py("convert", "part.ngc", "-o", "-", cwd=tmp_path)
    ngc2py("convert", "part.ngc", "-o", "other.py", cwd=tmp_path)
    assert out.stdout == (tmp_path / "other.py").read_text()


def test_convert_of_a_missing_file_is_one_clear_line(tmp_path):
    message = one_line_error(ngc2py("convert", "nope.ngc", cwd=tmp_path))
    assert "nope.ngc" in message


def test_convert_of_a_directory_is_one_clear_line(tmp_path):
    (tmp_path / "dir.ngc").mkdir()
    assert "directory" in one_line_error(ngc2py("convert", "dir.ngc", cwd=tmp_path))


# measured: rs274 -g on a directory opens it, reads nothing, and says this
# after its 5 start-up calls; run adds where (the file) after rs274's lines.
def test_run_of_a_directory_fails_like_rs274_opening_an_empty_file(tmp_path):
    (tmp_path / "dir.ngc").mkdir()
    proc = ngc2py("run", "dir.ngc", cwd=tmp_path)
    assert proc.returncode == 1 and len(proc.stdout.splitlines()) == 5
    assert proc.stderr.splitlines() == [
        "executing",
        "File ended with no percent sign",
        "",
        "  at dir.ngc",
    ]


def test_unreadable_file_is_one_clear_line(tmp_path):
    path = tmp_path / "secret.ngc"
    path.write_text("M2\n")
    path.chmod(0)
    if os.access(path, os.R_OK):
        pytest.skip("running as a user who can read any file")
    assert "secret.ngc" in one_line_error(ngc2py("convert", "secret.ngc", cwd=tmp_path))


def test_binary_junk_never_gives_a_traceback(tmp_path):
    (tmp_path / "junk.ngc").write_bytes(bytes(range(256)) * 8)
    # bytes: the offending line is echoed as the raw bytes it was read from
    proc = ngc2py("run", "junk.ngc", cwd=tmp_path, text=False)
    assert proc.returncode == 1 and b"Traceback" not in proc.stderr


def test_generated_module_reports_file_line_and_call_stack(tmp_path):
    (tmp_path / "p.ngc").write_text(
        "o<s> sub\nG0 X[1/#1]\no<s> endsub\no<s> call [0]\nM2\n"
    )
    ngc2py("convert", "p.ngc", cwd=tmp_path)
    proc = subprocess.run(
        [sys.executable, "p.py"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
    )
    assert proc.returncode == 1
    # rs274's two lines (message, line text), a caret under the word whose
    # value failed, file:line:column, the O-call that led there
    # (columns of a failing expression need Python 3.11's code positions)
    caret = (
        ["   ^", "  at p.ngc:2:4"] if sys.version_info >= (3, 11) else ["  at p.ngc:2"]
    )
    assert proc.stderr.splitlines()[1:] == [
        "Attempt to divide by zero",
        "G0 X[1/#1]",
        *caret,
        "  called from p.ngc:4: o<s> call [0]",
    ]


def test_bad_option_of_a_generated_module(tmp_path):
    (tmp_path / "p.ngc").write_text("M2\n")
    ngc2py("convert", "p.ngc", cwd=tmp_path)
    proc = subprocess.run(
        [sys.executable, "p.py", "-x"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env=dict(os.environ, PYTHONPATH=str(REPO)),
    )
    assert proc.returncode == 1 and "Traceback" not in proc.stderr


def test_cache_hits_and_invalidates_on_change(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    source = tmp_path / "p.ngc"
    source.write_text("o<ext> call\nM2\n")
    first = cache.cached_module("p.ngc")
    assert cache.cached_module("p.ngc") == first
    (tmp_path / "ext.ngc").write_text("o<ext> sub\nG0 X1\no<ext> endsub\nM2\n")
    second = cache.cached_module("p.ngc")
    assert "def o_ext" in Path(second).read_text()
    assert cache.cached_module("p.ngc") == second
    source.write_text("o<ext> call\nG0 X2\nM2\n")
    assert cache.cached_module("p.ngc") not in (first, second)


def test_the_compiler_s_fingerprint_is_its_sources_hash_noted_by_their_stamp(
    tmp_path,
):
    """The fingerprint is the hash of the sources' content, noted in the
    cache folder with the files' stamp (sizes and times) and read back
    while the stamp holds; a changed file or a note not to be trusted
    hashes them again. ngc2py's own is the same with and without a note."""
    package, folder = tmp_path / "pkg", tmp_path / "cache"
    package.mkdir()
    (package / "a.py").write_text("one = 1\n")
    (package / "b.c").write_text("int b;\n")
    (package / "notes.txt").write_text("not a source")
    first = cache.sources_fingerprint(str(package), str(folder))
    note = folder / cache._FINGERPRINT_NOTE
    assert note.read_text().split()[1] == first
    assert cache.sources_fingerprint(str(package), str(folder)) == first
    # the note is what is read while the stamp holds: content changed
    # behind an unchanged size and time is not looked at
    status = os.stat(package / "a.py")
    (package / "a.py").write_text("one = 2\n")
    os.utime(package / "a.py", ns=(status.st_atime_ns, status.st_mtime_ns))
    assert cache.sources_fingerprint(str(package), str(folder)) == first
    # a changed size (or time) hashes the files again
    (package / "a.py").write_text("one = 22\n")
    changed = cache.sources_fingerprint(str(package), str(folder))
    assert changed != first and note.read_text().split()[1] == changed
    (package / "notes.txt").write_text("changed, not a source")
    assert cache.sources_fingerprint(str(package), str(folder)) == changed
    # without a note (or with a broken one), the same hash
    for text in (None, "garbage", note.read_text().split()[0] + " zz" * 32):
        if text is None:
            note.unlink()
        else:
            note.write_text(text)
        assert cache.sources_fingerprint(str(package), str(folder)) == changed
    assert cache.sources_fingerprint(str(package), str(tmp_path / "none")) == changed
    # an unwritable folder: hashed, nothing noted
    blocked = tmp_path / "file"
    blocked.write_text("")
    assert cache.sources_fingerprint(str(package), str(blocked)) == changed
    ngc2py_package = os.path.dirname(os.path.realpath(cache.__file__))
    noted = cache.sources_fingerprint(ngc2py_package, str(tmp_path / "own"))
    assert cache.sources_fingerprint(ngc2py_package, str(tmp_path / "own")) == noted
    assert cache.sources_fingerprint(ngc2py_package, str(blocked)) == noted


@pytest.mark.parametrize("dont_write", [True, False])
def test_a_cached_module_s_bytecode_is_kept_and_used(tmp_path, monkeypatch, dont_write):
    """Compiled once, also where Python writes no bytecode
    (PYTHONDONTWRITEBYTECODE): later runs load the kept bytecode."""
    monkeypatch.setenv(cache.ENV, str(tmp_path / "cache"))
    monkeypatch.setattr(sys, "dont_write_bytecode", dont_write)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "p.ngc").write_text("#<a> = 2\nG0 X#<a>\nM2\n")
    module = cache.cached_module("p.ngc")
    pyc = Path(module).parent / "__pycache__"
    # a new entry's bytecode is written with it (tests/test_bytecode.py);
    # gone (an older entry, a removed file), the loader keeps what it compiles
    shutil.rmtree(pyc)
    monkeypatch.setattr(cache, "_COMPILED", {})  # (nor its code at hand)
    compiled = []
    original = cache.QuickLoader.source_to_code

    def counting(self, data, path, **kwargs):
        compiled.append(path)
        return original(self, data, path, **kwargs)

    monkeypatch.setattr(cache.QuickLoader, "source_to_code", counting)
    first = cache.load_cached(module)
    assert compiled == [module]
    assert [p.name.split(".")[0] for p in pyc.iterdir()] == [Path(module).stem]
    second = cache.load_cached(module)
    assert compiled == [module]  # the second load compiled nothing
    assert second.main.__code__.co_code == first.main.__code__.co_code
    assert second.__ngc__.files == ("p.ngc",)


def test_cache_never_pairs_one_compile_s_probes_with_another_s_module(
    tmp_path, monkeypatch
):
    # Two folders with the same program but different subroutine files share
    # a key. Compiled at the same time (campaign workers, parallel golden
    # checks), one's probes could be written last beside the other's module;
    # modules are named by their probes too, so a hit is always a pair.
    monkeypatch.setenv(cache.ENV, str(tmp_path / "cache"))
    metas = {}
    for folder, x in (("a", 1), ("b", 2)):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "p.ngc").write_text("o<ext> call\nM2\n")
        (tmp_path / folder / "ext.ngc").write_text(
            f"o<ext> sub\nG0 X{x}\no<ext> endsub\n"
        )
        monkeypatch.chdir(tmp_path / folder)
        cache.cached_module("p.ngc")
        (meta,) = (tmp_path / "cache").glob("*.json")
        metas[folder] = meta.read_text()
    # a compiled first, b's module written after a's, a's probes written last
    meta.write_text(metas["a"])
    monkeypatch.chdir(tmp_path / "a")
    module = cache.cached_module("p.ngc")
    assert "G0 X1" in Path(module).read_text()
    assert cache.module_probes(module)


#: Programs whose messages name their file, run under several names below:
#: an error in the program, and one in an external subroutine file it calls.
NAMED_PROGRAMS = {
    "error": "G0 X1\nG1 X[1/0]\nM2\n",
    "subroutine": "o<ext> call\nM2\n",
}


def _run_in_process(program: str):
    """``ngc2py run program`` in this process: (status, stdout, stderr)."""
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(["run", program])
    return status, out.getvalue(), err.getvalue()


def _counting_compiles(monkeypatch) -> list:
    """The paths ngc2py.cache compiles from now on."""
    compiled = []
    original = cache.compile_program

    def counting(path, *args, **kwargs):
        compiled.append(path)
        return original(path, *args, **kwargs)

    monkeypatch.setattr(cache, "compile_program", counting)
    return compiled


@pytest.mark.parametrize("kind", sorted(NAMED_PROGRAMS))
def test_a_program_under_another_name_reuses_its_entry(tmp_path, monkeypatch, kind):
    """The same program in another folder, by another name, absolute or
    relative: converted once, and every run names the file it was run by,
    as a run on an empty cache does (the source map's first file is set on
    loading; see ngc2py/cache.py)."""
    text = NAMED_PROGRAMS[kind]
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "ext.ngc").write_text(
            "o<ext> sub\nG1 X[2/0] F10\no<ext> endsub\nM2\n"
        )
    (tmp_path / "a" / "p.ngc").write_text(text)
    (tmp_path / "b" / "q.ngc").write_text(text)
    names = [
        ("a", "p.ngc"),
        ("b", "q.ngc"),
        ("a", str(tmp_path / "b" / "q.ngc")),
        ("b", str(tmp_path / "a" / "p.ngc")),
    ]
    alone = {}
    for k, (folder, name) in enumerate(names):
        monkeypatch.setenv(cache.ENV, str(tmp_path / ("alone%d" % k)))
        monkeypatch.chdir(tmp_path / folder)
        alone[folder, name] = _run_in_process(name)
    assert all(report[0] == 1 for report in alone.values())
    assert any(str(tmp_path) in report[2] for report in alone.values())

    monkeypatch.setenv(cache.ENV, str(tmp_path / "shared"))
    compiled = _counting_compiles(monkeypatch)
    for folder, name in names + names[::-1]:
        monkeypatch.chdir(tmp_path / folder)
        assert _run_in_process(name) == alone[folder, name], (folder, name)
    assert compiled == ["p.ngc"]


@pytest.mark.parametrize("rows", [False, True])
def test_an_error_in_a_program_of_chunks_names_no_call(tmp_path, rows):
    """A long program's main is cut into chunks (main_1, main_2...) that
    main calls: those calls are no O-calls, and an error (in a line of its
    own, or in a row of a table) names only its own line, as in a short
    program (a chunk's error had named main's last line as its call)."""
    # comments on the moves (a statement a line), then rows of one shape
    # (a table); the failing line among the statements, or in the table
    body = ["G1 X%d Y%d (pass %d)" % (k % 50, k % 7, k) for k in range(1200)]
    body += ["G1 X%d Y%d" % (k % 50, k % 7) for k in range(300)]
    body[1300 if rows else 700] = "G2 X0 Y0 R0.001"
    (tmp_path / "big.ngc").write_text("G21 G90 F100\n" + "\n".join(body) + "\nM2\n")
    ngc2py("convert", "big.ngc", cwd=tmp_path)
    module = (tmp_path / "big.py").read_text()
    assert "def main_2(" in module and "run_rows(" in module
    proc = ngc2py("run", "big.ngc", cwd=tmp_path)
    assert proc.returncode == 1
    assert proc.stderr.splitlines()[-3:] == [
        "Arc radius too small to reach end point",
        "G2 X0 Y0 R0.001",
        "  at big.ngc:%d" % (1302 if rows else 702),
    ]


def test_a_program_that_finds_itself_keeps_an_entry_of_its_own(tmp_path, monkeypatch):
    """A program that calls a subroutine by its own file's name finds itself
    as that file, which then shares the source map's first place with it:
    its entry is its name's alone, and a copy by another name beside it is
    compiled for itself (it finds the original, named apart)."""
    for name in ("p.ngc", "q.ngc"):
        (tmp_path / name).write_text("o<p> call\nM2\n")
    monkeypatch.chdir(tmp_path)
    alone = {}
    for name in ("p.ngc", "q.ngc"):
        monkeypatch.setenv(cache.ENV, str(tmp_path / ("alone-" + name)))
        alone[name] = _run_in_process(name)
    assert "called from q.ngc:1" in alone["q.ngc"][2]
    assert "at p.ngc:2" in alone["q.ngc"][2]
    monkeypatch.setenv(cache.ENV, str(tmp_path / "shared"))
    compiled = _counting_compiles(monkeypatch)
    for name in ("p.ngc", "q.ngc", "p.ngc", "q.ngc"):
        assert _run_in_process(name) == alone[name], name
    assert compiled == ["p.ngc", "q.ngc"]


def test_default_output_name():
    assert cli.default_output("dir/part.ngc") == "dir/part.py"


# --- against rs274 ----------------------------------------------------------


@pytest.mark.rs274
@pytest.mark.parametrize("mode", ["run", "convert"])
def test_external_subroutine_from_the_current_directory(mode, tmp_path):
    (tmp_path / "ext.ngc").write_text("o<ext> sub\nG0 X#1\nG0 Y[1/0]\no<ext> endsub\n")
    program = tmp_path / "main.ngc"
    program.write_text("G0 X1\no<ext> call [7]\nM2\n")
    assert (
        harness.compare(
            harness.run_rs274(program), harness.run_ngc2py(program, mode=mode)
        )
        == []
    )


def test_missing_program_message_is_rs274s(tmp_path):
    # measured: rs274 -g absent.ngc prints its 5 start-up calls, then the
    # message and an empty line after "executing", exit 1; run adds where.
    proc = ngc2py("run", "absent.ngc", cwd=tmp_path)
    assert proc.returncode == 1 and len(proc.stdout.splitlines()) == 5
    assert proc.stderr.splitlines() == [
        "executing",
        "Unable to open file <absent.ngc>",
        "",
        "  at absent.ngc",
    ]


@pytest.mark.rs274
@pytest.mark.parametrize("mode", ["run", "convert"])
def test_external_subroutine_on_the_ini_subroutine_path(mode, tmp_path):
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "far.ngc").write_text("o<far> sub\nG0 X#1\no<far> endsub\n")
    (tmp_path / "m.ini").write_text("[RS274NGC]\nSUBROUTINE_PATH = subs\n")
    program = tmp_path / "p.ngc"
    program.write_text("o<far> call [3]\nG0 Y1\nM2\n")
    args = ["-i", "m.ini"]
    expected = harness.run_rs274(program, args)
    assert harness.compare(expected, harness.run_ngc2py(program, args, mode=mode)) == []


def generated_namespace(text: str, name: str = "p.ngc") -> dict:
    from ngc2py.compiler import compile_text

    namespace: dict = {"__name__": "generated"}
    exec(compile(compile_text(text, name), name[:-4] + ".py", "exec"), namespace)
    return namespace


def test_an_escaping_python_exception_names_the_g_code_line(monkeypatch):
    import io

    from runtime.machine import Machine
    from runtime.main import run_cli

    def broken(self, line, *args, **words):
        raise ValueError("boom")

    # a general block, and plain moves (the fast paths)
    for method, program in (
        ("block", "G17 G0 X1\nM2\n"),
        ("move", "G0 X1 F10\nM2\n"),
        ("rapid", "G0 X1\nM2\n"),
        ("feed", "G1 X1\nM2\n"),
    ):
        with monkeypatch.context() as patch:
            patch.setattr(Machine, method, broken)
            ns = generated_namespace(program)
            out, err = io.StringIO(), io.StringIO()
            assert run_cli(ns["main"], ns["__ngc__"], [], out, err) == 1
        assert err.getvalue() == (
            "executing\ninternal error at p.ngc:1: ValueError: boom\n"
        ), method


def test_a_gcode_error_in_a_data_row_names_the_row(monkeypatch):
    import io

    from runtime.main import run_cli

    rows = "".join("G1 X%d Y1 F100\n" % i for i in range(12))
    ns = generated_namespace(rows + "G1 X1 Y2 Z3 G0\nM2\n")
    out, err = io.StringIO(), io.StringIO()
    assert run_cli(ns["main"], ns["__ngc__"], [], out, err) == 1
    lines = err.getvalue().splitlines()
    assert lines[2:] == ["G1 X1 Y2 Z3 G0", "  at p.ngc:13"]


def test_main_returns_the_status_and_uses_the_current_streams(tmp_path, monkeypatch):
    import io

    program = tmp_path / "t.ngc"
    program.write_text("G0 X1\nG1 X2\nM2\n")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("NGC2PY_CACHE", str(tmp_path / "cache"))
    expected = harness.run_rs274(program) if harness.rs274_path() else None
    for _ in range(2):  # nothing carries over from one run to the next
        out, err = io.StringIO(), io.StringIO()
        monkeypatch.setattr(sys, "stdout", out)
        monkeypatch.setattr(sys, "stderr", err)
        assert cli.main(["run", "t.ngc"]) == 1
        assert err.getvalue().splitlines()[:3] == [
            "executing",
            "Cannot do g1 with zero feed rate",
            "G1 X2",
        ]
        if expected is not None:
            assert out.getvalue().encode() == expected.stdout
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert cli.main(["run"]) == 1  # a usage error: rs274's status, no SystemExit


def test_ini_and_tool_table_complaints_are_printed_like_rs274s(tmp_path):
    (tmp_path / "t.ngc").write_text("G0 X1\nM2\n")
    (tmp_path / "bad.tbl").write_text("T1 P1 Z1 garbage\n")
    proc = ngc2py("run", "-t", "bad.tbl", "-i", "none.ini", "t.ngc", cwd=tmp_path)
    assert proc.stdout.startswith(
        "File: bad.tbl Unrecognized line skipped:\n    T1 P1 Z1 garbage\n    1 N....."
    )
    assert proc.stderr == "executing\nUnable to open inifile:none.ini:\n"


_RUN_WORDS = [
    "run",
    "p.ngc",
    "q.ngc",
    "out.txt",
    "-t",
    "-v",
    "-i",
    "-n",
    "-b",
    "-q",
    "--quiet",
    "--max-steps",
    "--max-steps=3",
    "--max",
    "--quie",
    "x.tbl",
    "0",
    "-1",
    "-",
    "--",
    "-h",
    "--help",
    "--bogus",
    "-bq",
    "-tx.tbl",
    "convert",
    "-o",
]


#: Words of the other commands the quick parser reads (ngc2py.cli._QUICK).
_OTHER_WORDS = _RUN_WORDS + [
    "stats",
    "flatten",
    "--json",
    "--jso",
    "--rapid-rate",
    "1000",
    "--output",
    "--output=x",
    "flat.ngc",
]


@given(
    hs.lists(hs.sampled_from(_RUN_WORDS), max_size=7).map(lambda words: ["run"] + words)
    | hs.lists(hs.sampled_from(_OTHER_WORDS), max_size=7).map(
        lambda words: ["stats"] + words
    )
    | hs.lists(hs.sampled_from(_OTHER_WORDS), max_size=7).map(
        lambda words: ["flatten"] + words
    )
    | hs.lists(hs.sampled_from(_OTHER_WORDS), max_size=8)
)
@settings(max_examples=2500, deadline=None)
def test_the_quick_parser_agrees_with_argparse(argv):
    """cli.quick_args (no argparse on the way of `ngc2py run`, `stats` or
    `flatten` with a program) must give argparse's answer whenever it gives
    one."""
    import contextlib
    import io

    quick = cli.quick_args(argv)
    if quick is None:
        return
    with (
        contextlib.redirect_stderr(io.StringIO()),
        contextlib.redirect_stdout(io.StringIO()),
    ):
        try:
            full = cli.parse_arguments(argv)
        except SystemExit:
            pytest.fail("argparse refuses %r, the quick parser took it" % (argv,))
    assert vars(quick) == vars(full)


def test_the_quick_parser_takes_the_usual_forms():
    from ngc2py import flatten
    from ngc2py import stats as stats_command

    args = cli.quick_args(["run", "p.ngc", "-t", "a.tbl", "-b", "-n", "0", "-q"])
    assert (args.program, args.tool_table, args.block_delete, args.continue_mode) == (
        "p.ngc",
        "a.tbl",
        True,
        "0",
    )
    assert cli.quick_args(["run", "-h"]) is None
    assert cli.quick_args(["run", "-"]) is None  # stdin: argparse's
    stats = cli.quick_args(["stats", "p.ngc", "--json", "-i", "m.ini"])
    assert (stats.program, stats.json, stats.ini) == ("p.ngc", True, "m.ini")
    assert stats.handler is stats_command.command
    flat = cli.quick_args(["flatten", "p.ngc", "-o", "flat.ngc", "-q"])
    assert (flat.output, flat.quiet, flat.handler) == ("flat.ngc", True, flatten.main)
    assert cli.quick_args(["flatten", "p.ngc"]).output == "-"
    # what only argparse reads: rates with units, a second name
    assert cli.quick_args(["stats", "p.ngc", "--rapid-rate", "120in"]) is None
    assert cli.quick_args(["flatten", "p.ngc", "q.ngc"]) is None


#: What a cached ``ngc2py run PROG`` must not import: each costs a run
#: milliseconds (argparse and its gettext, re and enum, about 8).
HEAVY = (
    "argparse",
    "gettext",
    "re",
    "enum",
    "typing",
    "json",
    "pathlib",
    "dataclasses",
)


def _fresh_run(tmp_path, arguments, watched, runs=2):
    """``ngc2py ARGUMENTS`` in a fresh interpreter (``runs`` times on one
    cache: the first compiles); the last run's process, its stderr ending
    with a line ``STATUS [the modules of watched it imported]``."""
    probe = (
        "import sys\nfrom ngc2py import cli\n"
        "code = cli.main(sys.argv[1].split('|'))\n"
        "print(code, sorted(set(sys.argv[2:]) & set(sys.modules)), file=sys.stderr)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(REPO), NGC2PY_CACHE=str(tmp_path / "cache"))
    for _ in range(runs):
        done = subprocess.run(
            [sys.executable, "-S", "-c", probe, "|".join(arguments), *watched],
            capture_output=True,
            text=True,
            env=env,
            cwd=tmp_path,
        )
    return done


@pytest.mark.parametrize("output", [None, "trace.txt"], ids=["stdout", "file"])
def test_a_cached_run_imports_nothing_heavy(tmp_path, output):
    # (with rs274's output file too: written atomically without tempfile,
    # its name read without getopt)
    program = tmp_path / "prog.ngc"
    program.write_text("G21 F100\nG1 X1 Y2\nM2\n")
    arguments = ["run", str(program)] + ([str(tmp_path / output)] if output else [])
    heavy = HEAVY + ("tempfile", "getopt", "shutil", "random", "importlib.util")
    done = _fresh_run(tmp_path, arguments, heavy)
    assert done.stderr.splitlines()[-1] == "0 []", done.stderr
    if output:
        assert "STRAIGHT_FEED(1.0000, 2.0000" in (tmp_path / output).read_text()


@pytest.mark.parametrize("command", [["stats"], ["flatten", "-o", "flat.ngc"]])
def test_cached_stats_and_flatten_import_nothing_heavy(tmp_path, command):
    # their command lines read without argparse (cli.quick_args), whose
    # help formatter brings shutil and its bz2 and lzma too
    program = tmp_path / "prog.ngc"
    program.write_text("G21 F100\nG1 X1 Y2\nG2 X3 Y2 R1\nM2\n")
    heavy = HEAVY + ("shutil", "locale", "bz2", "lzma", "tqdm")
    done = _fresh_run(tmp_path, [command[0], str(program)] + command[1:], heavy)
    assert done.stderr.splitlines()[-1] == "0 []", done.stderr


@pytest.mark.parametrize("command", ["convert", "run"])
def test_converting_imports_no_dataclasses_inspect_or_typing(tmp_path, command):
    # the compiler's classes are written out (ngc2py.records): dataclasses,
    # and inspect with it, cost a conversion 40-45 ms before any work; its
    # annotations are for the checker (typing: 5 ms more)
    program = tmp_path / "prog.ngc"
    program.write_text(
        "G21 F100\n#<_depth> = -1\no<cut> sub\n  G1 X#1 Z#<_depth>\no<cut> endsub\n"
        "o1 repeat [2]\n  o<cut> call [3]\no1 endrepeat\nM2\n"
    )
    arguments = [command, str(program)]
    if command == "convert":
        arguments += ["-o", str(tmp_path / "prog.py")]
    done = _fresh_run(tmp_path, arguments, ("dataclasses", "inspect", "typing"), runs=1)
    assert done.stderr.splitlines()[-1] == "0 []", done.stderr
    if command == "convert":
        assert "def o_cut(" in (tmp_path / "prog.py").read_text()
    else:
        assert "STRAIGHT_FEED(3.0000" in done.stdout


@given(
    hs.lists(
        hs.sampled_from(
            ["out", "--", "-", "-b", "-t", "x.tbl", "", "-x", "--max-steps=5"]
        ),
        max_size=4,
    )
)
def test_a_plain_output_file_is_read_as_getopt_reads_it(argv):
    import getopt

    from runtime.main import plain_output

    found = plain_output(argv)
    if found is None:
        return
    opts, rest = getopt.getopt(list(argv), "t:v:i:bn:", ["max-steps="])
    assert (opts, rest) == ([], [found])
