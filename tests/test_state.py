"""The machine's state is declared in one place (runtime/state.py).

Every field a Machine holds is declared in ``MachineState`` with what it
is; the mixins change fields but create none. These tests hold machines to
that: a new one has every declared field (but the two RETAIN_G43 swaps),
and one that ran any golden program holds nothing undeclared.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import rs274 as harness
from test_stats import scratch_run

from ngc2py import cli
from runtime import Machine, start
from runtime.canon import RecordingCanon
from runtime.state import FIELDS

#: Set only under RETAIN_G43 (every block runs the M code step).
RETAIN_G43_ONLY = {"_execute"}
GOLDEN = harness.REPO / "golden"


def test_a_new_machine_has_every_declared_field():
    machine = Machine(RecordingCanon())
    assert set(vars(machine)) == FIELDS - RETAIN_G43_ONLY


def test_retain_g43_swaps_a_declared_behaviour():
    with scratch_run(GOLDEN / "tools" / "retain_g43.ngc"):
        machine = Machine(RecordingCanon(), ini="retain_g43.ini")
    assert set(vars(machine)) == FIELDS


def _options(program: Path) -> dict:
    args = program.with_suffix(".args")
    words = args.read_text().split() if args.exists() else []
    options = {}
    for flag, name in (("-i", "ini"), ("-t", "tool_table"), ("-v", "var_file")):
        if flag in words:
            options[name] = words[words.index(flag) + 1]
    return options


@pytest.mark.parametrize(
    "folder", sorted(p.name for p in GOLDEN.iterdir() if p.is_dir()), ids=str
)
def test_running_programs_creates_no_undeclared_field(folder):
    programs = sorted((GOLDEN / folder).glob("*.ngc"))
    assert programs
    with scratch_run(programs[0]):
        for program in programs:
            options = _options(program)
            module = cli.load_program(program.name, options.get("ini"))
            machine = Machine(RecordingCanon(), source=module.__ngc__, **options)
            try:
                start(machine, module.main)
            except BaseException:  # errors and program ends alike
                pass
            undeclared = set(vars(machine)) - FIELDS
            assert not undeclared, "%s: %s" % (program.name, sorted(undeclared))
