"""runtime.codes: code numbering, validation and modal groups.

The unit tests pin the API; the ``rs274`` tests check the tables against the
installed rs274 by asking it about every G value 0..99.9, every M value
0..199 and pairs of codes on one line.
"""

from __future__ import annotations

import itertools
import os
import random
import subprocess
import tempfile
from concurrent.futures import ThreadPoolExecutor

import pytest

from runtime import codes
from runtime.errors import GCodeError

from rs274 import first_error_line, rs274_path

# --------------------------------------------------------------------------
# API
# --------------------------------------------------------------------------


def test_constants_follow_the_numbering():
    assert (codes.G0, codes.G1, codes.G17_1, codes.G38_2, codes.G59_3) == (
        0,
        10,
        171,
        382,
        593,
    )
    assert (codes.M0, codes.M3, codes.M199) == (10000, 10003, 10199)


@pytest.mark.parametrize(
    "code, name",
    [(10, "G1"), (593, "G59.3"), (0, "G0"), (10003, "M3"), (10100, "M100")],
)
def test_code_name(code, name):
    assert codes.code_name(code) == name
    assert codes.constant_name(code) == name.replace(".", "_")


@pytest.mark.parametrize(
    "value, code",
    [(1, 10), (59.3, 593), (1.00001, 10), (0.99999, 10), (-0.00001, 0), (38.2, 382)],
)
def test_g_code_accepts_values_near_a_tenth(value, code):
    assert codes.g_code(value) == code


@pytest.mark.parametrize(
    "value, message",
    [
        (1.05, "G-code out of range"),
        (100, "G-code out of range"),
        (99.99, "G-code out of range"),
        (-1, "Negative g code used"),
        (1e300, "Negative g code used"),  # C's int conversion overflows to INT_MIN
        (15, "Unknown g code used"),
    ],
)
def test_g_code_errors(value, message):
    with pytest.raises(GCodeError) as info:
        codes.g_code(value)
    assert info.value.message == message


@pytest.mark.parametrize(
    "value, message",
    [
        (1.5, "Non integer value for integer"),
        (-1, "Negative m code used"),
        (200, "M-code greater than 199: M200"),
        (10, "Unknown m code used: M10"),
        (1e300, "Negative m code used"),
    ],
)
def test_m_code_errors(value, message):
    with pytest.raises(GCodeError) as info:
        codes.m_code(value)
    assert info.value.message == message


def test_user_m_codes_pass_the_reader():
    assert codes.m_code(150) == 10150
    assert codes.modal_group(codes.M150) == 10


def test_modal_groups():
    assert codes.modal_group(codes.G1) == codes.modal_group(codes.G80) == 1
    assert codes.modal_group(codes.G92_1) != codes.modal_group(codes.G92)
    assert codes.modal_group(codes.M3) == codes.modal_group(codes.M5)


# --------------------------------------------------------------------------
# Against rs274
# --------------------------------------------------------------------------


def _first_error(line: str) -> str:
    """rs274's first error message for the program ``line`` + ``M2``."""
    with tempfile.TemporaryDirectory() as home:
        path = os.path.join(home, "t.ngc")
        with open(path, "w") as handle:
            handle.write(line + "\nM2\n")
        proc = subprocess.run(
            [rs274_path(), "-g", path],
            capture_output=True,
            env={**os.environ, "HOME": home},
            stdin=subprocess.DEVNULL,
            timeout=60,
        )
    return first_error_line(proc.stderr) if proc.returncode else ""


def _first_errors(lines):
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 4) as pool:
        return dict(zip(lines, pool.map(_first_error, lines)))


def _g(code: int) -> str:
    return "G%d.%d" % divmod(code, 10)


@pytest.mark.rs274
def test_known_g_codes_match_rs274():
    lines = [_g(code) for code in range(1000)]
    errors = _first_errors(lines)
    rs274_known = {
        code for code in range(1000) if errors[_g(code)] != "Unknown g code used"
    }
    assert rs274_known == set(codes.G_GROUPS)


@pytest.mark.rs274
def test_known_m_codes_match_rs274():
    lines = ["M%d" % number for number in range(200) if number != 98]
    errors = _first_errors(lines)
    unknown_at_read = {
        line
        for line, error in errors.items()
        if error.startswith("Unknown m code used") and int(line[1:]) < 100
    }
    expected_unknown = {
        "M%d" % n for n in range(100) if n != 98 and n not in codes.M_GROUPS
    }
    assert unknown_at_read == expected_unknown


@pytest.mark.rs274
def test_g_modal_groups_match_rs274():
    """Every same-group pair conflicts; a random sample of others does not."""
    same = [
        (a, b)
        for a, b in itertools.combinations(sorted(codes.G_GROUPS), 2)
        if codes.G_GROUPS[a] == codes.G_GROUPS[b] and codes.G80 not in (a, b)
    ]
    others = [
        (a, b)
        for a, b in itertools.combinations(sorted(codes.G_GROUPS), 2)
        if codes.G_GROUPS[a] != codes.G_GROUPS[b]
    ]
    sample = random.Random(1).sample(others, 300)
    errors = _first_errors(["%s %s" % (_g(a), _g(b)) for a, b in same + sample])
    conflict = "Two g codes used from same modal group"
    wrong = [
        pair
        for pair in same
        if errors["%s %s" % (_g(pair[0]), _g(pair[1]))] != conflict
    ]
    wrong += [
        pair
        for pair in sample
        if errors["%s %s" % (_g(pair[0]), _g(pair[1]))] == conflict
    ]
    assert wrong == []


@pytest.mark.rs274
def test_m_modal_groups_match_rs274():
    """Each M code conflicts with the first code of its own group only."""
    numbers = sorted(n for n in codes.M_GROUPS if n < 101 or n == 150)
    first_of_group = {}
    for number in numbers:
        first_of_group.setdefault(codes.M_GROUPS[number], number)
    pairs = [(r, n) for r in first_of_group.values() for n in numbers if n != r]
    errors = _first_errors(["M%d M%d" % pair for pair in pairs])
    conflict = "Two m codes used from same modal group"
    wrong = [
        pair
        for pair in pairs
        if (errors["M%d M%d" % pair] == conflict)
        != (codes.M_GROUPS[pair[0]] == codes.M_GROUPS[pair[1]])
    ]
    assert wrong == []


# --------------------------------------------------------------------------
# One rule for literal and computed word values
# --------------------------------------------------------------------------


def test_check_word_returns_what_rs274_keeps():
    assert codes.check_word("g", 59.3) == codes.G59_3
    assert codes.check_word("m", 3.00001) == codes.M3
    assert codes.check_word("t", 2.99999) == 3
    assert codes.check_word("h", -1.0) == -1
    assert codes.check_word("x", -1.5) == -1.5
    assert codes.check_word("d", -1.5) == -1.5


def _check_word_message(letter: str, value: float) -> str:
    try:
        codes.check_word(letter, value)
    except GCodeError as error:
        return error.message
    return ""


#: Word values rs274 reads as a computed ``[...]`` (so not at parse time).
WORD_VALUES = [
    (letter, value)
    for letter in "fsthldgm"
    for value in (-2.0, -1.00001, -1.0, -0.5, -0.00001, 0.0, 1.5, 2.99999, 200.0)
]


@pytest.mark.rs274
def test_check_word_fails_like_rs274():
    """For computed values; rs274 checks the same rule for literals."""
    lines = {
        ("%s[0+%.5f]" % (letter, value)): (letter, value)
        for letter, value in WORD_VALUES
    }
    errors = _first_errors(list(lines))
    value_errors = {_check_word_message(*word) for word in WORD_VALUES} - {""}
    wrong = []
    for line, word in lines.items():
        expected = _check_word_message(*word)
        # Without a value error, rs274 may still fail later (a block check).
        if errors[line] != expected and (expected or errors[line] in value_errors):
            wrong.append((line, errors[line], expected))
    assert wrong == []


def test_group_codes_applies_the_g80_rule():
    assert codes.group_codes([codes.G80, codes.G1]) == ({1: codes.G1}, {})
    assert codes.group_codes([codes.G1, codes.G80]) == ({1: codes.G1}, {})
    with pytest.raises(GCodeError, match="Two g codes used from same modal group"):
        codes.group_codes([codes.G1, codes.G0])
    with pytest.raises(GCodeError, match="Two m codes used from same modal group"):
        codes.group_codes([codes.M3, codes.M5])
    assert codes.group_codes([codes.G4, codes.M4]) == ({0: codes.G4}, {7: codes.M4})


@pytest.mark.rs274
def test_group_codes_matches_rs274():
    """Random lines of three G codes (G80 often among them)."""
    rng = random.Random(80)
    pool = sorted(codes.G_GROUPS) + [codes.G80] * 20
    triples = [tuple(rng.choice(pool) for _ in range(3)) for _ in range(300)]
    lines = {" ".join(_g(c) for c in triple): triple for triple in triples}
    errors = _first_errors(list(lines))
    conflict = "Two g codes used from same modal group"
    wrong = []
    for line, triple in lines.items():
        try:
            codes.group_codes(triple)
            predicted = False
        except GCodeError:
            predicted = True
        if predicted != (errors[line] == conflict):
            wrong.append((line, errors[line]))
    assert wrong == []
