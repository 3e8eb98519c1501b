"""Block delete (rs274's ``-b``) on lines that carry O-words.

With block delete on, rs274 reads a line that starts with ``/`` as an empty
line (interp_read.cc read_text), so a ``/o1 endif``, ``/M98 P100`` or
``/M99`` is not there at all and the O-words around it pair differently.
The line-by-line form follows that as it runs; the nested form pairs
O-words when it is written (a Fanuc-style file, a subroutine file), so its
module is written for one setting (compiler.deletes_structure) and refuses
the other with a clear message. ``ngc2py run -b``, golden checks, stats,
flatten and the preview compile the right one.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

import ngc2py
from ngc2py.compiler import compile_text
import rs274 as harness

#: Fanuc-style files (an M98 and its O-line keep the nested form) whose
#: block-deleted lines carry O-words, M98 or M99
FANUC_STYLE = [
    "G0 X1\n/o1 if [0]\nG0 X2\no1 endif\nM98 P7777\nM2\nO7777\nG0 X3\nM99\n",
    "G0 X1\n/M98 P7777\nM2\nO7777\nG0 X3\nM99\n",
    "G0 X1\n/M98 P7777 L2\nM98 P7777\nM2\nO7777\nG0 X3\n/M99\nG0 X4\nM99\n",
    "/o900 sub\no900 return [1]\no900 endsub\nM98 P7777\nM2\no7777\nM99\n",
    "o1 do\n#1=[#1+1]\n/o1 while [#1 LT 2]\nG0 X#1\nM98 P7777\no1 while [#1 LT 3]\nM2\nO7777\nM99\n",
    "o1 if [1]\nG0 X1\n/o1 else\nG0 X2\no1 endif\nM98 P7777\nM2\nO7777\n/N5 M99\nM99\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("block_delete", [False, True], ids=["plain", "b"])
@pytest.mark.parametrize("text", FANUC_STYLE)
@pytest.mark.parametrize("mode", ["run", "convert"])
def test_block_deleted_o_words_in_a_fanuc_style_file(
    text, block_delete, mode, tmp_path
):
    """The same trace and error as rs274, with and without -b, through
    ``ngc2py run`` and a module converted (with -b where run with it).
    Before, the nested form ignored block delete on such lines. (The first
    shape was found by the language campaign, seed 23002.)"""
    program = tmp_path / "t.ngc"
    args = ["-b"] if block_delete else []
    expected = harness.run_rs274(program, args, text=text)
    actual = harness.run_ngc2py(program, args, text=text, mode=mode)
    assert harness.compare(expected, actual) == []


def _subroutine_file(tmp_path):
    (tmp_path / "sb.ngc").write_text(
        "o<sb> sub\nG0 X1\n/o1 if [0]\nG0 X2\no1 endif\nG0 X3\no<sb> endsub\nM2\n"
    )
    (tmp_path / "t.ini").write_text("[RS274NGC]\nSUBROUTINE_PATH = .\n")
    (tmp_path / "m.ngc").write_text("o<sb> call\nM2\n")
    return tmp_path / "m.ngc"


@pytest.mark.rs274
@pytest.mark.parametrize("block_delete", [False, True], ids=["plain", "b"])
def test_block_deleted_o_words_in_a_subroutine_file(block_delete, tmp_path):
    """A subroutine file is written in the nested form: its ``/o1 if``
    pairs with its endif without -b, and with -b that endif fails."""
    program = _subroutine_file(tmp_path)
    args = ["-i", "t.ini"] + (["-b"] if block_delete else [])
    expected = harness.run_rs274(program, args)
    actual = harness.run_ngc2py(program, args)
    assert harness.compare(expected, actual) == []
    assert (expected.rc == 1) == block_delete  # the two settings differ


def test_a_module_refuses_the_other_setting(tmp_path):
    """A module written for one setting says so when run with the other,
    on the command line (exit status 1, before running anything) and from
    Python (ValueError); run with its own setting it runs."""
    text = FANUC_STYLE[0]
    plain = tmp_path / "plain.py"
    plain.write_text(compile_text(text, "t.ngc"))
    with_b = tmp_path / "with_b.py"
    with_b.write_text(compile_text(text, "t.ngc", block_delete=True))
    for module, flags, refused in (
        (plain, ["-b"], "convert it with -b to run it with -b"),
        (with_b, [], "convert it without -b to run it without -b"),
    ):
        proc = subprocess.run(
            [sys.executable, str(module), *flags], capture_output=True, text=True
        )
        assert proc.returncode == 1
        assert proc.stdout == ""
        assert refused in proc.stderr and "t.ngc" in proc.stderr
    assert (
        subprocess.run([sys.executable, str(plain)], capture_output=True).returncode
        == 0
    )
    namespace: dict = {}
    exec(
        compile(plain.read_text(), str(plain), "exec"), namespace
    )  # noqa: S102 - our module
    with pytest.raises(ValueError, match="block delete off"):
        namespace["run"](block_delete=True)


def test_an_ordinary_module_runs_with_either_setting():
    """Block-deleted lines without O-words, or O-words the line-by-line form
    follows as it runs: the module says nothing of block delete."""
    for text in ("/G0 X1\nM2\n", "/o1 if [0]\nG0 X2\no1 endif\nM2\n"):
        assert "block_delete=" not in compile_text(text, "t.ngc")
        assert compile_text(text, "t.ngc") == compile_text(
            text, "t.ngc", block_delete=True
        )


class _Canon:
    """A preview canon answering get_block_delete as told; logs rapids."""

    def __init__(self, block_delete):
        self.block_delete = block_delete
        self.rapids = []

    def get_block_delete(self):
        return self.block_delete

    def straight_traverse(self, x, *rest):
        self.rapids.append(round(x * 25.4, 6))

    def get_external_length_units(self):
        return 0.03937007874016

    def get_external_angular_units(self):
        return 1.0

    def get_axis_mask(self):
        return 0x3F

    def check_abort(self):
        return False

    def get_tool(self, pocket):
        return (pocket,) + (0.0,) * 12 + (0,)

    def __getattr__(self, name):
        if name.startswith("__") or name == "parameter_file":
            raise AttributeError(name)
        return lambda *args: None


@pytest.mark.parametrize("block_delete", [False, True], ids=["plain", "b"])
def test_the_preview_asks_which_setting(block_delete, tmp_path):
    """``ngc2py.parse`` runs the module for the canon's answer: its moves
    are those of the toolpath with that setting."""
    program = tmp_path / "t.ngc"
    program.write_text(FANUC_STYLE[2])
    canon = _Canon(block_delete)
    ngc2py.parse(str(program), canon, "G21", "")
    moves = ngc2py.toolpath(str(program), block_delete=block_delete)
    assert canon.rapids == [round(x, 6) for x in moves.end[:, 0]]
    assert canon.rapids == ([1.0, 3.0, 4.0] if block_delete else [1.0, 3.0, 3.0, 3.0])


@pytest.mark.rs274
@pytest.mark.parametrize("times", [2, 3])
@pytest.mark.parametrize(
    "extra", [[], ["--max-steps=100000"]], ids=["quick", "argparse"]
)
@pytest.mark.parametrize(
    "text", [FANUC_STYLE[1], "G0 X1\n/G0 X2\n/o1 if [1]\nG0 X3\no1 endif\nM2\n"]
)
def test_each_b_flips_block_delete_as_rs274(text, times, extra, tmp_path):
    """rs274 flips block delete at each ``-b`` (``-b -b`` is off again);
    ``ngc2py run`` does too, whichever of its option parsers reads the
    line (a --max-steps=N sends it to argparse). Before, ``-b -b`` was on."""
    program = tmp_path / "t.ngc"
    args = ["-b"] * times
    expected = harness.run_rs274(program, args, text=text)
    actual = harness.run_ngc2py(program, args + extra, text=text)
    assert harness.compare(expected, actual) == []
    once = harness.run_rs274(program, ["-b"], text=text)
    assert (expected.stdout == once.stdout) == (times % 2 == 1)  # the flip is seen


def test_each_b_flips_block_delete_in_every_command():
    """stats, plot, flatten, golden and convert read -b as ``run`` does."""
    from ngc2py import cli

    for command in (["stats", "p.ngc"], ["plot", "p.ngc", "-o", "p.png"], ["flatten", "p.ngc"],
                    ["golden", "check", "p.ngc"], ["convert", "p.ngc"], ["run", "p.ngc", "--max-steps=5"]):  # fmt: skip
        for times in range(4):
            argv = command + ["-b"] * times
            args = cli._parser_for(argv).parse_args(argv)
            assert args.block_delete == (times % 2 == 1), argv
