#!/usr/bin/env python3
"""Every simulation workflow against LinuxCNC, side by side.

    python bench/workflows.py [--repeat N] [--only NAME,...] [--big] [--keep DIR]

For each workload of bench/workloads.py (CAM moves, CAM arcs whose centres
and radii vary, a trigonometry loop, canned cycles as rows of hole words and
as a cycle line a hole, the CAM files and cycles again with every line
numbered, a shop's program of comments, restated modes and pauses; large,
and again at the size most programs are) it times, medians
of ``--repeat`` alternating runs:

* preview: LinuxCNC's ``gcode.parse`` (system Python) against
  ``ngc2py.parse`` with the same counting canon, in-process time of the
  module's import and the parse call; ngc2py's with its module cached, and its first parse of a
  new file (an empty compile cache: conversion included); a reload, the
  second parse of the file in one process for both (what a preview
  application does when the file changes or is opened again); and the canon's
  own calls alone (each call the parse made, made again from a list): the
  least any parse can take, so its ratio is the best one could reach;
* ``ngc2py stats`` and ``ngc2py flatten`` against ``rs274 -g`` (whole
  commands, wall time and peak memory);
* ``ngc2py plot`` (a PNG) against ``rs274 -g``, on the CAM, arc and drilling files;
* ``ngc2py.toolpath(path)`` (the moves as NumPy arrays) against ``rs274 -g``;
* a user's Canon subclass that counts straight_feed/arc_feed calls:
  microseconds per move on top of a do-nothing run.

``--big`` adds a 1M-move CAM file (stats and plot). Then the golden check of
a library: this project's golden/ corpus checked by ``ngc2py golden check``
(warm cache), and by pytest with ngc2py's plugin (the only plugin loaded),
against ``rs274 -g`` run on each program. Ratio = LinuxCNC's
time / ngc2py's (higher is better). Timings belong here, never in tests.
"""

from __future__ import annotations

import argparse
import os
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import workloads  # noqa: E402  (bench/ is not a package)
from run import (
    REPO,
    SYSTEM_PYTHON,
    Run,
    fmt_ratio,
    med,
    peak,
    user_python,
)  # noqa: E402

WORKLOADS = {
    "cam_100k": (workloads.cam, 100_000),
    "cam_arcs_100k": (workloads.cam_arcs, 100_000),
    "loop_200k": (workloads.loop, 200_000),
    "cycles_20k": (workloads.drill_cycles, 20_000),
    "cycle_lines_20k": (workloads.drill_lines, 20_000),
    # posts that number every line (N10, N20...)
    "cam_n_100k": (workloads.cam_numbered, 100_000),
    "cam_arcs_n_100k": (workloads.cam_arcs_numbered, 100_000),
    "cycles_n_20k": (workloads.drill_cycles_numbered, 20_000),
    # what shops' programs add: comments on moves, G90 G1 / G17 G2 restated
    # on every line, a hole at a time with G4 pauses
    "shop_20k": (workloads.shop, 20_000),
    # programs of the size most are (and the before-stop hook times): the
    # fixed costs, Python's start and imports, weigh most there
    "cam_20k": (workloads.cam, 20_000),
    "cam_arcs_3k": (workloads.cam_arcs, 3_000),
    "cycles_2k": (workloads.drill_cycles, 2_000),
}
BIG = {"cam_1m": (workloads.cam, 1_000_000)}

#: The same canon for gcode.parse and ngc2py.parse: it counts every call.
COUNTING_PARSE = """\
import sys, time
ANSWERS = {"get_external_angular_units": 1.0, "get_external_length_units": 0.03937007874016,
           "get_axis_mask": 0x3F, "get_block_delete": False, "check_abort": False}
class Canon:
    def __init__(self):
        self.counts = {}
    def straight_feed(self, *args):
        self.counts["feed"] = self.counts.get("feed", 0) + 1
    def straight_traverse(self, *args):
        self.counts["rapid"] = self.counts.get("rapid", 0) + 1
    def arc_feed(self, *args):
        self.counts["arc"] = self.counts.get("arc", 0) + 1
    def next_line(self, linecode):
        self.counts["lines"] = self.counts.get("lines", 0) + 1
    def __getattr__(self, name):
        if name.startswith("__") or name == "parameter_file":  # optional ones
            raise AttributeError(name)
        if name in ANSWERS:
            return lambda *args: ANSWERS[name]
        if name == "get_tool":
            return lambda pocket: (pocket,) + (0.0,) * 12 + (0,)
        return lambda *args: None
start = time.perf_counter()  # a fresh process: the import is timed too
if sys.argv[2] == "gcode":
    import gcode as parser
else:
    import ngc2py as parser
canon = Canon()
if sys.argv[3:] == ["again"]:  # a preview application's reload: timed the second time
    parser.parse(sys.argv[1], Canon(), "G21", "")
    start = time.perf_counter()
parser.parse(sys.argv[1], canon, "G21", "")
print(time.perf_counter() - start, sorted(canon.counts.items()))
"""

#: The same canon's calls alone: every call ngc2py.parse made on it (the
#: same objects), made again from a prepared list in C. No parse can take
#: less; gcode.parse's time over this is the best ratio one could reach.
CANON_CALLS = COUNTING_PARSE.split("if sys.argv[2]")[0] + """\
import operator
from collections import deque
from itertools import starmap
import ngc2py
calls = []
class Recording:
    def __init__(self, canon):
        self.canon = canon
    def __getattr__(self, name):
        method = getattr(self.canon, name)
        def record(*args):
            calls.append((name, args))
            return method(*args)
        return record
ngc2py.parse(sys.argv[1], Recording(Canon()), "G21", "")
canon = Canon()
made = [(getattr(canon, name),) + args for name, args in calls]
call = getattr(operator, "call", None)  # (Python 3.11)
start = time.perf_counter()
if call is not None:
    deque(starmap(call, made), maxlen=0)
else:
    for method, *args in made:
        method(*args)
print(time.perf_counter() - start, len(made))
"""

#: A user's canon that counts moves, against the same run with NullCanon.
USER_CANON = """\
import sys, time
from ngc2py.loading import load_program
from runtime.canon import Canon, NullCanon
from runtime.machine import Machine
from runtime.main import start
class Counting(Canon):
    moves = 0
    def straight_feed(self, *args):
        self.moves += 1
    def straight_traverse(self, *args):
        self.moves += 1
    def arc_feed(self, *args):
        self.moves += 1
module = load_program(sys.argv[1], None)
times = {"NullCanon": [], "Counting": []}
for canon in (NullCanon(), Counting(), NullCanon(), Counting(), NullCanon(), Counting()):
    begin = time.perf_counter()
    try:
        start(Machine(canon, source=module.__ngc__), module.main)
    except BaseException:
        pass
    times[type(canon).__name__].append(time.perf_counter() - begin)
print(min(times["NullCanon"]), min(times["Counting"]), canon.moves)
"""


#: The toolpath API as a user calls it: the program's moves as NumPy arrays.
TOOLPATH = "import sys, ngc2py; ngc2py.toolpath(sys.argv[1])"


def timed(cmd, cwd, env, repeat, out=None):
    return [Run(cmd, cwd, env, out) for _ in range(repeat)]


def in_process(cmd, cwd, env, repeat):
    """Median of the first number each run prints, and the rest of its output."""
    values, rest = [], ""
    for _ in range(repeat):
        proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
        if proc.returncode != 0 or not proc.stdout.strip():
            return None, (
                proc.stderr.strip().splitlines()[-1:] if proc.stderr else "failed"
            )
        first, _, rest = proc.stdout.strip().partition(" ")
        values.append(float(first))
    return statistics.median(values), rest


def rs274_each(folder: Path, home: Path) -> float:
    programs = [
        p for p in sorted(folder.rglob("*.ngc")) if p.with_suffix(".rc").exists()
    ]
    scratch = Path(tempfile.mkdtemp(prefix="ngc2py-bench-lib-"))
    try:
        copy = scratch / "lib"
        shutil.copytree(folder, copy)  # rs274 rewrites -v files: not ours
        begin = time.perf_counter()
        for p in programs:
            p = copy / p.relative_to(folder)
            a = p.with_suffix(".args")
            args = shlex.split(a.read_text()) if a.exists() else []
            subprocess.run(
                ["rs274", "-g", *args, p.name],
                cwd=p.parent,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
                env=dict(os.environ, HOME=str(home)),
                timeout=60,
            )
        return time.perf_counter() - begin
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument(
        "--only", help="comma-separated workloads: " + ", ".join({**WORKLOADS, **BIG})
    )
    ap.add_argument("--big", action="store_true", help="add the 1M-move CAM file")
    ap.add_argument(
        "--no-golden", action="store_true", help="leave out the library check"
    )
    ap.add_argument("--keep", help="write the programs and outputs here and keep them")
    args = ap.parse_args(argv)
    table = dict(WORKLOADS, **(BIG if args.big else {}))
    names = (
        [n for n in args.only.split(",") if n in {**WORKLOADS, **BIG}]
        if args.only
        else list(table)
    )
    work = Path(args.keep or tempfile.mkdtemp(prefix="ngc2py-workflows-"))
    work.mkdir(parents=True, exist_ok=True)
    home = work / "home"
    home.mkdir(exist_ok=True)
    py, site_packages = user_python(work)
    env = dict(
        os.environ,
        HOME=str(home),
        NGC2PY_CACHE=str(work / "cache"),
        PYTHONPATH=os.pathsep.join([str(REPO)] + site_packages),
    )
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    has_gcode = (
        subprocess.run(
            [SYSTEM_PYTHON, "-c", "import gcode"], capture_output=True
        ).returncode
        == 0
    )
    (work / "parse.py").write_text(COUNTING_PARSE)
    (work / "user_canon.py").write_text(USER_CANON)
    (work / "canon_calls.py").write_text(CANON_CALLS)
    print(
        "ratio = LinuxCNC's time / ngc2py's (higher is better); medians of %d runs\n"
        % args.repeat
    )
    row = "%-14s %-22s %9s %9s %8s %8s  %s"
    print(
        row % ("workload", "workflow", "LinuxCNC", "ngc2py", "ratio", "peakMB", "note")
    )
    try:
        for name in names:
            make, size = {**WORKLOADS, **BIG}[name]
            src = work / f"{name}.ngc"
            src.write_text(make(size))
            ref = timed(
                ["rs274", "-g", src.name, name + ".rs274"], work, env, args.repeat
            )
            rs = med(ref)
            print(
                row % (name, "rs274 -g", "%.2fs" % rs, "", "", "%.0f" % peak(ref), "")
            )
            if has_gcode and name in WORKLOADS:
                theirs, counts = in_process(
                    [SYSTEM_PYTHON, "parse.py", src.name, "gcode"],
                    work,
                    env,
                    args.repeat,
                )
                firsts = []
                for _ in range(args.repeat):  # each on an empty cache: a new file
                    shutil.rmtree(work / "cache", ignore_errors=True)
                    firsts.append(
                        in_process([py, "parse.py", src.name, "ngc2py"], work, env, 1)[
                            0
                        ]
                    )
                first = None if None in firsts else statistics.median(firsts)
                ours, ours_counts = in_process(
                    [py, "parse.py", src.name, "ngc2py"], work, env, args.repeat
                )
                same = (
                    "same calls"
                    if counts == ours_counts
                    else "COUNTS DIFFER %s %s" % (counts, ours_counts)
                )
                if theirs and ours:
                    print(
                        row
                        % (
                            name,
                            "parse (cached)",
                            "%.2fs" % theirs,
                            "%.2fs" % ours,
                            fmt_ratio(theirs, ours),
                            "",
                            same,
                        )
                    )
                if theirs and first:
                    print(
                        row
                        % (
                            name,
                            "parse (first, converts)",
                            "%.2fs" % theirs,
                            "%.2fs" % first,
                            fmt_ratio(theirs, first),
                            "",
                            "",
                        )
                    )
                again, _ = in_process(
                    [SYSTEM_PYTHON, "parse.py", src.name, "gcode", "again"],
                    work,
                    env,
                    args.repeat,
                )
                ours_again, _ = in_process(
                    [py, "parse.py", src.name, "ngc2py", "again"],
                    work,
                    env,
                    args.repeat,
                )
                if again and ours_again:
                    print(
                        row
                        % (
                            name,
                            "parse (reload in process)",
                            "%.2fs" % again,
                            "%.2fs" % ours_again,
                            fmt_ratio(again, ours_again),
                            "",
                            "a preview app's second load of the file",
                        )
                    )
                alone, made = in_process(
                    [py, "canon_calls.py", src.name], work, env, args.repeat
                )
                if theirs and alone:
                    print(
                        row
                        % (
                            name,
                            "parse: canon calls alone",
                            "%.2fs" % theirs,
                            "%.2fs" % alone,
                            fmt_ratio(theirs, alone),
                            "",
                            "%s calls: no parse can be quicker" % made,
                        )
                    )
            Run(
                [py, "-m", "ngc2py", "run", src.name], work, env, None
            )  # warm the cache
            for workflow, cmd in (
                ("stats", [py, "-m", "ngc2py", "stats", src.name]),
                (
                    "flatten",
                    [
                        py,
                        "-m",
                        "ngc2py",
                        "flatten",
                        "-q",
                        src.name,
                        "-o",
                        name + ".flat.ngc",
                    ],
                ),
                ("plot", [py, "-m", "ngc2py", "plot", src.name, "-o", name + ".png"]),
                ("ngc2py.toolpath()", [py, "-c", TOOLPATH, src.name]),
            ):
                if workflow == "plot" and name.startswith("loop"):
                    continue
                if workflow == "flatten" and name == "cam_1m":
                    continue
                runs = timed(cmd, work, env, args.repeat)
                note = "" if runs[0].status == 0 else "exit %d" % runs[0].status
                print(
                    row
                    % (
                        name,
                        workflow,
                        "%.2fs" % rs,
                        "%.2fs" % med(runs),
                        fmt_ratio(rs, med(runs)),
                        "%.0f" % peak(runs),
                        note,
                    )
                )
            if name in WORKLOADS:
                proc = subprocess.run(
                    [py, "user_canon.py", src.name],
                    cwd=work,
                    env=env,
                    capture_output=True,
                    text=True,
                )
                parts = proc.stdout.split()
                if len(parts) == 3 and int(parts[2]):
                    null, counting, moves = (
                        float(parts[0]),
                        float(parts[1]),
                        int(parts[2]),
                    )
                    print(
                        row
                        % (
                            name,
                            "user Canon subclass",
                            "",
                            "%.2fs" % counting,
                            "",
                            "",
                            "%.2f us/move with NullCanon, %.2f more counting"
                            " (%d moves)"
                            % (
                                null / moves * 1e6,
                                (counting - null) / moves * 1e6,
                                moves,
                            ),
                        )
                    )
        if not args.no_golden:
            library = REPO / "golden"
            count = sum(
                1 for p in library.rglob("*.ngc") if p.with_suffix(".rc").exists()
            )
            theirs = rs274_each(library, home)

            def library_row(workflow, runs, note, failed):
                # (a run that did not pass says so)
                ours = med(runs)
                note += "" if runs[0].status == 0 else "; " + failed
                cells = ("golden/ (%d)" % count, workflow, "%.2fs" % theirs)
                cells += ("%.2fs" % ours, fmt_ratio(theirs, ours), "%.0f" % peak(runs))
                print(row % (cells + (note,)))

            check = [py, "-m", "ngc2py", "golden", "check", "-q", str(library)]
            Run(check, work, env, None)  # warm the cache
            runs = timed(check, work, env, args.repeat)
            library_row(
                "golden check (warm)", runs, "rs274 -g on each program", "CHANGED"
            )
            # the same recordings as pytest tests: ngc2py's plugin alone (other
            # plugins this machine has installed would be timed too), no ini
            # file of this project's, one process
            copy = work / "golden-copy"
            shutil.rmtree(copy, ignore_errors=True)
            shutil.copytree(library, copy)
            (work / "empty.ini").write_text("[pytest]\n")
            tests = [
                py,
                "-m",
                "pytest",
                "-q",
                "-p",
                "no:cacheprovider",
                "-p",
                "ngc2py.pytest_plugin",
                "-c",
                str(work / "empty.ini"),
                "--rootdir",
                str(copy),
                str(copy),
            ]
            plugin_env = dict(env, PYTEST_DISABLE_PLUGIN_AUTOLOAD="1")
            runs = timed(tests, work, plugin_env, args.repeat)
            library_row(
                "pytest plugin (warm)", runs, "the same, as pytest items", "FAILED"
            )
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
