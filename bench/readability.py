#!/usr/bin/env python3
"""How readable the generated modules are (issue 13), over folders of G-code.

    python bench/readability.py [--no-black] [--worst N] [DIR ...]

Converts every ``.ngc`` under the folders (default: ``golden/`` and
LinuxCNC's samples in ``/usr/share/linuxcnc/ncfiles``), each from its own
folder (the program prefix rs274 looks for subroutine files in), and prints
for each folder and for all together:

* programs: how many converted (and how many failed to);
* code/G-code lines: a module's lines before its source map (``__ngc__``,
  or a compressed G-code text before it) over its G-code file's lines,
  mean and median;
* locals in Python variables: of the modules whose G-code names local
  parameters (``#<name>``, not ``#<_global>``), the share whose generated
  code never reaches them through the locals store (``v.name``,
  ``v["name"]``; ``v.exists``/``v.declare``/``v.read_or_zero`` count as
  the store too);
* tabs: tab characters and ``\\x09`` escapes in the modules;
* not black-stable: modules that black would change (``--no-black`` skips
  this, the slowest part).

Nothing is written into the folders. Figures, not timings: this is not a
benchmark and is safe to run anywhere.
"""

from __future__ import annotations

import argparse
import os
import re
import statistics
import sys
from pathlib import Path
from typing import Dict, List, Optional

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from ngc2py.compiler import CompileError, compile_file  # noqa: E402

DEFAULT_DIRS = [str(ROOT / "golden"), "/usr/share/linuxcnc/ncfiles"]

#: A read or setting of a local through the store: ``v.name`` or ``v[...]``.
STORE_LOCAL = re.compile(r"(?<![\w.])v(\.[A-Za-z_]\w*|\[)")
#: A named local in the G-code (a global starts with ``_``).
GCODE_LOCAL = re.compile(rb"#\s*<\s*[^_\s>]")
SOURCE_MAP = re.compile(r"^(__ngc__ = |# The G-code text of )", re.M)


def code_lines(module: str) -> int:
    """Lines of ``module`` before its source map."""
    found = SOURCE_MAP.search(module)
    head = module[: found.start()] if found else module
    return head.count("\n")


def gcode_lines(data: bytes) -> int:
    return data.count(b"\n") + (not data.endswith(b"\n") and bool(data))


def measure(path: Path, black_check: bool) -> Optional[Dict[str, object]]:
    data = path.read_bytes()
    here = os.getcwd()
    try:
        os.chdir(path.parent)
        module = compile_file(path.name)
    except (CompileError, RecursionError):
        return None
    finally:
        os.chdir(here)
    result: Dict[str, object] = {
        "path": str(path),
        "ratio": code_lines(module) / max(gcode_lines(data), 1),
        "has_locals": bool(GCODE_LOCAL.search(data)),
        "store": bool(STORE_LOCAL.search(module[: SOURCE_MAP.search(module).start()])),
        "tabs": module.count("\t") + module.count("\\x09"),
        "unstable": False,
    }
    if black_check:
        import black

        try:
            stable = black.format_str(module, mode=black.Mode()) == module
        except Exception:  # black cannot even read it
            stable = False
        result["unstable"] = not stable
    return result


def report(name: str, results: List[Dict[str, object]], failed: int, worst: int) -> None:
    print("== %s" % name)
    print("programs: %d converted, %d failed to convert" % (len(results), failed))
    if not results:
        return
    ratios = [r["ratio"] for r in results]
    print(
        "code/G-code lines: mean %.2f, median %.2f, share <= 1.5: %.0f%%"
        % (
            statistics.mean(ratios),
            statistics.median(ratios),
            100.0 * sum(x <= 1.5 for x in ratios) / len(ratios),
        )
    )
    local = [r for r in results if r["has_locals"]]
    if local:
        python = sum(not r["store"] for r in local)
        print(
            "locals in Python variables: %.0f%% of %d modules with named locals"
            % (100.0 * python / len(local), len(local))
        )
    print("tabs (\\t or \\x09) in modules: %d" % sum(r["tabs"] for r in results))
    print("not black-stable: %d" % sum(r["unstable"] for r in results))
    for r in results:
        if r["unstable"]:
            print("  not black-stable: %s" % r["path"])
    for r in sorted(results, key=lambda r: -r["ratio"])[:worst]:
        print("  %.2f %s" % (r["ratio"], r["path"]))
    if worst:
        for r in local:
            if r["store"]:
                print("  store: %s" % r["path"])


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dirs", nargs="*", default=DEFAULT_DIRS)
    parser.add_argument("--no-black", action="store_true")
    parser.add_argument("--worst", type=int, default=0, help="list the N worst")
    args = parser.parse_args(argv)
    sys.setrecursionlimit(10000)
    everything: List[Dict[str, object]] = []
    failed_total = 0
    for folder in args.dirs:
        results, failed = [], 0
        for path in sorted(Path(folder).rglob("*.ngc")):
            if not path.is_file():
                continue
            measured = measure(path, not args.no_black)
            if measured is None:
                failed += 1
            else:
                results.append(measured)
        report(folder, results, failed, args.worst)
        everything += results
        failed_total += failed
    if len(args.dirs) > 1:
        report("all", everything, failed_total, 0)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
