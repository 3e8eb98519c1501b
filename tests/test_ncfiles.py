"""LinuxCNC's own sample programs through rs274 and ngc2py.

The samples are used in place from /usr/share/linuxcnc/ncfiles (installed by
linuxcnc-uspace; never copied into this repository). Each runs in a scratch
copy of that folder (so sibling subroutine files are found) with no options,
and ngc2py must match rs274: stdout byte for byte, exit status, error message.

Samples that use codes outside the current release are still run, and are
marked xfail (non-strict) with the codes that put them out of scope, computed
from the program text -- so the summary shows exactly how many are out of
scope and why, and an XPASS shows when one starts to work.
Without LinuxCNC installed, every test here is skipped with that reason.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import rs274 as harness

NCFILES = Path("/usr/share/linuxcnc/ncfiles")

#: Codes outside ngc2py's current scope, with the feature they belong to.
OUT_OF_SCOPE = {
    # M100-M199 are unknown to the stand-alone rs274 (ngc2py agrees), but a
    # sample using one only matches if both fail alike: keep them listed.
    **{f"M{n}": "user M codes / remaps" for n in range(100, 200)},
}

_COMMENT = re.compile(r"\([^)]*\)|;.*$", re.M)
_NAME = re.compile(r"<[^>\n]*>")  # #<named> parameters and o<names>
_WORD = re.compile(r"([gm])(\d+(?:\.\d+)?)")
_G10_L = re.compile(r"g10(?!\d)[^\n]*?l(\d+)")


def codes_used(text: str) -> set:
    """G/M codes written literally in a program (comments removed)."""
    body = _COMMENT.sub("", text.lower())
    body = _NAME.sub("", body)
    body = body.replace(" ", "").replace("\t", "")  # spaces may split numbers
    used = set()
    for letter, number in _WORD.findall(body):
        value = float(number)
        code = f"{letter.upper()}{value:g}"
        used.add(code)
    for l_value in _G10_L.findall(body):
        used.add(f"G10 L{int(l_value)}")
    return used


_CALL = re.compile(r"o<([^>\n]*)>\s*call", re.I)


def out_of_scope(path: Path, _seen=None) -> list:
    """Out-of-scope codes a program uses, including in the subroutine files it
    calls (found next to it, as rs274 finds them from the program's folder)."""
    seen = set() if _seen is None else _seen
    seen.add(path)
    text = path.read_text(errors="replace")
    used = {c for c in codes_used(text) if c in OUT_OF_SCOPE}
    for name in _CALL.findall(_COMMENT.sub("", text)):
        called = path.parent / (name.strip().lower().replace(" ", "") + ".ngc")
        if called.is_file() and called not in seen:
            used.update(out_of_scope(called, seen))
    return sorted(used)


def _samples():
    if not NCFILES.is_dir():
        return [pytest.param(None, id="no-ncfiles", marks=pytest.mark.skip(
            reason=f"{NCFILES} not present (LinuxCNC's linuxcnc-uspace package not installed)"))]
    params = []
    for path in sorted(NCFILES.glob("*.ngc")):
        marks = [pytest.mark.rs274]
        codes = out_of_scope(path)
        if codes:
            features = sorted({OUT_OF_SCOPE[c] for c in codes})
            marks.append(pytest.mark.xfail(
                reason=f"uses {', '.join(codes)} ({'; '.join(features)}): outside ngc2py's current scope",
                strict=False,
            ))
        params.append(pytest.param(path, id=path.stem, marks=marks))
    return params


@pytest.mark.parametrize("program", _samples())
def test_ncfile(program):
    expected = harness.run_rs274(program, timeout=60)
    if expected.timed_out or expected.rc < 0:
        pytest.skip(f"rs274 itself hangs or crashes on {program.name}: no reference behaviour")
    actual = harness.run_ngc2py(program, timeout=180)
    problems = harness.compare(expected, actual)
    if problems:
        pytest.fail(f"{program.name}:\n" + "\n".join(problems), pytrace=False)


def test_codes_used_reads_programs_like_rs274():
    """The scope check itself: comments ignored, spaces and decimals handled."""
    text = "G1 X1 (G81 in a comment)\ng 8 3 Z1 ; G41 here too\nG38.2 Z-1\nG10 L1 P1 Z1\nM101\n"
    used = codes_used(text)
    assert {"G1", "G83", "G38.2", "G10", "G10 L1", "M101"} <= used
    assert "G81" not in used and "G41" not in used


def test_scope_follows_called_subroutine_files(tmp_path):
    """An out-of-scope code inside a called subroutine file puts the caller out of scope."""
    (tmp_path / "main.ngc").write_text("o<user> call\nM2\n")
    (tmp_path / "user.ngc").write_text("o<user> sub\nM101\no<user> endsub\n")
    assert out_of_scope(tmp_path / "main.ngc") == ["M101"]
