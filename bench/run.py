#!/usr/bin/env python3
"""ngc2py against LinuxCNC's rs274, side by side.

    python bench/run.py [--quick] [--repeat N] [--only NAME,...] [--keep DIR]

Generates the workloads (bench/workloads.py: CAM files of 10k, 100k and 1M
moves, 100k centre-format arcs, a 200k-iteration trigonometry loop, 100k
subroutine calls, canned drilling (rows of hole words, numbered or not, and
a cycle line a hole), a pocketing job, a shop's program of
commented moves, restated modes and hand drilling) into a temporary folder
and, for each one:

* converts it once (``ngc2py convert``: time and peak memory);
* runs ``rs274 -g PROG OUT`` and ``python PROG.py > OUT`` (cold: Python
  compiles a script on every run) and ``ngc2py run PROG`` (warm compile
  cache), alternating, ``--repeat`` times each; prints median wall-clock
  seconds, the ratio rs274 / ngc2py (higher is better: 2.0 means ngc2py takes
  half the time) and whether the traces are identical;
* trace-free: LinuxCNC's preview API ``gcode.parse`` with a do-nothing canon
  (in the system Python, when it has LinuxCNC's ``gcode`` module) against
  the converted module imported and run against ``runtime.canon.NullCanon``.

Then how time per line grows from 10k to 1M lines, and the 1M-line file's
convert-then-run total against rs274's run. ``--quick`` leaves out the
1M-line file. Timings belong here, never in the test suite.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
import workloads  # noqa: E402  (bench/ is not a package)

REPO = Path(__file__).resolve().parent.parent
SYSTEM_PYTHON = "/usr/bin/python3"  # where LinuxCNC's gcode module lives

#: name -> (generator, size, trace-free comparison too?)
WORKLOADS = {
    "cam_10k": (workloads.cam, 10_000, False),
    "cam_100k": (workloads.cam, 100_000, True),
    "arcs_100k": (workloads.arcs, 100_000, False),
    "loop_200k": (workloads.loop, 200_000, True),
    "calls_100k": (workloads.calls, 100_000, False),
    "drill_5k": (workloads.drilling, 5_000, False),
    "cam_arcs_100k": (workloads.cam_arcs, 100_000, True),
    "cycles_20k": (workloads.drill_cycles, 20_000, True),
    "cycle_lines_20k": (workloads.drill_lines, 20_000, True),
    "cycles_n_20k": (workloads.drill_cycles_numbered, 20_000, False),
    "pocket_40": (workloads.pocket, 40, False),
    "shop_20k": (workloads.shop, 20_000, False),
    # Last: generating it grows this process, and a child's peak memory (as
    # the kernel reports it) starts from the parent it was forked from.
    "cam_1m": (workloads.cam, 1_000_000, False),
}

GCODE_PARSE = """\
import sys, time, gcode
ANSWERS = {"get_external_angular_units": 1.0, "get_external_length_units": 0.03937007874016,
           "get_axis_mask": 0x3F, "get_block_delete": False, "check_abort": False}
class Canon:
    def __getattr__(self, name):
        if name.startswith("__") or name == "parameter_file":  # optional ones
            raise AttributeError(name)
        if name in ANSWERS:
            return lambda *args: ANSWERS[name]
        if name == "get_tool":
            return lambda pocket: (pocket,) + (0.0,) * 12 + (0,)
        return lambda *args: None
start = time.perf_counter()
gcode.parse(sys.argv[1], Canon(), "G21", "")
print(time.perf_counter() - start)
"""

NULL_RUN = """\
import sys, time, importlib
start = time.perf_counter()
sys.path.insert(0, sys.argv[1])
module = importlib.import_module(sys.argv[2])
from runtime.canon import NullCanon
module.run(NullCanon())
print(time.perf_counter() - start)
"""


class Run:
    """One child process: wall seconds, peak memory (MB), exit status, output."""

    def __init__(self, cmd: List[str], cwd: Path, env: dict, stdout_to: Optional[Path]):
        start = time.perf_counter()
        with open(stdout_to or os.devnull, "wb") as out:
            proc = subprocess.Popen(
                cmd, cwd=cwd, env=env, stdout=out, stderr=subprocess.DEVNULL
            )
            _, status, usage = os.wait4(proc.pid, 0)
        self.seconds = time.perf_counter() - start
        self.peak_mb = usage.ru_maxrss / 1024
        self.status = os.waitstatus_to_exitcode(status)
        proc.returncode = self.status


def median_runs(makers, repeat: int) -> List[List[Run]]:
    """Run each command maker ``repeat`` times, alternating between them."""
    results: List[List[Run]] = [[] for _ in makers]
    for _ in range(repeat):
        for i, make in enumerate(makers):
            results[i].append(make())
    return results


def med(runs: List[Run]) -> float:
    return statistics.median(r.seconds for r in runs)


def peak(runs: List[Run]) -> float:
    return max(r.peak_mb for r in runs)


def fmt_ratio(reference: float, ours: float) -> str:
    return "%.2fx" % (reference / ours) if ours > 0 else "-"


def same_file(a: Path, b: Path) -> str:
    try:
        with open(a, "rb") as fa, open(b, "rb") as fb:
            while True:
                ca, cb = fa.read(1 << 20), fb.read(1 << 20)
                if ca != cb:
                    return "DIFFERS"
                if not ca:
                    return "identical"
    except OSError:
        return "missing"


def user_python(work: Path) -> Tuple[str, List[str]]:
    """A Python as a user's ``pip install .`` leaves it: a venv of this
    interpreter, without the start-up hooks of this machine's own
    site-packages (``.pth`` files such as an editable install's import
    finder, which cost a cold run tens of milliseconds a user does not pay).
    The dependencies are found in this interpreter's site-packages, through
    PYTHONPATH; returns the venv's python and those folders.

    The packages' bytecode is written first, as ``pip install`` writes it:
    otherwise the first run after an edit compiles the compiler itself (a
    few tenths of a second), which a first parse would be charged with."""
    import site

    venv = work / "venv"
    if not (venv / "bin" / "python").exists():
        subprocess.run(
            [sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True
        )
    python = str(venv / "bin" / "python")
    subprocess.run(
        [python, "-m", "compileall", "-q", str(REPO / "ngc2py"), str(REPO / "runtime")],
        env={k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"},
        check=True,
    )
    return python, site.getsitepackages()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument(
        "--quick", action="store_true", help="leave out the 1M-line CAM file"
    )
    ap.add_argument(
        "--repeat", type=int, default=3, help="runs of each command (default 3)"
    )
    ap.add_argument(
        "--only", help="comma-separated workload names: " + ", ".join(WORKLOADS)
    )
    ap.add_argument("--keep", help="write the programs and outputs here and keep them")
    args = ap.parse_args(argv)

    names = list(WORKLOADS)
    if args.only:
        names = [n for n in args.only.split(",") if n in WORKLOADS]
    elif args.quick:
        names.remove("cam_1m")
    rs274 = shutil.which("rs274")
    has_gcode = (
        os.path.exists(SYSTEM_PYTHON)
        and subprocess.run(
            [SYSTEM_PYTHON, "-c", "import gcode"], capture_output=True
        ).returncode
        == 0
    )
    work = Path(args.keep or tempfile.mkdtemp(prefix="ngc2py-bench-"))
    work.mkdir(parents=True, exist_ok=True)
    home = work / "home"
    home.mkdir(exist_ok=True)
    cache = work / "cache"
    py, site_packages = user_python(work)
    path = os.pathsep.join([str(REPO)] + site_packages)
    env = dict(os.environ, HOME=str(home), PYTHONPATH=path, NGC2PY_CACHE=str(cache))
    # Measure what a user's machine does: Python keeps the runtime's bytecode
    # in __pycache__ (pip install writes it too). A sandbox that forbids that
    # would charge every run for recompiling the runtime package.
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    subprocess.run(
        [py, "-c", "import runtime.machine, ngc2py.cli"], env=env, cwd=str(REPO)
    )
    print(
        "rs274: %s   gcode.parse: %s"
        % (
            rs274 or "not installed",
            "yes" if has_gcode else "no (system Python lacks LinuxCNC's gcode)",
        )
    )
    print(
        "python: %s in a bare venv (as `pip install .` leaves it), start-up %.3fs\n"
        % (
            sys.version.split()[0],
            med([Run([py, "-c", "pass"], work, env, None) for _ in range(5)]),
        )
    )
    print(
        "ratio = rs274's time / ngc2py's time (higher is better); medians of %d alternating runs\n"
        % args.repeat
    )
    head = "%-11s %8s %9s %8s %9s %8s %9s %8s %7s  %s" % (
        "workload",
        "lines",
        "convert",
        "rs274",
        "prog.py",
        "ratio",
        "run",
        "ratio",
        "peakMB",
        "trace",
    )
    print(head)
    print("-" * len(head))
    per_line: Dict[str, float] = {}
    convert_times: Dict[str, float] = {}
    rs274_times: Dict[str, float] = {}
    preview: List[Tuple[str, float, float]] = []
    try:
        for name in names:
            make, size, trace_free = WORKLOADS[name]
            src = work / f"{name}.ngc"
            src.write_text(make(size))
            lines = sum(1 for _ in open(src))
            module = work / f"{name}.py"
            conv = Run(
                [py, "-m", "ngc2py", "convert", src.name, "-o", module.name],
                work,
                env,
                None,
            )
            if conv.status != 0:
                print(
                    "%-11s %8d  convert failed (exit %d): not supported yet?"
                    % (name, lines, conv.status)
                )
                continue
            convert_times[name] = conv.seconds
            # fill the compile cache once: 'ngc2py run' below is the warm case
            Run([py, "-m", "ngc2py", "run", src.name], work, env, None)
            ref_out, cold_out, warm_out = (
                work / f"{name}.rs274",
                work / f"{name}.cold",
                work / f"{name}.warm",
            )
            makers = [
                lambda: Run([py, module.name], work, env, cold_out),
                lambda: Run([py, "-m", "ngc2py", "run", src.name], work, env, warm_out),
            ]
            if rs274:
                makers.insert(
                    0,
                    lambda: Run([rs274, "-g", src.name, ref_out.name], work, env, None),
                )
            results = median_runs(makers, args.repeat)
            if rs274:
                ref, cold, warm = results
                ref_s = med(ref)
                rs274_times[name] = ref_s
                trace = (
                    "identical"
                    if same_file(ref_out, cold_out)
                    == "identical"
                    == same_file(ref_out, warm_out)
                    else "DIFFERS"
                )
                if ref[0].status != cold[0].status:
                    trace += " (exit %d vs %d)" % (ref[0].status, cold[0].status)
                print(
                    "%-11s %8d %8.2fs %7.2fs %8.2fs %8s %8.2fs %8s %7.0f  %s"
                    % (
                        name,
                        lines,
                        conv.seconds,
                        ref_s,
                        med(cold),
                        fmt_ratio(ref_s, med(cold)),
                        med(warm),
                        fmt_ratio(ref_s, med(warm)),
                        max(peak(cold), peak(warm), conv.peak_mb),
                        trace,
                    )
                )
            else:
                cold, warm = results
                print(
                    "%-11s %8d %8.2fs %8s %8.2fs %8s %8.2fs %8s %7.0f  (no rs274)"
                    % (
                        name,
                        lines,
                        conv.seconds,
                        "-",
                        med(cold),
                        "-",
                        med(warm),
                        "-",
                        max(peak(cold), peak(warm), conv.peak_mb),
                    )
                )
            if name.startswith("cam_"):
                per_line[name] = med(cold) / lines
            if trace_free and has_gcode:
                ours, theirs = [], []
                for _ in range(args.repeat):
                    for cmd, into in (
                        ([SYSTEM_PYTHON, "-c", GCODE_PARSE, src.name], theirs),
                        ([py, "-c", NULL_RUN, str(work), name], ours),
                    ):
                        proc = subprocess.run(
                            cmd, cwd=work, env=env, capture_output=True, text=True
                        )
                        if proc.returncode == 0 and proc.stdout.strip():
                            into.append(float(proc.stdout.split()[-1]))
                if ours and theirs:
                    preview.append(
                        (name, statistics.median(theirs), statistics.median(ours))
                    )
        if preview:
            print(
                "\ntrace-free: gcode.parse (do-nothing canon) against module.run(NullCanon())"
            )
            for name, theirs, ours in preview:
                print(
                    "  %-11s gcode.parse %7.2fs   NullCanon %7.2fs   ratio %s"
                    % (name, theirs, ours, fmt_ratio(theirs, ours))
                )
        if len(per_line) > 1:
            print(
                "\ngrowth (python PROG.py, microseconds per line):",
                "  ".join("%s %.2f" % (n, t * 1e6) for n, t in per_line.items()),
            )
        if "cam_1m" in convert_times and "cam_1m" in rs274_times:
            total = convert_times["cam_1m"] + per_line["cam_1m"] * sum(
                1 for _ in open(work / "cam_1m.ngc")
            )
            print(
                "\n1M-line CAM file: convert + first run %.2fs against rs274 %.2fs (ratio %s)"
                % (
                    total,
                    rs274_times["cam_1m"],
                    fmt_ratio(rs274_times["cam_1m"], total),
                )
            )
    finally:
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
