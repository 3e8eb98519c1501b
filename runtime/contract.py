"""The contract between generated modules and the runtime, in one place.

A module ngc2py writes imports the names below and uses the machine
through the methods and fields below, nothing else (tests/test_contract.py
converts every golden program and holds its module to these lists). The
rest of runtime/ is private to it: it may change without breaking a
module converted before (docs/ARCHITECTURE.md, "Runtime API used by
generated code", says what each name does).
"""

from __future__ import annotations

import re

#: module -> the names a generated module may import from it
IMPORTS = {
    "runtime": ("Machine", "SourceMap", "run_cli", "start"),
    # rs274's operators and functions (floats in, floats out)
    "runtime.ops": (
        "abs_",
        "acos",
        "and_",
        "asin",
        "atan2",
        "cos",
        "div",
        "eq",
        "exp",
        "finite",
        "fix",
        "fup",
        "ge",
        "gt",
        "le",
        "ln",
        "lt",
        "mod",
        "ne",
        "or_",
        "power",
        "round_",
        "sin",
        "sqrt",
        "tan",
        "truth",
        "xor",
    ),
    "runtime.fast": ("run_rows",),
    # and every G and M code's constant (CODE_NAME: G0, G38_2, M3, ...)
    "runtime.codes": ("to_integer",),
}

#: The name of a G or M code's constant in runtime.codes.
CODE_NAME = re.compile(r"[GM]\d+(_\d+)?")

#: What generated code uses of the machine ``m``: one method per kind of
#: statement, the parameter stores it binds (p = m.params.values, g =
#: m.globals, v = m.locals) and the few fields of the state it reads or sets.
MACHINE = (
    # blocks and moves
    "block",
    "move",
    "feed",
    "rapid",
    "arc",
    "gcode",
    "mcode",
    # comments, one method per kind (runtime.comments.LINE_METHODS)
    "comment",
    "message",
    "debug",
    "print",
    "log",
    "abort",
    "logopen",
    "logappend",
    "logclose",
    "py",
    "pyrun",
    "pyreload",
    # subroutines and control flow
    "define",
    "definition_value",
    "call",
    "call_named",
    "call_found",
    "m98",
    "m99_back",
    "m98_frame_end",
    "is_m98",
    "seek_failed",
    "top_level_return",
    "check_label",
    "frame_mark",
    "left_frame",
    "same_frame",
    "repeat",
    "repeat_again",
    "repeat_kept",
    "step",
    "fail",
    "end_of_file",
    "flow",  # a file run line by line (runtime.oflow.Flow: next, o, define)
    # the parameter stores
    "params",
    "globals",
    "locals",
    # fields of the state (runtime.state)
    "block_delete",
    "doing_break",
    "doing_continue",
    "executed_if",
    "reading_profile",
)


def importable(module: str, name: str) -> bool:
    """Whether the contract lets a generated module import ``name`` from ``module``."""
    if module == "runtime.codes" and CODE_NAME.fullmatch(name):
        return True
    return name in IMPORTS.get(module, ())


__all__ = ["CODE_NAME", "IMPORTS", "MACHINE", "importable"]
