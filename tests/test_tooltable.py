"""Tests for runtime.tooltable, with a comparison against rs274 (marked rs274)."""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import pytest

import rs274 as harness
from runtime.tooltable import (
    DEFAULT_TOOL_TABLE_PATH,
    default_tool_table,
    load_tool_table,
    scan_tool_line,
    parse_tool_table,
)


def test_all_fields():
    scan = scan_tool_line(
        "T1 P1 Z0.5 D0.25 X0.1 Y0.2 A1 B2 C3 U4 V5 W6 I10 J20 Q3 ;comment here\n"
    )
    entry = scan.entry
    assert scan.pocket_words == 1
    assert (entry.tool, entry.pocket, entry.diameter) == (1, 1, 0.25)
    assert entry.offsets == (0.1, 0.2, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
    assert entry.offset("z") == 0.5
    assert (entry.frontangle, entry.backangle, entry.orientation) == (10.0, 20.0, 3)
    assert entry.comment == "comment here"


@pytest.mark.parametrize("line", ["; only a comment\n", "\n", " ;x\n", "X"])
def test_ignored_lines(line):
    assert scan_tool_line(line) is None


@pytest.mark.parametrize(
    "line",
    [
        "T7 P9 Z-1.5 garbage\n",
        "T7 P9 Zabc\n",
        "T7 P9 Z 1.5\n",
        "T7 P9 K3\n",
        "T8 P2 Z1 \r\n",
    ],
)
def test_rejected_lines(line):
    assert scan_tool_line(line).entry is None


def test_sscanf_like_numbers():
    entry = scan_tool_line("T7.5 P9 Z1e1\n").entry
    assert (entry.tool, entry.offset("Z")) == (7, 10.0)
    scan = scan_tool_line("T7P9Z1.5\n")
    assert (scan.entry.tool, scan.pocket_words, scan.entry.offset("Z")) == (7, 0, 0.0)


def test_rejected_line_with_p_word_uses_up_an_index():
    table = parse_tool_table("T7 P1 Z2\nT8 P2 Z1 garbage\nT4 P7\n", "t.tbl")
    assert table.find(4) == 3


def test_indices_follow_lines_with_p_words():
    table = parse_tool_table("; header\n\nT7 P9 Z-1.5\nT1 P3 Z2\nT3 P1\n", "t.tbl")
    assert [table.find(tool) for tool in (7, 1, 3)] == [1, 2, 3]
    assert table.find(4) is None


def test_line_without_pocket_goes_to_spindle_and_is_found_last():
    table = parse_tool_table("T7 Z1\nT7 P1 Z2\n", "t.tbl")
    assert table.find(7) == 1
    assert table.lookup(7).offset("Z") == 2.0
    assert parse_tool_table("T7 Z1\n", "t.tbl").find(7) == 0


def test_tool_change_replaces_the_spindle_slot():
    table = parse_tool_table("T7 Z1\nT7 P1 Z2\nT9\tP2 Z1\n", "t.tbl")
    assert table.find(9) == 0
    assert table.with_spindle(table.find(7)).find(9) is None


def test_duplicates_first_wins():
    table = parse_tool_table("T7 P9 Z-1.5\nT7 P3 Z2\n", "t.tbl")
    assert table.lookup(7).offset("Z") == -1.5


def test_load_report_text():
    table = parse_tool_table("T7 P9 Z1 K3\nT8 P1\nT8 P2 Z1 K", "d.tbl")
    assert table.load_report == (
        "File: d.tbl Unrecognized line skipped:\n    T7 P9 Z1 K3\n"
        "File: d.tbl Unrecognized line skipped:\n    T8 P2 Z1 K"
    )


def test_missing_file_is_empty(tmp_path):
    table = load_tool_table(str(tmp_path / "none.tbl"))
    assert table.slots == {} and table.load_report == ""


def test_default_table_matches_shipped_file_when_present():
    path = Path(DEFAULT_TOOL_TABLE_PATH)
    if not path.exists():
        pytest.skip("LinuxCNC's sample tool table is not installed")
    shipped, builtin = load_tool_table(str(path)), default_tool_table()
    assert shipped.slots.keys() == builtin.slots.keys()
    for index, entry in builtin.slots.items():
        # Comments are left out of the built-in copy; all else must agree.
        assert shipped.slots[index]._replace(comment="") == entry


@pytest.mark.rs274
def test_default_table_matches_rs274():
    program = (
        "".join(f"T{t} M6\n(DEBUG, {_PARAMS})\n" for t in (1, 2, 3, 99999)) + "M2\n"
    )
    with tempfile.TemporaryDirectory() as folder:
        result = harness.run_rs274(Path(folder) / "prog.ngc", text=program)
    stdout = result.stdout.decode()
    table = default_tool_table()
    got = list(
        zip(
            map(int, _CHANGE.findall(stdout)),
            (m.strip() for m in _MESSAGE.findall(stdout)),
        )
    )
    assert got == [_expected_tool(table, t) for t in (1, 2, 3, 99999)]


# --------------------------------------------------------------------------
# Comparison with rs274
# --------------------------------------------------------------------------

_TABLES = [
    "T1 P1 Z0.5 D0.25 X0.1 Y0.2 A1 B2 C3 U4 V5 W6 I10 J20 Q3 ;comment here\nT7 P9 Z-1.5\n",
    "; header comment\n\nT7 P9 Z-1.5\n;another\nT1 P3 Z2\n",
    "T7 P9 Z-1.5\nT7 P3 Z2\nT5 P1 Z+1.5 D-2 X-.5\n",
    "T7 Z1\nT7 P1 Z2\nT9\tP2 Z1\n",
    "T7 P1 Z2\r\nT8 P2 Z1 \r\nT4 P7 Z1e1 Q12\n",
    "T7 P9 Z-1.5 garbage\nt6 p9 z1.5 d2\nT7.5 P2 Z3\nT2 P2 Z1 K",
    "T1 P1 P5 Z1\nT2 P Z2\nT3 P3 Z3\n  \nT5 Z5 ;no pocket\nT6 P1 Q-2 Iinf\n",
]

_PARAMS = " ".join(f"#{n}" for n in range(5400, 5414))
_CHANGE = re.compile(r"CHANGE_TOOL\((\d+)\)")
_MESSAGE = re.compile(r'MESSAGE\("(.*)"\)')


def _expected_tool(table, tool):
    index = table.find(tool)
    entry = table.slots[index]
    values = [
        entry.tool,
        *entry.offsets,
        entry.diameter,
        entry.frontangle,
        entry.backangle,
        entry.orientation,
    ]
    return index, " ".join(f"{float(v):.6f}" for v in values)


@pytest.mark.rs274
@pytest.mark.parametrize("text", _TABLES)
def test_tables_match_rs274(text):
    table = parse_tool_table(text, "tools.tbl")
    # One run per tool: an M6 changes what the spindle slot (index 0) holds.
    for tool in sorted({e.tool for e in table.slots.values() if e.tool > 0}):
        stdout, err = _run_with_table(text, f"T{tool} M6\n(DEBUG, {_PARAMS})\nM2\n")
        assert stdout.startswith(table.load_report)
        assert (
            err,
            int(_CHANGE.findall(stdout)[0]),
            _MESSAGE.findall(stdout)[0].strip(),
        ) == (
            "",
            *_expected_tool(table, tool),
        )
    stdout, err = _run_with_table(text, "T4242 M6\nM2\n")
    assert err == "Requested tool 4242 not found in the tool table"


def _run_with_table(table_text, program):
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "tools.tbl").write_text(table_text)
        (Path(folder) / "prog.ngc").write_text(program)
        result = harness.run_rs274(Path(folder) / "prog.ngc", ["-t", "tools.tbl"])
    return result.stdout.decode(), result.err


@pytest.mark.rs274
def test_tool_change_replaces_spindle_slot_like_rs274():
    text = "T7 Z1\nT7 P1 Z2\nT9\tP2 Z1\n"
    table = parse_tool_table(text, "tools.tbl")
    assert table.with_spindle(table.find(7)).find(9) is None
    _, err = _run_with_table(text, "T9 M6\nT7 M6\nT9 M6\nM2\n")
    assert err == "Requested tool 9 not found in the tool table"
