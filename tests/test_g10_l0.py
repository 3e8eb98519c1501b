"""G10 L0 (reload the tool table) is refused while a tool is loaded.

rs274 2.9 (convert_modal_0) reads its own spindle slot's tool number: an
M6 changes that slot only when the next line is read, and neither M61 Q0
nor T0 M6 clears the number, so the refusal follows rs274's copy rather
than the tool in the spindle. Found by a sweep of real programs (a lathe
touch-off subroutine).
"""

from __future__ import annotations

import pytest

import rs274 as harness

TOOLS = "T1 P1 D0.5 Z1\nT2 P2 D0.25 Z2\nT3 P3 Z3\n"


@pytest.mark.rs274
@pytest.mark.parametrize(
    "text",
    [
        "T2 M6\nG10 L0\nM2\n",
        "T2 M6\nM61 Q0\nG10 L0\nM2\n",
        "T2 M6\nT0 M6\nG10 L0\nM2\n",
        "T2 M6\nT3 M6\nG10 L0\nM2\n",
        "T2 M6\nT3 M6 G10 L0\nM2\n",
        "T2 M6 G10 L0\nM2\n",
        "M61 Q2\nG10 L0\nM2\n",
        "T2\nG10 L0\nM2\n",
        "G10 L0\nM2\n",
        "T2 M6\nG10 L1 P2 Z5\nG10 L0\nM2\n",
    ],
)
def test_g10_l0_with_a_loaded_tool_as_rs274(text, tmp_path):
    (tmp_path / "tools.tbl").write_text(TOOLS)
    program = tmp_path / "p.ngc"
    program.write_text(text)
    expected = harness.run_rs274(program, ["-t", "tools.tbl"])
    actual = harness.run_ngc2py(program, ["-t", "tools.tbl"])
    assert harness.compare(expected, actual) == []
    refused = expected.err.startswith("G10 L0 not allowed with loaded tool")
    assert refused == (expected.rc == 1)  # (the table was read: no other error)
