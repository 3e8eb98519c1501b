"""The answers a preview canon gives to gcode.parse's questions, from
gcode_answers.json: one table for tests/gcode_reference.py (run by the
system Python, next to LinuxCNC's gcode module) and tests/test_preview.py."""

import json
from pathlib import Path

ANSWERS = {
    key: value
    for key, value in json.loads(
        Path(__file__).with_name("gcode_answers.json").read_text()
    ).items()
    if not key.startswith("_")
}
QUESTIONS = set(ANSWERS) | {"get_tool"}
