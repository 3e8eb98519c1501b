"""Wrapped rotary axes and locking indexers ([AXIS_A..C] WRAPPED_ROTARY,
LOCKING_INDEXER_JOINT; runtime/rotary.py), held to rs274 (marked rs274).

The INI values are read as rs274 2.9 reads them (an int by lexical_cast, a
joint by atol), the programs go through every place rs274 treats such an
axis apart, and long runs of rows with A/B/C words check that the fast
paths step aside for them.
"""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cam_strategies
import rs274 as harness
import strategies
from runtime.machine import Machine
from runtime.canon import NullCanon
from runtime.rotary import unwrap, wrap_angle

WRAPPED_A = "[AXIS_A]\nWRAPPED_ROTARY = 1\n"
INDEXER_B = "[AXIS_B]\nLOCKING_INDEXER_JOINT = 4\n"
BOTH = (
    WRAPPED_A + INDEXER_B + "[AXIS_C]\nWRAPPED_ROTARY = 1\nLOCKING_INDEXER_JOINT = 5\n"
)
AT_G30 = "[EMCIO]\nTOOL_CHANGE_AT_G30 = 1\n"

INIS = {
    "wrapped_a": WRAPPED_A,
    "indexer_b": INDEXER_B,
    "both": BOTH + AT_G30,
    "old_names": "[AXIS_3]\nWRAPPED_ROTARY = 1\n[AXIS_4]\nLOCKING_INDEXER = 1\n",
}


def _compare(tmp_path, ini: str, text: str, mode: str = "inprocess"):
    (tmp_path / "m.ini").write_text(ini)
    program = tmp_path / "p.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, ["-i", "m.ini"])
    actual = harness.run_ngc2py(program, ["-i", "m.ini"], mode=mode)
    assert harness.compare(expected, actual) == []
    return expected


# --------------------------------------------------------------------------
# reading the INI
# --------------------------------------------------------------------------

PROBE_WRAP = "G0 A350\nG0 A10\nG0 B350\nG0 B10\nG0 C-10\nM2\n"
PROBE_INDEX = "G64 P0.1\nG0 A10\nG0 B20\nG0 C30\nG0 X1 A1\nM2\n"


@pytest.mark.rs274
@pytest.mark.parametrize("value", strategies.WRAPPED_VALUES[1:] + ["+1", "01", " 1 "])
def test_wrapped_rotary_values_as_rs274(value, tmp_path):
    ini = f"[AXIS_B]\nWRAPPED_ROTARY = {value}\n"
    _compare(tmp_path, ini, PROBE_WRAP)


@pytest.mark.rs274
@pytest.mark.parametrize(
    "value",
    strategies.INDEXER_VALUES + ["99999999999999999999", "+0", "-1.5", "2147483648"],
)
def test_locking_indexer_joint_values_as_rs274(value, tmp_path):
    ini = f"[AXIS_C]\nLOCKING_INDEXER_JOINT = {value}\n"
    _compare(tmp_path, ini, PROBE_INDEX)


@pytest.mark.rs274
@pytest.mark.parametrize("ini", sorted(INIS))
def test_several_axes_and_old_names_as_rs274(ini, tmp_path):
    _compare(tmp_path, INIS[ini], PROBE_WRAP)
    _compare(tmp_path, INIS[ini], PROBE_INDEX)


@pytest.mark.rs274
def test_ini_parameters_unaffected_as_rs274(tmp_path):
    text = (
        "(debug, #<_ini[axis_a]wrapped_rotary> #<_ini[AXIS_B]LOCKING_INDEXER_JOINT>)\n"
        "(debug, #<_ini[axis_c]locking_indexer_joint>)\nM2\n"
    )
    ini = "[RS274NGC]\nINI_VARS = 1\n" + BOTH.replace("= 5", "= 3abc")
    _compare(tmp_path, ini, text)


# --------------------------------------------------------------------------
# programs
# --------------------------------------------------------------------------

PROGRAMS = [
    # unwrapping: the word's sign gives the direction, -0 backwards
    "G0 A350\nG0 A10\nG0 A-10\nG1 F100 A20\nG0 A359.9999\nG0 A-0\nG0 A0\nM2\n",
    "G0 A360\nM2\n",
    "G0 A-360\nM2\n",
    "G0 A359.99999\nM2\n",
    # incremental words are not checked
    "G91 G0 A400\nG0 A-1000\nG90 G0 A0\nM2\n",
    # G53: the offsets and the tool's A offset come off, then the sign of the word
    "G10 L2 P1 A100\nG0 A10\nG53 G0 A20\nG53 G0 A-20\nG53 G0 A0\nG53 G0 A400\nM2\n",
    "G92 A30\nG0 A10\nG53 G0 A-5\nG53 G0 C-5\nM2\n",
    # arcs, probes
    "G0 A350\nG2 X1 I0.5 A10 F100\nG3 X0 I-0.5 A-5\nG0 A-370\nM2\n",
    "G0 A350\nG38.2 A10 F100\n(debug,#5064)\nG38.2 X1 A-10\n(debug,#5064 #5065 #5066)\n"
    "G38.3 C-20 X2\n(debug,#5066)\nM2\n",
    # G92, G52, G10: words of a turn or more refused (G10 L2 excepted)
    "G0 A300\nG91 G0 A400\nG90\nG92 A10\nG92 A-359.999\n(debug,#5214)\nG52 A400\nM2\n",
    "G0 A300\nG52 A-360\nM2\n",
    "G0 A300\nG10 L20 P1 A10\nG10 L2 P1 A400\nG10 L20 P2 A-400\nM2\n",
    "G41 D0\nG92 A400\nM2\n",
    "G10 L20 P0 C360\nM2\n",
    # G28.1/G30.1 keep angles in [0, 360); G28/G30 unwrap the reference point
    "G0 A300\nG28.1\n(debug,#5164)\nG0 A-30\nG30.1\n(debug,#5184)\nG0 A-0\nG28.1\n"
    "(debug,#5164)\nG91 G0 A-1000\nG90 G28.1\n(debug,#5164)\nM2\n",
    "#5164=100\n#5184=-100\nG0 A700\nG28\nG30 A0\nG30 X1\nG28 C5\nM2\n",
    "#5164=400\nG0 A10\nG28 X1\nG30\nM2\n",
    "#5164=-359.9\nG0 A10\nG28 A5\nM2\n",
    # indexers: G0 only, alone, in exact path mode, motion mode kept
    "G64 P0.1\nG0 B45\nG0 X1\nG61.1\nG0 B90\nG61\nG0 B0\nG64 P0.2 Q0.3\nG0 B4\nM2\n",
    "G1 X1 F100\nG0 B10\nX2\nG1 B20\nM2\n",
    "G0 B10 X1\nM2\n",
    "G0 A10 B10\nM2\n",
    "G0 C10 B10\nM2\n",
    "B10\nM2\n",
    "G81 X1 Y1 Z-1 R1 B10\nM2\n",
    "G38.2 B10 F100\nM2\n",
    "G91 G0 B10\nG0 B10\nG90 G0 B-400\nG0 B10\nM2\n",
    "G0 X1 Y1\nG0 B10 @2\nM2\n",
    "G10 L2 P1 R30\nG0 X1 Y1\nG53 G0 B10\nM2\n",
    "G1 F100 X0 Y0\nG41 D0\nG1 X1 Y1\nG0 B10\nG1 X2 Y2\nG40\nG0 X0\nM2\n",
    "G1 F100 X0 Y0\nG41.1 D1\nG1 X5 Y1\nG1 X10 Y1\nG0 B10\nG1 X10 Y10\nG40\nM2\n",
    "G64 P0.5 Q0.2\nG0 B10\nG28 B0\nG28.1\nG0 B5\nG0 Y1\nG30 Y2 B20\nG28\n"
    "(debug,#5420 #5425)\nM2\n",
    "G0 B10 C10\nM2\n",
    # a wrapped indexer told to go a turn or more: rs274 ignores the failed
    # unwrap and finds the axes it never computed moved (the "both" INI)
    "G0 C-400\nM2\n",
    "G1 X1 F100\nG0 X0 Y0\nG0 C10\nG0 C360\nM2\n",
    "G53 G0 C500\nM2\n",
    "G91 G0 C500\nG90 G0 C-370\nM2\n",
    "G0 C10\nG0 B20\nG28\nM2\n",
    # a tool change at G30: indexers first, between the AXIS comments
    "#5185=1\n#5186=0\n#5185=50\n#5186=20\nT1 M6\nM2\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("ini", ["wrapped_a", "indexer_b", "both"])
@pytest.mark.parametrize("text", PROGRAMS)
def test_programs_as_rs274(ini, text, tmp_path):
    _compare(tmp_path, INIS[ini], text)


@pytest.mark.rs274
@pytest.mark.parametrize("text", PROGRAMS[:8])
def test_converted_module_as_rs274(text, tmp_path):
    _compare(tmp_path, INIS["both"], text, mode="convert")


def test_unwrap_rules():
    assert unwrap(10.0, 10.0, 350.0, "a") == 370.0
    assert unwrap(-10.0, -10.0, 370.0, "a") == 370.0
    assert unwrap(-0.0, -0.0, 359.9, "a") == 0.0
    # the direction is the word's sign, not the sign of what is left after offsets
    assert unwrap(20.0, -80.0, 10.0, "a") == 80.0
    with pytest.raises(Exception, match="Invalid absolute position 360.00 .* axis B"):
        unwrap(360.0, 0.0, 0.0, "b")
    assert wrap_angle(-30.0) == 330.0 and wrap_angle(720.5) == 0.5


def test_reference_point_rs274_never_computed():
    """rs274 homes a wrapped axis whose reference point is a turn or more to
    values it never computed: not matched, said so."""
    machine = Machine(canon=NullCanon())
    machine.settings = machine.settings._replace(wrapped_rotary=(True, False, False))
    machine._rotary_rules = True
    machine.params[5164] = 400.0
    machine.block(1, 280, x=1.0)  # only X homes: fine
    with pytest.raises(Exception, match="does not support"):
        machine.block(2, 280)


def test_plain_without_the_settings():
    """No wrapped axis, no indexer: the fast paths stay open (no check per row)."""
    machine = Machine(canon=NullCanon())
    machine.refresh_plain()
    assert machine._rotary_rules is False and machine._plain is True


# --------------------------------------------------------------------------
# long runs of rows (data tables): the fast paths step aside
# --------------------------------------------------------------------------


def _rows(template: str, count: int) -> str:
    return "".join(template.format(i=i, a=(i * 37.5) % 700 - 350) for i in range(count))


ROW_PROGRAMS = [
    "G21 G90 F500\n" + _rows("G1 X{i}.5 A{a:.4f}\n", 80) + "M2\n",
    "G21 G90 F500\n" + _rows("G1 X{i}.5 Y1 C{a:.3f}\n", 70) + "M2\n",
    "G21 G90 F500\n"
    + _rows("X{i} Y{i} Z1\n", 70)
    + _rows("G0 A{a:.4f}\n", 70)
    + "M2\n",
    "G21 G90 F500\n" + _rows("G0 B{a:.4f}\n", 70) + _rows("G1 X{i}.25\n", 70) + "M2\n",
    "G21 G90 F500\n" + _rows("G2 X{i} Y0 I0.5 J0 A{a:.4f}\nG0 X0 Y0\n", 40) + "M2\n",
    "G21 G90 F500\nG1 X1\n" + _rows("G1 X{i}.5 B{i}\n", 70) + "M2\n",
]


@pytest.mark.rs274
@pytest.mark.parametrize("ini", ["wrapped_a", "both", "indexer_b"])
@pytest.mark.parametrize("text", ROW_PROGRAMS)
def test_row_runs_as_rs274(ini, text, tmp_path):
    program = cam_strategies.cam_sized(text)
    _compare(tmp_path, INIS[ini] + "[AXIS_C]\nWRAPPED_ROTARY = 1\n", program)


# --------------------------------------------------------------------------
# drawn programs
# --------------------------------------------------------------------------

_DRAWN = settings(
    max_examples=30,
    deadline=None,
    suppress_health_check=list(HealthCheck),
    database=None,
)


def _compare_files(tmp_path, files, args):
    for name, body in files.items():
        (tmp_path / name).write_text(body)
    program = tmp_path / "prog.ngc"
    expected = harness.run_rs274(program, args)
    actual = harness.run_ngc2py(program, args, mode="inprocess")
    assert harness.compare(expected, actual) == []


@pytest.mark.rs274
@_DRAWN
@given(strategies.rotary_programs())
def test_drawn_rotary_programs_as_rs274(tmp_path_factory, program):
    files, args = program
    _compare_files(tmp_path_factory.mktemp("rotary"), files, args)


@pytest.mark.rs274
@_DRAWN
@given(cam_strategies.cam_programs(), strategies.rotary_inis())
def test_drawn_cam_programs_under_rotary_inis_as_rs274(tmp_path_factory, text, ini):
    files = {"prog.ngc": text, "rotary.ini": ini}
    _compare_files(tmp_path_factory.mktemp("cam"), files, ["-i", "rotary.ini"])
