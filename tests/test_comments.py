"""runtime.comments: active comments, checked against rs274 with a fake machine."""

from __future__ import annotations

from typing import List, Tuple

import pytest

from runtime.comments import (
    Comment,
    Decimals,
    Name,
    classify,
    execute_comment,
    format_value,
    split_parts,
)
from runtime.errors import GCodeError
from runtime.params import Globals, Locals, Params
import rs274 as harness
from test_ops import TRACE_CALL

#: The trace calls a comment can produce.
COMMENT_CALLS = {"COMMENT", "MESSAGE", "LOG", "LOGOPEN", "LOGAPPEND", "LOGCLOSE"}


class RecordingCanon:
    """Records comment-related canon calls as (TRACE NAME, text)."""

    def __init__(self):
        self.calls: List[Tuple[str, str]] = []

    def comment(self, text):
        self.calls.append(("COMMENT", text))

    def message(self, text):
        self.calls.append(("MESSAGE", text))

    def log(self, text):
        self.calls.append(("LOG", text))

    def logopen(self, name):
        self.calls.append(("LOGOPEN", name))

    def logappend(self, name):
        self.calls.append(("LOGAPPEND", name))

    def logclose(self):
        self.calls.append(("LOGCLOSE", ""))

    def print_text(self, text):
        self.calls.append(("PRINT", text))


class FakeMachine:
    """params/globals/locals/canon, with rs274's start-up values."""

    PREDEFINED = frozenset({"_x", "_value"})

    def __init__(self):
        self.canon = RecordingCanon()
        self.params = Params({5599: 1.0})
        self.globals = Globals(self)
        self.locals = Locals()

    def predefined(self, name):
        return 0.0


#: The program's settings, in G-code and as the fake machine gets them.
SETUP_GCODE = """#1=3.14159
#2=-2.5
#3=0.00005
#4=-0.0001
#5=[100000*100000*100000*100000*10]
#6=[100000*100000*100000*100000*100]
#7=4294967296.7
#8=0.5
#<loc>=12.5
#<_glob>=-7
"""


def setup_machine() -> FakeMachine:
    m = FakeMachine()
    values = {
        1: 3.14159,
        2: -2.5,
        3: 0.00005,
        4: -0.0001,
        5: 1e21,
        6: 1e22,
        7: 4294967296.7,
        8: 0.5,
    }
    for number, value in values.items():
        m.params[number] = value
    m.locals.loc = 12.5
    m.globals._glob = -7.0
    return m


#: Comment texts whose behaviour rs274 reproduces deterministically.
COMMENTS = [
    "debug,#1 #2 #3 #4 #5 #6 #7 #8",
    "debug,#0 #5601 #5602 #5603 #4294967297 #99999999999999999999",
    "debug,#<loc> #<LOC> #< l o c > #<_glob> #<_x> #<nope> #<> #<x#1>",
    "debug,x#1y#2 #-1 # 1 #a #10.5 ##1 #<loc>>",
    "debug,%.2f#1 %d#2 #1 %.0f#8 %d#7",
    "debug,%.3f #1 %x %% % %5d#1 %e#1 %.50f#1 %.2lf#1 %D#1 %.2F#1",
    "debug,%.%d#1 %. %.5 x%.3f %%d#1",
    "debug,%.9f#1 %.9f#6 %d#6 %.3f#5",
    "  DeBuG,#1",
    "debug , spaced",
    "print,printed #1 #<loc>",
    "PRINT,a%%b %d",
    "log,a%db #1",
    'log,hello "q" \\n',
    "logopen,/tmp/ngc2py-never-created.txt",
    "logappend, rel.txt",
    "logclose",
    "  LogClose",
    "logclose ",
    "msg,Case Kept  ",
    " MSG , spaced",
    "msg,#1 %d",
    "Plain Comment  ",
    "PROBEOPEN /tmp/probe.txt",
    "probeclose",
    "abortx",
]


def run_ours(comments: List[str], capsys) -> List[Tuple[str, str]]:
    m = setup_machine()
    events: List[Tuple[str, str]] = []
    for text in comments:
        execute_comment(m, classify(text))
        events += m.canon.calls
        m.canon.calls = []
    assert capsys.readouterr().out == ""  # PRINT reaches the canon, not stdout
    return events


def rs274_events(tmp_path, program: str) -> Tuple[List[Tuple[str, str]], str]:
    """rs274's comment calls and PRINT lines, in stdout order; and its error."""
    result = harness.run_rs274(tmp_path / "prog.ngc", text=program)
    events = []
    for line in result.stdout.decode("latin-1").splitlines():
        match = TRACE_CALL.match(line)
        if match is None:
            events.append(("PRINT", line))
        elif match.group(1) in COMMENT_CALLS:
            events.append((match.group(1), match.group(2)[1:-1]))
    return events, result.err


# --------------------------------------------------------------------------
# Unit tests (facts observed with rs274)
# --------------------------------------------------------------------------


def test_classify_prefixes():
    assert classify("  MSG,Hi ") == Comment("msg", "Hi ")
    assert classify("MSG , x") == Comment("plain", "MSG , x")
    assert classify("logclose") == Comment("logclose", "")
    assert classify("logclose ").kind == "plain"
    assert classify("LOGOPEN,f.txt") == Comment("logopen", "f.txt")
    assert classify("PROBEOPEN f.txt") == Comment("plain", "PROBEOPEN f.txt")


def test_split_parts():
    assert split_parts("a#1 #<A b>%d#22 #x %.3f") == (
        "a",
        1,
        " ",
        Name("ab"),
        Decimals(0),
        22,
        " #x ",
        Decimals(3),
    )
    assert split_parts("%.50f") == (".50f",)
    assert split_parts("ok #<unterminated") == ("ok ",)
    assert split_parts("trailing #") == ("trailing ",)


def test_format_value():
    assert format_value(3.14159) == "3.141590"
    assert format_value(-0.00005) == "0.000000"
    assert format_value(-0.4, 0) == "-0"
    assert format_value(1e22) == "######"
    assert format_value(None) == "######"


def test_debug_is_silent_unless_5599_is_positive():
    m = setup_machine()
    m.params[5599] = 0.0
    execute_comment(m, classify("debug,x"))
    m.params[5599] = 0.5
    execute_comment(m, classify("debug,y"))
    assert m.canon.calls == [("MESSAGE", "y")]


def test_abort_raises_the_expanded_text():
    with pytest.raises(GCodeError) as info:
        execute_comment(setup_machine(), classify("abort, stop #1 here #<nope>"))
    assert info.value.message == " stop 3.141590 here ######"


def test_parts_may_be_given_explicitly():
    m = setup_machine()
    execute_comment(m, Comment("log", "ignored", ("v=", 1, Name("loc"))))
    assert m.canon.calls == [("LOG", "v=3.14159012.500000")]


# --------------------------------------------------------------------------
# Differential tests
# --------------------------------------------------------------------------


@pytest.mark.rs274
def test_comments_match_rs274(tmp_path, capsys):
    program = SETUP_GCODE + "".join("(%s)\n" % c for c in COMMENTS) + "M2\n"
    expected, err = rs274_events(tmp_path, program)
    assert err == ""
    assert run_ours(COMMENTS, capsys) == expected


@pytest.mark.rs274
def test_debug_switch_matches_rs274(tmp_path, capsys):
    program = (
        SETUP_GCODE
        + "#5599=0\n(debug,hidden)\n#5599=0.5\n(debug,shown)\n#5599=-1\n(debug,h)\nM2\n"
    )
    expected, _ = rs274_events(tmp_path, program)
    m = setup_machine()
    for switch, text in (
        (0.0, "debug,hidden"),
        (0.5, "debug,shown"),
        (-1.0, "debug,h"),
    ):
        m.params[5599] = switch
        execute_comment(m, classify(text))
    assert m.canon.calls == expected


@pytest.mark.rs274
def test_abort_matches_rs274(tmp_path):
    _, err = rs274_events(tmp_path, SETUP_GCODE + "(abort, stop #1 %d#2 #<nope>)\nM2\n")
    with pytest.raises(GCodeError) as info:
        execute_comment(setup_machine(), classify("abort, stop #1 %d#2 #<nope>"))
    assert info.value.message == err


def test_empty_comment_is_silent():
    """rs274 acts on the last comment only when its text is not empty."""
    assert classify("").kind == "none"
    assert classify(" ") == Comment("plain", "")
    from ngc2py.parser import parse_text

    lines = parse_text(b"()\n(foo) ()\n() (foo)\nG0 X1 ( )\n", "t.ngc").lines
    acted_on = [line.comment and (line.comment.kind, line.comment.text) for line in lines]
    assert acted_on == [None, None, ("plain", "foo"), ("plain", "")]
