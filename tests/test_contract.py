"""Generated modules keep to the runtime's contract (runtime/contract.py).

Every golden program is converted and its module read as a tree: it may
import only the contract's names, in ``from`` imports of the contract's
modules, and use the machine ``m`` only through the contract's methods and
fields. The contract's names must exist. A compiler change that reaches
into the runtime's private parts fails here first.
"""

from __future__ import annotations

import ast
import importlib

import pytest

import rs274 as harness

from ngc2py.compiler import compile_file
from runtime import Machine
from runtime.contract import IMPORTS, MACHINE, importable
from runtime.state import FIELDS

GOLDEN = harness.REPO / "golden"


def test_every_name_of_the_contract_exists():
    for module, names in IMPORTS.items():
        loaded = importlib.import_module(module)
        for name in names:
            assert hasattr(loaded, name), "%s.%s" % (module, name)
    for name in MACHINE:
        assert hasattr(Machine, name) or name in FIELDS, "m.%s" % name


def breaches(text: str):
    """What a module's text uses of the runtime beyond the contract."""
    found = []
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.Import):
            found += ["import %s" % alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            found += [
                "from %s import %s" % (node.module, alias.name)
                for alias in node.names
                if not importable(node.module, alias.name)
            ]
        elif (
            isinstance(node, ast.Attribute)
            and isinstance(node.value, ast.Name)
            and node.value.id == "m"
            and node.attr not in MACHINE
        ):
            found.append("m.%s" % node.attr)
    return found


def test_a_breach_is_seen():
    text = "from runtime.machine import Machine\nimport os\nm.current\nm.block(1)\n"
    assert breaches(text) == [
        "from runtime.machine import Machine",
        "import os",
        "m.current",
    ]


@pytest.mark.parametrize(
    "folder", sorted(p.name for p in GOLDEN.iterdir() if p.is_dir()), ids=str
)
def test_generated_modules_keep_to_the_contract(folder):
    for program in sorted((GOLDEN / folder).glob("*.ngc")):
        args = program.with_suffix(".args")
        words = args.read_text().split() if args.exists() else []
        ini = program.parent / words[words.index("-i") + 1] if "-i" in words else None
        text = compile_file(str(program), None if ini is None else str(ini))
        assert not breaches(text), "%s: %s" % (program.name, breaches(text))
