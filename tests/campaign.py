"""A differential campaign run by hand: many fresh programs per profile, each
run by rs274 and by ngc2py, with per-profile figures and the mismatches kept.

Not part of the test suite (pytest collects ``test_*.py`` only). The programs
are drawn by the same generators the differential tests use
(tests/strategies.py, tests/long_programs.py), from a seed of your choice, so
a campaign with a new seed sees programs CI never saw::

    nice -n 10 python tests/campaign.py --seed 7 --count 2000 --jobs 2 \\
        --out /tmp/campaign valid invalid comp subfiles
    python tests/campaign.py --list            # the profiles

Every run happens in a scratch copy of the program's folder with its own
HOME (tests/rs274.py), rs274 first: a program rs274 hangs or crashes on is
counted as ``rejected`` (no reference), not compared. ngc2py runs in-process
(``ngc2py run``, as ``ngc2py golden`` runs it) in worker processes.

For each mismatch, ``OUT/<profile>/<n>/`` holds the program's files, the
options (``args``) and the differences (``diff.txt``); for each program
rs274 hung or crashed on, ``OUT/<profile>/rejected/<n>/`` holds its files
and why (``diff.txt``: the time-out or the signal); ``OUT/summary.txt``
holds the figures.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import multiprocessing
import os
import re
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import rs274 as harness  # noqa: E402

_COMP_TABLE = harness.GOLDEN / "cutter_comp" / "tools.tbl"


def _text(text):
    return {"prog.ngc": text}, []


def _text_args(program):
    text, args = program
    return {"prog.ngc": text}, list(args)


def _with_table(program):
    text, table = program
    return {"job.ngc": text, "tools.tbl": table}, ["-t", "tools.tbl"]


def _comp_table(text):
    return {"prog.ngc": text, "tools.tbl": _COMP_TABLE.read_text()}, ["-t", "tools.tbl"]


def _subfiles(program):
    files, args = program
    return dict(files), list(args)


def _cam_rotary():
    """CAM rows (A, B, C words among them) under wrapped axes and indexers."""
    import cam_strategies
    import strategies as s
    from hypothesis import strategies as st

    def files(drawn):
        text, ini = drawn
        return {"prog.ngc": text, "rotary.ini": ini}, ["-i", "rotary.ini"]

    return st.tuples(cam_strategies.cam_programs(), s.rotary_inis()).map(files)


def _with_spindles(program):
    import strategies

    text, count = program
    return {"prog.ngc": text, "m.ini": strategies.spindles_ini(count)}, ["-i", "m.ini"]


def _cam_shop():
    """What shops' programs add to CAM rows: comments after a move's or an
    arc's words, holes drilled a line at a time with a G4 pause, and modes
    restated on every line (G90 G1, G17 G2)."""
    import cam_strategies as c

    cam = c.cam_programs() | c.arc_programs()
    return c.commented(cam) | c.hand_drilling() | c.restating(cam)


def _holes():
    """Rows of holes the replay takes (runtime.fast.hole_rows): tables of
    hole words, numbered or not, series drilled alike, restated cycle lines."""
    from hypothesis import strategies as st

    import test_cycles as t

    return st.one_of(
        t.cycle_tables(), t.series_drilled_alike(), t.restated_cycle_lines()
    )


def _profiles():
    import strategies as s

    # name: (strategy, how a drawn example becomes files and options,
    #        the program's file name, rs274's time limit)
    return {
        "valid": (s.valid_programs(), _text, "prog.ngc", 20),
        "valid_feed": (s.valid_programs(feed_modes=True), _text, "prog.ngc", 20),
        "cycles": (s.cycle_programs(), _text, "prog.ngc", 20),
        "holes": (_holes(), _text, "prog.ngc", 20),
        "invalid": (s.invalid_programs(), _text, "prog.ngc", 20),
        "language": (s.language_programs(), _text_args, "prog.ngc", 5),
        "whole": (s.whole_language_programs(), _with_table, "job.ngc", 20),
        "broken_whole": (
            s.broken_whole_language_programs(),
            _with_table,
            "job.ngc",
            20,
        ),
        "long": (s.long_programs(), _text_args, "prog.ngc", 20),
        "long_error": (s.long_error_programs(), _text_args, "prog.ngc", 20),
        "subfiles": (s.subroutine_file_programs(), _subfiles, "main.ngc", 20),
        "comp": (s.compensated_programs(), _text, "prog.ngc", 20),
        "comp_table": (
            s.compensated_programs(tool_table=True),
            _comp_table,
            "prog.ngc",
            20,
        ),
        "rotary": (s.rotary_programs(), _subfiles, "prog.ngc", 20),
        "cam_rotary": (_cam_rotary(), _subfiles, "prog.ngc", 20),
        "cam_shop": (_cam_shop(), _text, "prog.ngc", 20),
        "spindles": (s.spindle_ini_programs(), _with_spindles, "prog.ngc", 20),
        "valid_spindles": (s.valid_spindle_programs(), _with_spindles, "prog.ngc", 20),
    }


def draw(strategy, count: int, seed: int) -> list:
    """``count`` examples of ``strategy`` drawn by Hypothesis from ``seed``
    (generation only: no shrinking, no database)."""
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as with_seed

    found = []

    @with_seed(seed)
    @settings(
        max_examples=count,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def collect(example):
        found.append(example)

    collect()
    return found


_SCRATCH_DIR = re.compile(r"(EOF in file:|already defined in file:)/\S*?/subs/")


def _portable(result):
    return dataclasses.replace(
        result, err=_SCRATCH_DIR.sub(r"\1<dir>/subs/", result.err)
    )


def compare_one(job):
    """Run one program both ways: (profile, index, status, differences)."""
    profile, index, files, args, main, timeout = job
    with tempfile.TemporaryDirectory() as tmp:
        for name, text in files.items():
            path = Path(tmp) / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        program = Path(tmp) / main
        expected = harness.run_rs274(program, args, timeout=timeout)
        if expected.timed_out or (expected.rc is not None and expected.rc < 0):
            why = (
                f"timed out after {timeout} s"
                if expected.timed_out
                else f"signal {-expected.rc}"
            )
            return profile, index, "rejected", why
        try:
            actual = harness.run_ngc2py(
                program, args, mode="inprocess", timeout=timeout * 6
            )
        except BaseException as exc:  # noqa: BLE001 - a campaign reports everything
            return profile, index, "mismatch", f"ngc2py raised {exc!r}"
    problems = harness.compare(_portable(expected), _portable(actual))
    if problems:
        return profile, index, "mismatch", "\n".join(problems)
    return profile, index, "match", ""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("profiles", nargs="*")
    parser.add_argument("--seed", type=int, default=int(time.time()))
    parser.add_argument("--count", type=int, default=500)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", default="campaign-out")
    parser.add_argument("--list", action="store_true")
    opts = parser.parse_args(argv)
    profiles = _profiles()
    if opts.list or not opts.profiles:
        print("profiles:", " ".join(profiles))
        return 0
    out = Path(opts.out)
    out.mkdir(parents=True, exist_ok=True)
    summary = []
    for name in opts.profiles:
        strategy, convert, main_name, timeout = profiles[name]
        start = time.time()
        examples = draw(strategy, opts.count, opts.seed)
        seen, jobs = set(), []
        for example in examples:
            files, args = convert(example)
            key = json.dumps([files, args], sort_keys=True)
            if key in seen:
                continue
            seen.add(key)
            jobs.append((name, len(jobs), files, args, main_name, timeout))
        counts = {"match": 0, "mismatch": 0, "rejected": 0}
        with multiprocessing.Pool(opts.jobs, maxtasksperchild=200) as pool:
            for profile, index, status, diff in pool.imap_unordered(
                compare_one, jobs, chunksize=4
            ):
                counts[status] += 1
                if status != "match":
                    # mismatches, and the programs rs274 hangs or crashes on
                    # (to check they really are: OUT/<profile>/rejected/)
                    folder = out / profile / str(index)
                    if status == "rejected":
                        folder = out / profile / "rejected" / str(index)
                    folder.mkdir(parents=True, exist_ok=True)
                    files, args = jobs[index][2], jobs[index][3]
                    for fname, text in files.items():
                        (folder / fname).parent.mkdir(parents=True, exist_ok=True)
                        (folder / fname).write_text(text)
                    (folder / "args").write_text(" ".join(args) + "\n")
                    (folder / "diff.txt").write_text(diff + "\n")
        line = (
            f"{name}: seed {opts.seed}, {len(jobs)} programs, {counts['match']} match,"
            f" {counts['mismatch']} mismatch, {counts['rejected']} rejected by rs274"
            f" ({time.time() - start:.0f} s)"
        )
        print(line, flush=True)
        summary.append(line)
        with open(out / "summary.txt", "a") as fh:
            fh.write(line + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
