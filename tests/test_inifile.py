"""Tests for runtime.inifile, with comparisons against rs274 (marked rs274)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

import rs274 as harness
from runtime import arcs
from runtime.inifile import IniFile, load_ini, settings_from


def _rs274_with_ini(folder):
    """rs274 -i m.ini -g p.ngc in ``folder``, which is also its HOME."""
    return subprocess.run(
        [harness.rs274_path(), "-i", "m.ini", "-g", "p.ngc"],
        cwd=folder,
        capture_output=True,
        text=True,
        env={**os.environ, "HOME": str(folder)},
        timeout=60,
    )


def test_find_rules():
    ini = IniFile.parse(
        "# comment\n[EMCIO]\nTOOL_TABLE = a.tbl\n  ; note\n[RS274NGC]junk\n"
        "FEATURES = 4 # four\nFEATURESX = 9\nSUBROUTINE_PATH=a:\\\nb  \n[RS274NGC]\nLATE = 1\n"
    )
    assert ini.find("TOOL_TABLE", "EMCIO") == "a.tbl"
    assert ini.find("FEATURES", "RS274NGC") == "4 # four"
    assert ini.find("SUBROUTINE_PATH", "RS274NGC") == "a:b"
    assert ini.find("LATE", "RS274NGC") is None  # only the first [RS274NGC] counts
    assert ini.find("TOOL_TABLE", "emcio") is None
    assert ini.find("MISSING", "EMCIO") is None


def test_settings_and_validation():
    settings = settings_from(
        IniFile.parse(
            "[EMCIO]\nTOOL_CHANGE_QUILL_UP = 1\nTOOL_CHANGE_AT_G30 = yes\n"
            "[RS274NGC]\nFEATURES = 4 \nCENTER_ARC_RADIUS_TOLERANCE_MM = 0.01\n"
            "CENTER_ARC_RADIUS_TOLERANCE_INCH = 0.5\n[AXIS_4]\nWRAPPED_ROTARY = 1\n"
            "[AXIS_C]\nWRAPPED_ROTARY = 2\nLOCKING_INDEXER_JOINT = 3abc\n"
        )
    )
    assert settings.tool_change_quill_up and not settings.tool_change_at_g30
    assert settings.features == 4
    assert settings.center_arc_radius_tolerance_mm == 0.01
    assert (
        settings.center_arc_radius_tolerance_inch
        == arcs.CENTER_ARC_RADIUS_TOLERANCE_INCH
    )
    # rs274 2.9 reads [AXIS_A]..[AXIS_C], not the joints' [AXIS_3]..[AXIS_5]
    assert settings.wrapped_rotary == (False, False, True)
    assert settings.indexer_joints == (-1, -1, 3)
    assert (
        settings.stderr_report
        == "invalid [RS274NGC]CENTER_ARC_RADIUS_TOLERANCE_INCH in INI file\n\n"
    )
    assert settings.ini_value("EMCIO", "TOOL_CHANGE_AT_G30") == "yes"


def test_subroutine_path_is_relative_to_cwd(tmp_path, monkeypatch):
    (tmp_path / "subs").mkdir()
    monkeypatch.chdir(tmp_path)
    settings = settings_from(
        IniFile.parse("[RS274NGC]\nSUBROUTINE_PATH = missing::subs\n")
    )
    assert settings.subroutine_path == (str((tmp_path / "subs").resolve()),)


def test_unreadable_file(tmp_path):
    path = str(tmp_path / "none.ini")
    assert load_ini(path).stderr_report == f"Unable to open inifile:{path}:\n"


# --------------------------------------------------------------------------
# Comparison with rs274: the arc tolerance settings and their stderr report
# --------------------------------------------------------------------------

_ARC = "G21 F100\nG0 X0 Y0\nG2 X2.015 Y0 I1\nM2\n"


@pytest.mark.rs274
@pytest.mark.parametrize(
    "value",
    ["0.01", "0.02", " 0.02 ", "0.02 # c", "0.02x", "0.001", "0.0009", "0.5", ""],
)
def test_arc_tolerance_matches_rs274(tmp_path, value):
    ini_text = f"[RS274NGC]\nCENTER_ARC_RADIUS_TOLERANCE_MM = {value}\n"
    (tmp_path / "m.ini").write_text(ini_text)
    (tmp_path / "p.ngc").write_text(_ARC)
    done = _rs274_with_ini(tmp_path)
    settings = load_ini(str(tmp_path / "m.ini"))
    assert done.stderr.startswith("executing\n" + settings.stderr_report)
    try:
        arcs.arc_from_center(
            True,
            "XY",
            (0.0, 0.0),
            (2.015, 0.0),
            (1.0, 0.0),
            False,
            1,
            False,
            settings.center_arc_radius_tolerance_mm,
        )
        accepted = True
    except arcs.GCodeError:
        accepted = False
    assert ("ARC_FEED" in done.stdout) == accepted


@pytest.mark.rs274
@pytest.mark.parametrize(
    "content",
    [
        None,  # a folder
        b"[RS274NGC]\r\nCENTER_ARC_RADIUS_TOLERANCE_MM=abc\r\nORIENT_OFFSET=10\r\n",
        b"[RS274NGC]\nORIENT_OFFSET=10\r\r\n",
        bytes(range(256)) * 4,
    ],
    ids=["folder", "dos_line_ends", "lone_carriage_return", "binary"],
)
def test_odd_files_report_and_apply_like_rs274(tmp_path, content):
    """The stderr report, and whether ORIENT_OFFSET took effect (M19)."""
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")
    if content is None:
        (tmp_path / "m.ini").mkdir()
    else:
        (tmp_path / "m.ini").write_bytes(content)
    (tmp_path / "p.ngc").write_text("S100 M3\nM19 R1\nM2\n")
    done = _rs274_with_ini(tmp_path)
    settings = load_ini(str(tmp_path / "m.ini"))
    assert done.stderr == "executing\n" + settings.stderr_report
    assert settings.opened
    angle = 1.0 + settings.orient_offset
    assert f"ORIENT_SPINDLE(0, {angle:.4f}, 0)" in done.stdout


#: ini texts around LinuxCNC's 255-character line buffer (its IniFile reads
#: lines with fgets): ``{subs}`` is a SUBROUTINE_PATH value naming ./subs
_LONG_LINES = [
    "[RS274NGC]\nSUBROUTINE_PATH = {subs}:{pad}\n",  # cut after 255: the rest a line
    "[RS274NGC]\n{hashes}SUBROUTINE_PATH = {subs}\n",  # a comment, then the key
    "[RS274NGC]\n{hashes_254}SUBROUTINE_PATH = {subs}\n",  # one line: a comment
    "[RS274NGC]\nSUBROUTINE_PATH = {subs}:{pad_253}\\\nx\n",  # joined at the cut
    "[RS274NGC]\nSUBROUTINE_PATH = \\\n{subs}",  # joined, no newline at the end
    "[RS274NGC]\nSUBROUTINE_PATH = {subs}\\",  # a backslash at the very end
    "[RS274NGC]\nSUBROUTINE_PATH = \\\n",  # the file ends while joining
]


@pytest.mark.rs274
@pytest.mark.parametrize("template", _LONG_LINES)
def test_long_and_joined_lines_read_as_rs274_reads_them(tmp_path, template):
    """Whether rs274 finds the subroutine through SUBROUTINE_PATH, for lines
    longer than its buffer and backslash joins at its edges: ngc2py's
    answer, trace and message are rs274's. (Found by a sweep of real
    programs: a 282-character SUBROUTINE_PATH.)"""
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")
    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "foo.ngc").write_text("o<foo> sub\nG0 X1\no<foo> endsub\nM2\n")
    subs = str(tmp_path / "subs")
    pad = "/nowhere" * 40
    text = template.format(
        subs=subs,
        pad=pad,
        pad_253="/" * (253 - len("SUBROUTINE_PATH = %s:" % subs) - 1),
        hashes="#" * 255,
        hashes_254="#" * 254,
    )
    (tmp_path / "m.ini").write_text(text)
    (tmp_path / "p.ngc").write_text("o<foo> call\nM2\n")
    done = _rs274_with_ini(tmp_path)
    ours = subprocess.run(
        [sys.executable, "-m", "ngc2py", "run", "-i", "m.ini", "p.ngc"],
        cwd=tmp_path, capture_output=True, text=True,
        env={**os.environ, "HOME": str(tmp_path)}, timeout=120,
    )  # fmt: skip
    assert ours.stdout == done.stdout
    assert (ours.returncode, ours.stderr.split("\n")[:2]) == (
        done.returncode,
        done.stderr.split("\n")[:2],
    )
