"""[RS274NGC] feature flags rs274 2.9 reads that leave ``rs274 -g``'s output
as it is, held to rs274 (marked rs274).

* HAL_PIN_VARS (on by default): ``#<_hal[...]>`` reads a HAL pin, but the
  stand-alone rs274 has no HAL: the name is never found, as without the flag.
* NO_DOWNCASE_OWORD: keeps the case of a name in a comment's ``#<...>``; rs274
  looks names up without regard to case, and reads the O-word names of the
  line itself downcased either way (so the subroutine file is ``name.ngc``
  in lower case).

A flag is a boost::lexical_cast<bool>: only "0" and "1" count; other
values leave the default.
"""

from __future__ import annotations

import pytest

import rs274 as harness

FLAG_VALUES = ["1", "0", "yes", "2", ""]

HAL_PROGRAMS = [
    "(debug, #<_hal[x.y]>)\nM2\n",
    "#1 = EXISTS[#<_hal[x.y]>]\n(debug, #1)\n#2 = EXISTS[#<_HAL[motion.x]>]\n(debug, #2)\nM2\n",
    "#1 = #<_hal[x.y]>\nM2\n",
    "#1 = #<_hal[]>\nM2\n",
    "#1 = #<_hal[a]b>\nM2\n",
]

CASE_PROGRAMS = [
    "#<foo> = 3\n#<_Bar> = 4\n(debug, #<foo> #<FOO> #<F o O> #<_bar> #<_BAR>)\n"
    "(print, #<_X> #<_ini[axis_a]max> #<_INI[AXIS_A]MAX>)\nM2\n",
    "o<Sub> sub\n(debug, in sub #1 #<Loc>)\no<Sub> endsub\nO<SUB> call [7]\n(debug, #<_value>)\nM2\n",
    "o<MySub> call\nM2\n",
    "o<MYSUB2> call\nM2\n",
]


def _both(tmp_path, ini: str, text: str, files=None):
    (tmp_path / "m.ini").write_text(ini)
    for name, body in (files or {}).items():
        (tmp_path / name).write_text(body)
    program = tmp_path / "p.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, ["-i", "m.ini"])
    actual = harness.run_ngc2py(program, ["-i", "m.ini"], mode="inprocess")
    return expected, actual


@pytest.mark.rs274
@pytest.mark.parametrize("value", FLAG_VALUES)
@pytest.mark.parametrize("text", HAL_PROGRAMS)
def test_hal_pin_vars_as_rs274(value, text, tmp_path):
    expected, actual = _both(tmp_path, f"[RS274NGC]\nHAL_PIN_VARS = {value}\n", text)
    assert harness.compare(expected, actual) == []


@pytest.mark.rs274
@pytest.mark.parametrize("value", FLAG_VALUES)
@pytest.mark.parametrize("text", CASE_PROGRAMS)
def test_no_downcase_oword_as_rs274(value, text, tmp_path):
    files = {
        "MySub.ngc": "o<MySub> sub\n(debug, in MySub)\no<MySub> endsub\nM2\n",
        "mysub2.ngc": "o<mysub2> sub\n(debug, in mysub2)\no<mysub2> endsub\nM2\n",
    }
    ini = f"[RS274NGC]\nNO_DOWNCASE_OWORD = {value}\nINI_VARS = 1\n[AXIS_A]\nMAX = 5\n"
    expected, actual = _both(tmp_path, ini, text, files)
    assert harness.compare(expected, actual) == []
