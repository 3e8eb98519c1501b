#!/usr/bin/env python3
"""Re-record the golden expectations from the reference rs274.

    python golden/record.py              # every golden program
    python golden/record.py golden/oword golden/params/named.ngc

For each program ``golden/<feature>/<name>.ngc`` this runs
``rs274 -g [options from <name>.args] <name>.ngc`` in a scratch copy of the
program's folder with its own HOME (see tests/rs274.py) and writes

    <name>.out   rs274's stdout, byte for byte
    <name>.err   rs274's error message (first stderr line that is not
                 "executing"), or empty
    <name>.rc    rs274's exit status

Programs are run in parallel with a process pool. Not recorded:

* helper files (external subroutines called by other programs): their first
  line contains ``(helper`` ;
* programs with a ``<name>.expect`` file (rs274 crashes or hangs on them; see
  golden/README.md): for those, rs274's stdout up to the crash is saved as
  ``<name>.partial`` (the expectation's ``stdout_prefix``), and it is reported
  if rs274 no longer crashes or hangs (then the .expect should go);
* programs on which rs274 times out or dies from a signal now: they are
  reported, nothing is written, and the exit status is 2 so the problem is
  not missed.
"""

from __future__ import annotations

import argparse
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

import rs274 as harness  # noqa: E402  (tests/rs274.py)
from ngc2py import golden  # noqa: E402  (the recording format users' golden files share)


def is_helper(path: Path) -> bool:
    try:
        with path.open(errors="replace") as f:
            first = f.readline()
    except OSError:
        return False
    return "(helper" in first.lower()


def collect(targets) -> list:
    programs = []
    roots = [Path(t) for t in targets] or [HERE]
    for root in roots:
        root = root.resolve()
        if root.is_dir():
            candidates = sorted(root.rglob("*.ngc"))
        elif root.suffix == ".ngc":
            candidates = [root]
        else:
            continue  # .out/.err/... from a shell glob: not a program
        for p in candidates:
            if p.parent == HERE:
                continue  # programs live in feature folders
            if is_helper(p):
                continue
            programs.append(p)
    return sorted(set(programs))


def record_one(path_str: str, timeout: float):
    path = Path(path_str)
    result = harness.run_rs274(path, harness.read_args(path), timeout=timeout)
    if path.with_suffix(".expect").exists():
        if result.rc is None or result.rc < 0:
            path.with_suffix(".partial").write_bytes(result.stdout)
            return path_str, "expect", result
        return path_str, "EXPECT-BUT-SANE", result
    if result.rc is None:
        return path_str, "TIMEOUT", result
    if result.rc < 0:
        return path_str, f"SIGNAL {-result.rc}", result
    golden.save(path, result)
    return path_str, "ok", result


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="*", help="programs or folders (default: all of golden/)")
    ap.add_argument("-j", "--jobs", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--timeout", type=float, default=30.0)
    ap.add_argument("-q", "--quiet", action="store_true")
    args = ap.parse_args(argv)

    if harness.rs274_path() is None:
        print("record.py: rs274 not found on PATH (install linuxcnc-uspace)", file=sys.stderr)
        return 1
    programs = collect(args.paths)
    if not programs:
        print("record.py: no programs found", file=sys.stderr)
        return 1

    bad = []
    counts = {"ok": 0, "errors": 0}
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = [pool.submit(record_one, str(p), args.timeout) for p in programs]
        for fut in futures:
            name, status, result = fut.result()
            rel = os.path.relpath(name, HERE)
            if status == "expect":
                what = "hangs" if result.rc is None else f"dies (signal {-result.rc})"
                print(f"{rel}: rs274 still {what}; kept .expect, wrote .partial")
                continue
            if status == "EXPECT-BUT-SANE":
                bad.append((rel, status))
                print(
                    f"{rel}: has a .expect but rs274 now exits normally (rc={result.rc}); "
                    "remove the .expect and re-record",
                    file=sys.stderr,
                )
                continue
            if status != "ok":
                bad.append((rel, status))
                print(f"NOT RECORDED {rel}: rs274 {status}", file=sys.stderr)
                continue
            counts["ok"] += 1
            if result.rc != 0:
                counts["errors"] += 1
            if not args.quiet:
                print(f"{rel}: rc={result.rc} {result.err}")
    print(
        f"recorded {counts['ok']} programs ({counts['errors']} end in an error); "
        f"{len(bad)} not recorded"
    )
    if bad:
        print(
            "rs274 crashed or hung on the programs above: give each a <name>.expect "
            "and list it in golden/README.md",
            file=sys.stderr,
        )
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
