"""runtime.params: numbered and named parameters, checked against rs274."""

from __future__ import annotations

import copy

import pytest

import runtime.machine  # noqa: F401 - it makes Globals' predefined names read-only
from runtime.errors import GCodeError
from runtime.inifile import IniSettings
from runtime.params import Globals, Locals, Params, attr_safe
from test_ops import rs274_error, rs274_messages


class FakeMachine:
    """Just what Globals needs: the predefined names and their values, and
    settings without an INI file."""

    PREDEFINED = frozenset({"_x", "_value", "_line"})
    settings = IniSettings()

    def predefined(self, name):
        return {"_x": 5.5, "_value": 0.0, "_line": 7.0}[name]


def error_of(action) -> str:
    """The GCodeError message ``action()`` raises, or "" if it succeeds."""
    try:
        action()
    except GCodeError as exc:
        return exc.message
    return ""


# --------------------------------------------------------------------------
# Numbered parameters
# --------------------------------------------------------------------------

INDEXES = [
    "0",
    "1",
    "5601",
    "5602",
    "-1",
    "1.00005",
    "1.0002",
    "0.99995",
    "[0-0.5]",
    "5600.5",
    "[3000000000]",
    "[0-3000000000]",
    "[2147483647.5]",
    "[2**31]",
    "30.9999",
    "31.00011",
    "5399",
    "5400",
    "5413",
    "5414",
    "5419",
    "5420",
    "5428",
    "5429",
    "5599",
]


def test_initial_values_and_default_zero():
    p = Params({5220: 1.0, 5221: 2.5})
    assert (p[5220], p[5221.0], p[31]) == (1.0, 2.5, 0.0)


def test_index_close_to_integer_is_rounded():
    p = Params()
    p[1.00005] = 3.0
    assert p[0.99995] == 3.0 and p[1] == 3.0


@pytest.mark.parametrize(
    "index, message",
    [
        (0, "Parameter number out of range"),
        (5602, "Parameter number out of range"),
        (3e9, "Parameter number out of range"),
        (float("nan"), "Parameter number out of range"),
        (1.0002, "Non integer value for integer"),
        (-0.5, "Non integer value for integer"),
    ],
)
def test_bad_indexes(index, message):
    assert error_of(lambda: Params()[index]) == message


def test_readonly_ranges():
    p = Params()
    assert error_of(lambda: p.__setitem__(5400, 1.0)) == "Parameter is readonly"
    assert error_of(lambda: p.__setitem__(5428, 1.0)) == "Parameter is readonly"
    p.set_internal(5400, 4.0)  # the interpreter itself may
    assert p[5400] == 4.0
    p.position = (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0)  # and publishes these
    assert [p[n] for n in range(5420, 5429)] == list(p.position)
    assert p.get_internal(5428) == 9.0


def test_position_unreadable_under_cutter_comp():
    p = Params()
    p.cutter_comp = True
    assert error_of(lambda: p[5421]) == (
        "Cannot read current position with cutter radius compensation on"
    )
    assert p[5400] == 0.0


def test_call_arguments_saved_set_and_restored():
    p = Params()
    p[1], p[2], p[3], p[31] = 11.0, 22.0, 33.0, 31.0
    saved = p.save_locals()
    p.set_call_args([7.0])
    assert (p[1], p[2], p[3], p[30], p[31]) == (7.0, 0.0, 0.0, 0.0, 31.0)
    p[2] = 99.0
    p.restore_locals(saved)
    assert (p[1], p[2], p[3], p[31]) == (11.0, 22.0, 33.0, 31.0)


@pytest.mark.rs274
@pytest.mark.parametrize("index", INDEXES)
def test_setting_index_errors_match_rs274(tmp_path, index):
    # the index is checked before the value: rs274 never reaches the 1/0
    expected = rs274_error(tmp_path, "#%s=[1/0]\nM2\n" % index)
    ours = error_of(lambda: Params.setting_index(float(eval_index(index))))
    assert ours == (expected if expected != "Attempt to divide by zero" else "")


@pytest.mark.rs274
@pytest.mark.parametrize("index", INDEXES)
def test_reading_index_errors_match_rs274(tmp_path, index):
    expected = rs274_error(tmp_path, "#1=#%s\nM2\n" % index)
    assert error_of(lambda: Params()[float(eval_index(index))]) == expected


def eval_index(text: str) -> float:
    """The value of one of INDEXES (numbers, or ``[0-x]``/``[2**n]`` forms)."""
    inner = text.strip("[]")
    if inner.startswith("0-"):
        return -float(inner[2:])
    if "**" in inner:
        base, exponent = inner.split("**")
        return float(base) ** float(exponent)
    return float(inner)


@pytest.mark.rs274
def test_call_argument_rules_match_rs274(tmp_path):
    program = """#1=11
#2=22
#3=3
o<s> sub
(debug,#1 #2 #3 #30)
#1=99
o<s> endsub
o<s> call [7]
(debug,#1 #2 #3)
M2
"""
    p = Params()
    p[1], p[2], p[3] = 11.0, 22.0, 3.0
    saved = p.save_locals()
    p.set_call_args([7.0])
    inside = "%f %f %f %f" % (p[1], p[2], p[3], p[30])
    p[1] = 99.0
    p.restore_locals(saved)
    after = "%f %f %f" % (p[1], p[2], p[3])
    assert rs274_messages(tmp_path, program) == [inside, after]


# --------------------------------------------------------------------------
# Named parameters
# --------------------------------------------------------------------------


def test_unset_names_fail():
    v, g = Locals(), Globals(FakeMachine())
    assert error_of(lambda: v.nope) == "Named parameter #<nope> not defined"
    assert error_of(lambda: g["_a.b"]) == "Named parameter #<_a.b> not defined"


def test_predefined_names_are_read_through_the_machine_and_read_only():
    g = Globals(FakeMachine())
    assert g._x == 5.5 and g.exists("_x") == 1.0
    assert error_of(lambda: setattr(g, "_x", 1.0)) == (
        "Cannot assign to read-only parameter #<_x>"
    )
    assert error_of(lambda: g.__setitem__("_line", 1.0)) == (
        "Cannot assign to read-only parameter #<_line>"
    )


def test_names_that_look_like_python_are_data():
    v, g = Locals(), Globals(FakeMachine())
    for name in ("exists", "declare", "__class__", "__dict__", "func", "_machine_"):
        v[name] = 1.5
        assert v[name] == 1.5 and v.exists(name) == 1.0
    g["_machine_"] = 2.0
    assert g["_machine_"] == 2.0 and g._x == 5.5 and g.exists("exists") == 0.0
    assert type(v) is Locals and copy.copy(v)["exists"] == 1.5


def test_attribute_access_rule():
    assert attr_safe("i") and attr_safe("_feed") and attr_safe("x1")
    for name in ("exists", "declare", "__class__", "_machine_", "a.b", "if", "1a", ""):
        assert not attr_safe(name)


def test_declare_makes_a_name_exist_for_the_rest_of_the_line():
    v, g = Locals(), Globals(FakeMachine())
    v.declare("n")
    assert v.n == 0.0
    v.n = 4.0
    v.declare("n")
    assert v.n == 4.0
    g.declare("_x")  # predefined: its assignment fails later, not here
    assert g.exists("_x") == 1.0 and "_x" not in g.__dict__


@pytest.mark.rs274
def test_named_parameter_rules_match_rs274(tmp_path):
    program = """#<_foo>=[#<_foo>+1] #1=#<_foo>
#<n>=2 #2=EXISTS[#<n>] #3=#<n>
#<Ab C> = 3
(debug,#1 #2 #3 #<abc>)
M2
"""
    v, g = Locals(), Globals(FakeMachine())
    g.declare("_foo")
    first = g._foo + 1.0
    one = g._foo
    g._foo = first
    v.declare("n")
    two, three = v.exists("n"), v.n
    v.n = 2.0
    v.abc = 3.0
    expected = "%f %f %f %f" % (one, two, three, v.abc)
    assert rs274_messages(tmp_path, program) == [expected]


@pytest.mark.rs274
@pytest.mark.parametrize(
    "program, action",
    [
        ("#1=#<nope>", lambda v, g: v.nope),
        ("#1=#<_nope>", lambda v, g: g._nope),
        ("#<_x>=1", lambda v, g: setattr(g, "_x", 1.0)),
        ("#<_value>=1", lambda v, g: setattr(g, "_value", 1.0)),
        ("#1=#<Ab C>", lambda v, g: v.abc),
    ],
)
def test_named_errors_match_rs274(tmp_path, program, action):
    v, g = Locals(), Globals(FakeMachine())
    assert error_of(lambda: action(v, g)) == rs274_error(tmp_path, program + "\nM2\n")


@pytest.mark.rs274
def test_main_level_locals_are_invisible_in_subroutines(tmp_path):
    program = """#<a>=1
o<s> sub
o1 if [EXISTS[#<a>]]
(debug,seen)
o1 else
(debug,unseen)
o1 endif
o<s> endsub
o<s> call
M2
"""
    main, frame = Locals(), Locals()
    main.a = 1.0
    assert rs274_messages(tmp_path, program) == [
        "seen" if frame.exists("a") else "unseen"
    ]
