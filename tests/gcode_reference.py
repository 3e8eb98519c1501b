"""Run LinuxCNC's own ``gcode.parse`` on a program and print its calls as JSON.

Run with the interpreter that has LinuxCNC's ``gcode`` module (Debian's
``/usr/bin/python3`` with linuxcnc-uspace): ``python3 gcode_reference.py
PROG.ngc CODES_JSON OUT.json``, CODES_JSON being the JSON list of the extra
arguments of ``gcode.parse`` (``["G20", "G17"]`` for unitcode and
initcode); the result goes to OUT.json (stdout is the module's: it prints
PRINT comments there). The recording canon answers the module's questions like
tests/test_preview.py's does, so the two call sequences can be compared.
"""

import json
import sys

import gcode
from gcode_answers import ANSWERS, QUESTIONS  # the canon's answers, shared


class Recorder:
    def __init__(self):
        self.calls = []
        self.questions = []

    def __getattr__(self, name):
        if name.startswith("__") or name == "parameter_file":
            raise AttributeError(name)

        def method(*args):
            if name in QUESTIONS:
                self.questions.append(name)
                if name == "get_tool":
                    return (args[0],) + (0.0,) * 12 + (0,)
                return ANSWERS[name]
            if name == "next_line":
                line = args[0]
                args = (line.sequence_number, list(line.gcodes), list(line.mcodes))
                args += (line.feed_rate, line.speed)
            self.calls.append([name, list(args)])

        return method


def main():
    recorder = Recorder()
    extra = json.loads(sys.argv[2])
    result = list(gcode.parse(sys.argv[1], recorder, *extra))
    message = gcode.strerror(result[0]) if result[0] >= gcode.MIN_ERROR else ""
    with open(sys.argv[3], "w") as out:
        json.dump(
            {
                "calls": recorder.calls,
                "result": result,
                "message": message,
                "questions": sorted(set(recorder.questions)),
            },
            out,
        )


if __name__ == "__main__":
    main()
