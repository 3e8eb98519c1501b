"""The machine against rs274: blocks driven as generated code drives them.

Each case is a small G-code program of literal words only. A tiny test-only
reader (:func:`blocks_of`) turns each line into the ``Machine.block`` call a
compiled program would make; the machine's TraceCanon output and error are
then compared with what the installed rs274 prints for the same program.
Nothing expected is hard-coded: rs274 is asked every time.
"""

from __future__ import annotations

import io
import os
import re
import subprocess
from pathlib import Path
from typing import List, Optional, Tuple

import pytest

import rs274 as harness
from runtime.canon import RecordingCanon, TraceCanon
from runtime.codes import G0, G1, M2, g_code, m_code
from runtime.errors import GCodeError
from runtime.machine import Machine

_WORD = re.compile(r"([a-z@^])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
_NAMES = {"@": "polar_dist", "^": "polar_angle"}


def blocks_of(text: str) -> List[Tuple[int, tuple, Optional[str], dict]]:
    """(line, codes, N digits, words) for each line with something to do."""
    result = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = re.sub(r"\(.*?\)", "", raw).lower().replace(" ", "")
        n = None
        match = re.match(r"n(\d+)", line)
        if match:
            n, line = match.group(1), line[match.end() :]
        codes, words = [], {}
        for letter, value in _WORD.findall(line):
            if letter == "g":
                codes.append(g_code(float(value)))
            elif letter == "m":
                codes.append(m_code(float(value)))
            else:
                words[_NAMES.get(letter, letter)] = float(value)
        if codes or words or n is not None:
            result.append((number, tuple(codes), n, words))
    return result


def run_machine(text: str, tmp_path: Path, args=()) -> Tuple[str, str]:
    """Run ``text`` on a Machine with a TraceCanon: (stdout, error message)."""
    options = {}
    flags = list(args)
    while flags:
        flag, value = flags.pop(0), flags.pop(0)
        options[{"-t": "tool_table", "-v": "var_file", "-i": "ini"}[flag]] = str(
            tmp_path / value
        )
    out = io.StringIO()
    machine = Machine(TraceCanon(out), **options)

    def main(m: Machine) -> None:
        for number, codes, n, words in blocks_of(text):
            m.block(number, *codes, n=n, **words)
        m.end_of_file(False, False)

    try:
        machine.run(main)
    except GCodeError as error:
        return out.getvalue(), error.message
    return out.getvalue(), ""


def compare(text: str, tmp_path: Path, files=None, args=()) -> None:
    for name, content in (files or {}).items():
        (tmp_path / name).write_text(content)
    program = tmp_path / "prog.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, list(args))
    out, err = run_machine(text, tmp_path, args)
    assert err == expected.err
    assert out == expected.stdout.decode()


def need_rs274():
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")


PROGRAMS = {
    "basic": "G21 G90\nN10 G1 X1 Y2 F100\nG2 X2 Y2 I0.5\nT1 M6\nG43 H1\nM3 S1000\nG0 Z5\nM2\n",
    "inch": "G20\nG1 X1 F10\nG4 P1\nG21\nG1 X2\nM30\n",
    "n_column": "N0012 G1 X1 F1\nN1234567 G1 X2\nN5 G0 X0\nM2\n",
    "no_end": "G1 X1 F10\nG1 X3\n",
    "incremental": "G91 G0 X1 Y1\nX1\nG90 X0 Y0\nG91\nG91\nM2\n",
    "arcs_xy": "F10\nG2 X1 Y1 I0.5 J0.5\nG3 X0 Y0 R1\nG2 X0 Y0 I1 P2\nG3 X5 Y0 Z1 R-3\nM2\n",
    "arcs_xz": "G18 F10\nG2 X1 Z1 I0.5 K0.5\nG3 X0 Z0 R1 Y2\nG2 Z1 K0.5\nM2\n",
    "arcs_yz": "G19 F10\nG2 Y1 Z1 J0.5 K0.5\nG3 Y0 Z0 R1 X2\nM2\n",
    "arcs_inch": "G20 F10\nG2 X1 Y1 I0.5 J0.5\nG3 X0 Y0 R1\nM2\n",
    "abs_ijk": "G90.1 F10\nG0 X1\nG2 X1 Y2 I1 J1\nG91.1\nM2\n",
    "inverse_time": "G93\nG1 X3 Y4 F2\nG2 X4 Y5 R1 F1\nG94\nF5 G1 X0\nG95 S100 F1 G1 X1\nM2\n",
    "offsets": "G10 L2 P2 X1 Y2 Z3\nG55\nG0 X0 Y0\nG10 L20 P0 X5\nG0 Y1\nG54 G0 X0\nM2\n",
    "rotation": "G10 L2 P1 R30 X1\nG0 X1 Y1\nG10 L20 P1 X0 Y0\nG0 X1\nM2\n",
    "g92": "G0 X1 Y1\nG92 X0 Y0\nG0 X1\nG92.2\nG0 Y0\nG92.3\nG0 Z1\nG92.1\nG0 X0\nM2\n",
    "g52": "G0 X1\nG52 X1\nG0 X0\nG92 X2\nG0 X0\nM2\n",
    "g53": "G10 L2 P1 X1 Y2\nG54\nG53 G0 X0 Y0\nG53 G1 Z1 F1\nG0 X0\nM2\n",
    "home_rotated": "G10 L2 P1 R30 X1\nG0 X1 Y0\nG92 X2\nG0 X3 Y1\nG28.1\nG0 X0 Y0\nG28\nM2\n",
    "home": "G0 X1 Y2 Z3\nG28.1\nG0 X0 Y0 Z0\nG28\nG0 X5\nG28 X1\nG30.1\nG30 Y7\nM2\n",
    "tools": "T2\nM6\nG43\nG0 Z0\nG49\nT1 M6 G43 H2\nG0 X1\nM61 Q3\nG43\nG0 X0\nM2\n",
    "polar": "G0 @1 ^90\nG0 @2\nG0 ^45\nG91 G0 @1\nG0 ^10\nM2\n",
    "modes": "G17\nG18\nG19\nG17\nG61\nG61.1\nG64\nG64 P0.1 Q0.2\nG98\nG99\nG80\nG40\nM48\nM49\nM50 P1\nM51 P0\nM52 P1\nM53 P0\nM2\n",
    "spindle": "S100 M3\nM4\nM5\nM7\nM8\nM9\nM7\nM0\nM1\nM60\nG97\nG96 S10 D500\nM2\n",
    "end_resets": "G91 G18 G93 M7 M8 M49\nG10 L2 P2 X1\nG55\nM30\n",
    "stop_in_middle": "G0 X1\nM2\nG0 X2\n",
    "m19": "S500 M3\nM19 R90 Q2 P1\nM5\nM19\nM19 P2\nM2\n",
    "m66": "M66 P0 L0\nM66 E0\nM66 P1 L2 Q1\nM2\n",
    "lathe": "G7\nG0 X10\nG8\nG0 X10\nG7 X4\nG8 X4\nG8\nM2\n",
    "m6_without_t": "M6\nG43\nM2\n",
    "io": "M62 P1\nM63 P2\nM64 P3\nM65 P4\nM67 E1 Q2.5\nM68 E2 Q3\nM2\n",
    "forget_state": "M71\nG0 X1\nM2\n",
}

ERRORS = {
    "axes_no_motion": "X1\nM2\n",
    "two_axis_codes": "G1 G28 X1\nM2\n",
    "same_group": "G0 G1 X1\nM2\n",
    "same_m_group": "M3 M4\nM2\n",
    "too_many_m": "M3 M7 M48 M0 M6\nM2\n",
    "zero_feed": "G1 X1\nM2\n",
    "zero_feed_arc": "G2 X1 I1\nM2\n",
    "inverse_no_f": "G93 G1 X1\nM2\n",
    "arc_words": "G2 X1 F1\nM2\n",
    "arc_mixed": "G2 X1 R1 I1 F1\nM2\n",
    "arc_k_in_xy": "G2 X1 K1 F1\nM2\n",
    "arc_r_no_end": "G18 G2 R1 F1\nM2\n",
    "arc_radius": "G2 X1 Y0 I0.3 F1\nM2\n",
    "arc_abs_missing": "G90.1 G2 X1 I1 F1\nM2\n",
    "arc_p": "G2 X1 I1 F1 P0\nM2\n",
    "g4_no_p": "G4\nM2\n",
    "g53_g2": "G53 G2 X1 F1\nM2\n",
    "g53_incremental": "G91 G53 G0 X1\nM2\n",
    "g92_no_axes": "G92\nM2\n",
    "g80_axes": "G80 X1\nM2\n",
    "i_word": "I1\nM2\n",
    "p_word": "P1\nM2\n",
    "q_word": "Q1\nM2\n",
    "r_word": "R1\nM2\n",
    "h_word": "H1\nM2\n",
    "d_word": "D1\nM2\n",
    "l_word": "L1\nM2\n",
    "e_word": "E1\nM2\n",
    "negative_f": "F-1\nM2\n",
    "negative_s": "S-1\nM2\n",
    "negative_t": "T-1\nM2\n",
    "unknown_tool": "T99\nM2\n",
    "unknown_h": "G43 H99\nM2\n",
    "m61_no_q": "M61\nM2\n",
    "g10_l": "G10 L3\nM2\n",
    "g10_p": "G10 L2 P10\nM2\n",
    "g10_r_l20": "G10 L20 P1 R1\nM2\n",
    "polar_x": "G0 @1 X1\nM2\n",
    "polar_origin": "G0 @1\nM2\n",
    "polar_incremental": "G91 G0 ^1\nM2\n",
    "polar_g92": "G92 @1\nM2\n",
    "polar_g53": "G53 G0 @1\nM2\n",
    "g4_with_arc": "G4 G2 X1 I1 P1 F1\nM2\n",
    "user_m": "M100\nM2\n",
    "user_m_with_p": "M101 P1 Q2\nM2\n",
    "m66_both": "M66 P1 E1\nM2\n",
    "m66_timeout": "M66 L1 P1\nM2\n",
    "m66_analog_wait": "M66 E1 L1 Q1\nM2\n",
    "m19_q": "M19 Q0 R1\nM2\n",
    "m19_p": "M19 P2.5\nM2\n",
    "m19_r": "M19 R400\nM2\n",
    "error_after_moves": "G0 X1\nG1 X2\nM2\n",
    # Out-of-scope codes: rs274's checks fail before "not supported" would.
    "spline_pq": "F100\nG5 X1 Y2\nM2\n",
    "spline_ij": "F100\nG5 X1 Y2 I1 P1 Q1\nM2\n",
    "spline_z": "F100\nG5 X1 Z2 I1 J1 P1 Q1\nM2\n",
    "spline_plane": "F100 G18\nG5 X1 Y2 P1 Q1\nM2\n",
    "spline_feed": "G5 X1 Y2 P1 Q1\nM2\n",
    "spline_inverse": "G93\nG5 X1 Y2 P1 Q1\nM2\n",
    "quadratic_ij": "F100\nG5.1 X1 Y2 I1\nM2\n",
    "nurbs_xy": "F100\nG5.2 X1\nM2\n",
    "nurbs_feed": "G5.2 X1 Y1 P1\nM2\n",
    "nurbs_end": "S100 M3 G91 G5.3\nM2\n",
    "g33_k": "S100 M3 G33 Z-1\nM2\n",
    "g33_f": "G33 Z-1 K1 F1\nM2\n",
    "g33_spindle": "G33 Z-1 K1\nM2\n",
    "g33_1_spindle": "G33.1 Z-1 K1 I1 E1\nM2\n",
    "probe_feed": "G38.2 Z-1\nM2\n",
    "probe_per_rev": "G95 S0\nG38.3 Z-1 F1\nM2\n",
    "probe_close": "F1\nG91 G38.2 Z0 A0\nM2\n",
    "g76_p": "S100 G76 Z-1\nM2\n",
    "g76_ijk": "S100 M3\nG76 P1 Z-1 J1 K2\nM2\n",
    "g76_spindle": "G76 P1 Z-1 I1 J1 K2 E1\nM2\n",
    "g76_rotary": "S100 M3\nG76 P1 Z-1 I0 J1 K2 A1\nM2\n",
    "g76_i": "S100 M3\nG76 P1 Z-1 I0 J1 K2\nM2\n",
    "g76_j": "S100 M3\nG76 P1 Z-1 I1 J0 K2\nM2\n",
    "g76_k": "S100 M3\nG76 P1 Z-1 I1 J1 K1\nM2\n",
    "cycle_r": "F1\nG81 Z-1\nM2\n",
    "cycle_feed": "G81 Z-1 R1\nM2\n",
    "cycle_inverse": "G93\nG81 Z-1 R1 F1\nM2\n",
    "cycle_l0": "F1\nG81 Z-1 R1 L0\nM2\n",
    "cycle_no_z": "F1\nG82 R1 X1\nM2\n",
    "cycle_r_below": "F1 G91\nG83 Z1 R1\nM2\n",
    "cycle_xz": "F1 G18\nG85 Y2 R1\nM2\n",
    "cycle_yz": "F1 G19\nG89 Y1 R1\nM2\n",
    "cycle_rotary": "F1\nG73 Z-1 R1 A1 Q1\nM2\n",
    "cycle_uv_plane": "F1 G17.1\nG81 Z-1 R1\nM2\n",
    "cycle_uw_plane": "F1 G18.1\nG74 X1 R1\nM2\n",
    "lathe_q": "G71 Z-1\nM2\n",
    "lathe_plane": "G72.2 Q1\nM2\n",
    "lathe_p": "G71 P1 Q2\nM2\n",
    "lathe_j": "G18\nG71.1 X1 Z1 Q1 J1\nM2\n",
    "lathe_e": "G18\nG72 X1 Z1 Q1 E1\nM2\n",
    "comp_plane": "G19\nG41\nM2\n",
    "comp_d": "S100 G42 D1.5\nM2\n",
    "comp_negative_d": "G41 D-1\nM2\n",
    "comp_tool": "G41 D9\nM2\n",
    "comp_no_d": "G42.1\nM2\n",
    "comp_l": "G41.1 D1 L1\nM2\n",
    "restore_nothing": "M64 P1 M72\nM2\n",
}


@pytest.mark.rs274
@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_program_matches_rs274(name, tmp_path):
    need_rs274()
    compare(PROGRAMS[name], tmp_path)


@pytest.mark.rs274
@pytest.mark.parametrize("name", sorted(ERRORS))
def test_error_matches_rs274(name, tmp_path):
    need_rs274()
    compare(ERRORS[name], tmp_path)


TOOL_TABLE = "T5 P3 Z1.5 D0.25 ;five\nT7 P9 Z2 X0.1\n"


@pytest.mark.rs274
@pytest.mark.parametrize(
    "text",
    [
        "T7 M6\nG43\nT5\nM6\nG43 H7\nM61 Q5\nG43\nT0 M6\nG43\nG49\nM2\n",
        "G43 H7\nG0 Z0\nG49\nG0 X1\nT5 M6\nG0 X2\nG20\nG0 X3\nG43 H7\nG0 X4\nG21\nG0 X5\nM2\n",
        "G20 G43 H7\nG0 Z0\nG21\nG49\nG0 X1\nG43 H7\nG0 Z0\nG49\nT5 M6\nG0 X2\nM2\n",
        "G43.1 Z1 X2\nG0 X0\nG43.2 H5\nG0 Y0\nG49\nG0 Z0\nM2\n",
        "G10 L1 P5 Z1.5 R0.25 Q3\nT5 M6\nG10 L1 P5 X0.5 I10 J20\nG43\nG0 Z1\n"
        "G10 L10 P7 Z0\nG10 L11 P5 Z2\nG43\nG0 X0\nG10 L1 P5\nM2\n",
        "G10 L2 P1 R30\nG92 X1 Y2\nG0 X3 Y4 Z5\nG10 L10 P7 X1\nG10 L10 P7 Y1\n"
        "G10 L10 P5 X1 Y2\nG10 L11 P5 Y-1\nG10 L1 P7 Q-1 R1\nM2\n",
        "G10 L1 P7 Q1.5 Z1\nM2\n",
        "G10 L1 P7 Q10 Z1\nM2\n",
        "G10 L0 P1\nG10 L0\nT7 M6 G43\nM2\n",
    ],
)
def test_tool_table_matches_rs274(text, tmp_path):
    need_rs274()
    compare(text, tmp_path, {"t.tbl": TOOL_TABLE}, ["-t", "t.tbl"])


VAR_FILE = (
    "5161\t3\n5162\t1\n5210\t1\n5211\t0.5\n5213\t7\n5220\t2\n"
    "5241\t1.5\n5242\t2.5\n5250\t30\n"
)


@pytest.mark.rs274
def test_start_sequence_follows_var_file(tmp_path):
    need_rs274()
    compare(
        "G0 X1\nG28\nG55\nG54\nG92.3\nM2\n",
        tmp_path,
        {"p.var": VAR_FILE},
        ["-v", "p.var"],
    )


INI_FILE = (
    "[EMCIO]\nTOOL_CHANGE_QUILL_UP = 1\nTOOL_CHANGE_AT_G30 = 1\nTOOL_CHANGE_WITH_SPINDLE_ON = 1\n"
    "[RS274NGC]\nORIENT_OFFSET = 10\nCENTER_ARC_RADIUS_TOLERANCE_MM = 0.001\n"
)


@pytest.mark.rs274
@pytest.mark.parametrize(
    "text",
    [
        "G10 L2 P1 X1 Z2\nG0 X5 Y5 Z5\nG30.1\nG0 X0\nS10 M3\nT1 M6\nM19 R5\nM2\n",
        "F1 G2 X2 Y0 I1.001\nM2\n",
    ],
)
def test_ini_settings_match_rs274(text, tmp_path):
    need_rs274()
    compare(text, tmp_path, {"m.ini": INI_FILE}, ["-i", "m.ini"])


@pytest.mark.rs274
def test_failing_to_open_prints_only_the_initialisation(tmp_path):
    # rs274 initialises, then stops at the open: no ON_RESET at all.
    need_rs274()
    (tmp_path / "home").mkdir()
    expected = subprocess.run(
        [harness.rs274_path(), "-g", "missing.ngc"],
        cwd=tmp_path,
        env={**os.environ, "HOME": str(tmp_path / "home")},
        capture_output=True,
        text=True,
    )
    out = io.StringIO()
    with pytest.raises(GCodeError) as error:
        Machine(TraceCanon(out)).fail_open("Unable to open file <missing.ngc>")
    assert error.value.message == harness.first_error_line(expected.stderr)
    assert out.getvalue() == expected.stdout


# --------------------------------------------------------------------------
# Whole programs: ngc2py's generated code on the machine against rs274
# --------------------------------------------------------------------------

POCKET_TABLE = "T1 P5 D1\nT2 P9 D2\nT7 P3 Z1\n"
SHOW_TOOLS = (
    "(debug, cp=#<_current_pocket> sp=#<_selected_pocket>"
    " ct=#<_current_tool> st=#<_selected_tool>)\n"
)

WHOLE_PROGRAMS = {
    "line_numbers": "(debug, #<_line>)\n#1 = #<_line>\nG0 X#<_line> Y#1\n"
    "o1 if [#<_line> EQ 4]\n(debug, #<_line>)\no1 endif\nM2\n",
    "line_in_sub": "o<s> sub\n#<l> = #<_line>\n(debug, #<l> #<_line>)\no<s> endsub\n"
    "G0 X1\no<s> call\nM2\n",
    "pockets": SHOW_TOOLS
    + "T2\n"
    + SHOW_TOOLS
    + "M6\n"
    + SHOW_TOOLS
    + "T7 M6\n"
    + SHOW_TOOLS
    + "M61 Q1\n"
    + SHOW_TOOLS
    + "T0 M6\n"
    + SHOW_TOOLS
    + "M2\n",
    "tool_offset_flag": "G43 H0\n(debug, #<_tool_offset>)\nG43.1 Z1\n"
    "(debug, #<_tool_offset>)\nG43.1 Z0\n(debug, #<_tool_offset>)\nM2\n",
    "m98_words_checked_not_run": "M98 P100 G1 X7 F1 M3 T1\nM98 P100 L0\n#1 = 5\n"
    "M98 P[50+50] L[2]\n(debug, #1 #<_value> #<_call_level>)\nG0 X5\nM2\n"
    "O100\n#1 = [#1 + 1]\n(debug, #<_call_level>)\nG91 G0 X1\nM99\n",
    "m98_q_word": "M98 P100 Q1\nM2\nO100\nM99\n",
    # an else after its if's endif skips ahead where an arm has run, reading
    # the M98 lines on the way, to the next line of its label or the end of
    # the file (language campaign, seed 33005; the Fanuc sub keeps the
    # nested form)
    "m98_read_by_a_stray_else": "o104 if [1]\no104 endif\no104 else\n"
    "M98 P1 X[1/#3]\no104 endif\nM2\nO7777\nM99\n",
    "m98_read_by_a_stray_else_to_the_end": "o104 if [0]\no104 endif\n"
    "N5444 o104 else\nM98 P1 X[1/#3]\nO7777\n",
    # the file's last line, an M98 line, is read before the end of the
    # file fails (language campaign, seed 33006)
    "m98_read_as_the_last_line_skipped": "o102 repeat [0]\nM98 P[#1 + 0.5]\n",
    # a definition read to the end of the file, its M98 line inside an if
    # that failed as a whole (a label the do around it holds): rs274 reads
    # the line all the same (language campaign, seed 33006)
    "m98_read_in_a_failed_construct_of_a_definition": "o<s0> sub\no101 do\n"
    "o103 while [#<stray> LT 1]\no101 if [0]\nM98 P[#1 + 0.5]\n",
    "m98_after_a_definition_not_read_with_it": "#1 = 0.5\no<s> sub\nG0 X1\n"
    "o<s> endsub\nG0 X2\no1 if [0]\nM98 P[#1]\no1 endif\nM2\nO7777\nM99\n",
    # a loop never closed that ends by skipping reads to the end of the
    # file: the M98 lines after what holds it too
    "m98_read_past_a_repeat_never_closed": "o1 if [1]\no2 repeat [0]\nG0 X1\n"
    "o1 endif\nM98 P[#1 + 0.5]\nM2\nO7777\nM99\n",
    "m98_read_past_a_while_never_closed": "o1 if [1]\no2 while [0]\nG0 X1\n"
    "o1 endif\nG0 X2\nM98 P[#1 + 0.5]\nM2\n",
    "m98_read_by_a_stray_else_not_failing": "o104 if [1]\no104 endif\n"
    "o104 else\nM98 P1 X[1/#1]\no104 endif\n#1 = 2\no104 if [0]\no104 endif\n"
    "o104 else\nM98 P1 X[1/#1]\n(debug, reached)\no104 endif\nM2\nO1\nM99\n",
    "call_before_definition": "G21\no<a> call\no<a> call\no<a> sub\nG0 X1\n"
    "o<a> endsub\nM2\n",
    "call_from_sub_before_definition": "o<b> sub\no<a> call\no<b> endsub\n"
    "o<b> call\nG0 X2\no<a> sub\nG0 X1\no<a> endsub\nM2\n",
    "redefinition": "o<s> sub\nG0 X1\no<s> endsub\no<s> call\no<s> sub\nG0 X2\n"
    "o<s> endsub\nM2\n",
    "late_definition_not_called_early": "G0 X1\nM2\no<a> sub\no<a> endsub\n",
    "missing_sub_in_closed_file": "%\nG21\no<nope> call\nG0 X1\n%\n",
}


#: The closing ``while`` of a do-loop left one call level down by an
#: ``M98 .. L0`` in its body: rs274 does not find the do's label in that
#: frame and reads the line as a new while-loop (interp_o_word.cc,
#: O_while) -- true, it goes on past it, never looping; false, it skips
#: ahead for the label (none: the file ends). Found by the valid_feed
#: campaign (seed 28002). Each program ends with a Fanuc subroutine.
STRANDED_DO = {
    "true": "#1 = 0\no103 do\n#1 = [#1 + 1]\n(print, a #1)\nM98 P9001 L0\n"
    "o103 while [#1 LT 4]\n(print, after)\nG0 X1\nM2\n",
    "false": "#1 = 0\no103 do\n#1 = [#1 + 1]\n(print, a #1)\nM98 P9001 L0\n"
    "o103 while [#1 LT 1]\n(print, after)\nG0 X1\nM2\n",
    # false, the skip stops at a line it cannot read
    "false_unreadable": "#1 = 0\no103 do\n#1 = [#1 + 1]\nM98 P9001 L0\n"
    "o103 while [#1 GT 3]\n(print, after)\no104 if [1]\no104 endif\n"
    "G0 X[1/0]\nM2\n",
    # in an o-sub: the frame marks are the call's
    "in_sub": "o<s> sub\n#<i> = 0\no103 do\n#<i> = [#<i> + 1]\n(print, s #<i>)\n"
    "M98 P9001 L0\no103 while [#<i> LT 3]\n(print, after)\no<s> endsub\n"
    "o<s> call\n(print, back)\nM2\n",
    # an M99 returns from the frame first: a do-loop as ever
    "m99_first": "#1 = 0\no103 do\n#1 = [#1 + 1]\n(print, a #1)\nM98 P9001 L0\n"
    "M99\no103 while [#1 LT 3]\n(print, after)\nM2\n",
    # L known at run time: 1 the first time round, 0 the second
    "computed_l": "#1 = 0\n#2 = 1\no103 do\n#1 = [#1 + 1]\n(print, a #1)\n"
    "M98 P9001 L[#2]\n#2 = 0\no103 while [#1 LT 4]\n(print, after)\nM2\n",
    # an M98 L0 in an if inside the loop, on the second round
    "in_if": "#1 = 0\no103 do\n#1 = [#1 + 1]\no105 if [#1 EQ 2]\nM98 P9001 L0\n"
    "o105 endif\n(print, a #1)\no103 while [#1 LT 4]\n(print, after)\nM2\n",
    # nested do-loops: the inner's while read anew, then the outer's
    "nested": "#1 = 0\no1 do\no2 do\n#1 = [#1 + 1]\n(print, a #1)\n"
    "M98 P9001 L0\no2 while [#1 LT 3]\n(print, mid)\no1 while [#1 LT 5]\n"
    "(print, after)\nM2\n",
    # the condition read fails first
    "condition_fails": "#1 = 0\no103 do\n#1 = [#1 + 1]\nM98 P9001 L0\n"
    "o103 while [1/0]\nM2\n",
}


@pytest.mark.rs274
@pytest.mark.parametrize("name", sorted(STRANDED_DO))
def test_do_loop_left_by_m98_l0_reads_its_while_anew(name, tmp_path):
    need_rs274()
    program = tmp_path / "prog.ngc"
    program.write_text(STRANDED_DO[name] + "O9001\nG91 G0 X1\nG90\nM99\n")
    expected = harness.run_rs274(program, [])
    actual = harness.run_ngc2py(program, [])
    assert (actual.stdout, actual.err, actual.rc) == (
        expected.stdout,
        expected.err,
        expected.rc,
    )


@pytest.mark.rs274
@pytest.mark.parametrize("name", sorted(WHOLE_PROGRAMS))
def test_whole_program_matches_rs274(name, tmp_path):
    need_rs274()
    (tmp_path / "t.tbl").write_text(POCKET_TABLE)
    program = tmp_path / "prog.ngc"
    program.write_text(WHOLE_PROGRAMS[name])
    expected = harness.run_rs274(program, ["-t", "t.tbl"])
    actual = harness.run_ngc2py(program, ["-t", "t.tbl"])
    assert (actual.stdout, actual.err, actual.rc) == (
        expected.stdout,
        expected.err,
        expected.rc,
    )


@pytest.mark.rs274
@pytest.mark.parametrize("var_file", ["missing.var", "no/such/folder/p.var"])
def test_var_file_that_does_not_exist_matches_rs274(var_file, tmp_path):
    # rs274 reports the missing file on stderr (it cannot link it to its
    # backup) and runs; in a folder that does not exist it says nothing.
    need_rs274()
    program = tmp_path / "prog.ngc"
    program.write_text("G0 X#5161\n#5161 = 3\nM2\n")
    expected = harness.run_rs274(program, ["-v", var_file])
    actual = harness.run_ngc2py(program, ["-v", var_file])
    assert (actual.stdout, actual.stderr, actual.rc) == (
        expected.stdout,
        expected.stderr,
        expected.rc,
    )


# --------------------------------------------------------------------------
# Behaviour that needs no rs274
# --------------------------------------------------------------------------


def recorded(*blocks) -> List[Tuple[str, tuple]]:
    canon = RecordingCanon()
    machine = Machine(canon)

    def main(m):
        for codes, words in blocks:
            m.block(1, *codes, **words)

    machine.run(main)
    return canon.calls


def test_run_brackets_program_with_start_and_reset_calls():
    calls = recorded(((G0,), {"x": 1.0}), ((M2,), {}))
    names = [name for name, _ in calls]
    assert names[:6] == [
        "use_length_units",
        "set_g5x_offset",
        "set_g92_offset",
        "set_xy_rotation",
        "set_feed_reference",
        "on_reset",
    ]
    assert names[-3:] == ["program_end", "on_reset", "on_reset"]
    assert ("straight_traverse", (1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)) in calls


def test_error_still_closes_with_two_resets():
    canon = RecordingCanon()
    machine = Machine(canon)
    with pytest.raises(GCodeError, match="Cannot do g1 with zero feed rate"):
        machine.run(lambda m: m.block(3, G1, x=1.0))
    assert [name for name, _ in canon.calls[-2:]] == ["on_reset", "on_reset"]
    assert machine.line == 3


def test_nothing_runs_after_program_end():
    calls = recorded(((M2,), {}), ((G0,), {"x": 5.0}))
    assert not any(name == "straight_traverse" for name, _ in calls)


def test_position_parameters_follow_moves():
    machine = Machine(RecordingCanon())
    machine.run(lambda m: m.block(1, G0, x=1.5, z=-2.0))
    assert machine.params[5420] == 1.5
    assert machine.params[5422] == -2.0
    assert machine.globals["_x"] == 1.5


def test_call_gives_fresh_arguments_and_restores_them():
    machine = Machine(RecordingCanon())
    seen = []

    def sub(m):
        seen.append((m.params[1], m.params[2], m.params[3], m.globals["_call_level"]))
        return 7.0

    def main(m):
        m.params[1] = 9.0
        m.call(sub, 4.0, 5.0)
        seen.append((m.params[1], m.globals["_value"], m.globals["_value_returned"]))

    machine.run(main)
    assert seen == [(4.0, 5.0, 0.0, 1.0), (9.0, 7.0, 1.0)]


def test_call_named_needs_a_definition():
    machine = Machine(RecordingCanon())
    with pytest.raises(GCodeError, match="Failed to find sub 'Ounknown' before EOF"):
        machine.call_named("unknown")


@pytest.mark.rs274
def test_lathe_tool_needs_g18_for_compensation_like_rs274(tmp_path):
    need_rs274()
    table = {"tools.tbl": "T1 P1 D6 Z25\nT3 P3 D3 Z1 Q2\n"}
    compare("G41 D3\nM2\n", tmp_path, files=table, args=("-t", "tools.tbl"))


_ABS_NAMES = ["_abs_" + axis for axis in "xyzabc"]


@pytest.mark.rs274
@pytest.mark.parametrize(
    "text",
    [
        "G10 L2 P1 X100\nG0 X0\n",
        "G10 L2 P1 X10 Y20 Z30 A5 R30\nG92 X1 Y2 A1\nG0 X3 Y1 Z3 A4\n",
        "G10 L1 P1 X2 Z1 A5\nT1 M6 G43\nG0 X1 A1\nG43.1 Z2\nG92 Z1\nG20\n",
    ],
)
def test_abs_position_parameters_match_rs274(text, tmp_path):
    """#<_abs_x>..#<_abs_c>: the machine position (offsets, rotation and tool
    length included), read as rs274 prints them; there is no _abs_u/v/w."""
    need_rs274()
    (tmp_path / "tools.tbl").write_text("T1 P1 D6 Z25\n")
    probe = "(DEBUG," + " ".join(f"#<{name}>" for name in _ABS_NAMES + ["_abs_u"])
    program = tmp_path / "prog.ngc"
    program.write_text(text + probe + ")\nM2\n")
    expected = harness.run_rs274(program, ["-t", "tools.tbl"])
    machine = Machine(RecordingCanon(), tool_table=str(tmp_path / "tools.tbl"))
    values = []

    def main(m: Machine) -> None:
        for number, codes, n, words in blocks_of(text):
            m.block(number, *codes, n=n, **words)
        values.extend(f"{m.predefined(name):.6f}" for name in _ABS_NAMES)
        assert m.predefined("_abs_u") is None

    machine.run(main)
    message = re.search(r'MESSAGE\("(.*)"\)', expected.stdout.decode()).group(1)
    assert message == " ".join(values + ["######"])


def test_other_spindles_fail_where_rs274_reads_them():
    # The stand-alone rs274 has one spindle: $2 fails at the S step, before
    # M3 (golden/spindle/dollar_*.ngc pin down every step's message).
    machine = Machine(RecordingCanon())
    with pytest.raises(
        GCodeError, match=r"Invalid spindle \(\$\) number in Spindle speed command"
    ):
        machine.run(lambda m: m.block(1, m_code(3), s=100.0, dollar=2.0))


def test_repeat_rounds_like_rs274():
    # rs274 runs "repeat [2.6]" three times and "repeat [-1]" not at all.
    machine = Machine(RecordingCanon())
    assert len(list(machine.repeat(2.6))) == 3
    assert list(machine.repeat(-1.0)) == []


def test_calls_nest_nine_deep_at_most():
    # rs274 runs a sub at call level 9 but refuses the call that would make 10.
    machine = Machine(RecordingCanon())
    levels = []

    def nested(m):
        levels.append(m.call_level)
        m.call(nested)

    with pytest.raises(GCodeError, match="Too many subroutine levels"):
        machine.run(lambda m: m.call(nested))
    assert levels == list(range(1, 10))
