#!/usr/bin/env python3
"""Time LinuxCNC's ``rs274 -g`` against ngc2py's generated modules.

    python bench/run.py [--repeat N] [--moves N]

For each program: rs274 runs it N times; ngc2py compiles it once
(``ngc2py convert``, timed separately) and the generated module runs N times.
Both write to a file (not a terminal) so printing is not what is measured.
The table shows median wall-clock seconds and the ratio ngc2py / rs274, and
whether the two outputs were identical.

Programs (written to a temporary folder at run time):

* ``flange``        -- examples/flange.ngc
* ``loops_subs``    -- nested while/repeat loops calling subroutines with
                       arguments and return values (tens of thousands of calls)
* ``cam_100k``      -- a synthetic CAM file: 100 000 plain G1 moves
* ``arcs_20k``      -- 20 000 centre-format arcs
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

REPO = Path(__file__).resolve().parent.parent


def loops_subs() -> str:
    return """\
(loop and subroutine heavy)
G21 G90 F500
o<cell> sub
  #<acc> = [#1 * 0.5 + #2]
  o<cell> return [#<acc> MOD 97]
o<cell> endsub
o<move> sub
  G1 X[#1 MOD 50] Y[#2 MOD 50]
o<move> endsub
#<_total> = 0
#<i> = 0
o1 while [#<i> LT 120]
  #<j> = 0
  o2 while [#<j> LT 100]
    o<cell> call [#<i>] [#<j>]
    #<_total> = [#<_total> + #<_value>]
    o3 if [[#<j> MOD 10] EQ 0]
      o<move> call [#<i>] [#<j>]
    o3 endif
    #<j> = [#<j> + 1]
  o2 endwhile
  #<i> = [#<i> + 1]
o1 endwhile
(print, total #<_total>)
M2
"""


def cam(moves: int) -> str:
    lines = ["(synthetic CAM output)", "G21 G90 G17 G94", "G0 X0 Y0 Z5", "G1 Z-1 F800"]
    for k in range(moves):
        x = (k * 7919 % 100000) / 1000.0
        y = (k * 104729 % 80000) / 1000.0
        lines.append(f"X{x:.3f} Y{y:.3f}")
    lines += ["G0 Z5", "M2"]
    return "\n".join(lines) + "\n"


def arcs(count: int) -> str:
    lines = ["(many arcs)", "G21 G90 G17 F600", "G0 X10 Y0"]
    for k in range(count):
        code = "G3" if k % 2 == 0 else "G2"
        lines.append(f"{code} X10 Y0 I-10 J0 Z{-(k % 10) / 10:.1f}")
    lines.append("M2")
    return "\n".join(lines) + "\n"


def timed(cmd, cwd, env, repeat):
    times = []
    out = None
    for _ in range(repeat):
        with tempfile.TemporaryFile() as sink:
            start = time.perf_counter()
            proc = subprocess.run(cmd, cwd=cwd, env=env, stdout=sink, stderr=subprocess.PIPE)
            times.append(time.perf_counter() - start)
            sink.seek(0)
            out = (sink.read(), proc.returncode)
    return statistics.median(times), out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--moves", type=int, default=100_000)
    args = ap.parse_args(argv)

    rs274 = shutil.which("rs274")
    work = Path(tempfile.mkdtemp(prefix="ngc2py-bench-"))
    home = work / "home"
    home.mkdir()
    env = dict(os.environ, HOME=str(home), PYTHONPATH=str(REPO))
    programs = {
        "flange": (REPO / "examples" / "flange.ngc").read_text(),
        "loops_subs": loops_subs(),
        f"cam_{args.moves // 1000}k": cam(args.moves),
        "arcs_20k": arcs(20_000),
    }
    print(f"{'program':<12} {'rs274 s':>9} {'compile s':>10} {'module s':>9} {'ratio':>7}  same output")
    try:
        for name, text in programs.items():
            src = work / f"{name}.ngc"
            src.write_text(text)
            module = work / f"{name}.py"
            start = time.perf_counter()
            conv = subprocess.run(
                [sys.executable, "-m", "ngc2py", "convert", src.name, "-o", str(module)],
                cwd=work, env=env, capture_output=True,
            )
            compile_s = time.perf_counter() - start
            if conv.returncode != 0:
                err = conv.stderr.decode(errors="replace").strip().splitlines()
                print(f"{name:<12} ngc2py convert failed: {err[-1] if err else conv.returncode}")
                continue
            mod_s, mod_out = timed([sys.executable, str(module)], work, env, args.repeat)
            if rs274:
                ref_s, ref_out = timed([rs274, "-g", src.name], work, env, args.repeat)
                same = "yes" if ref_out == mod_out else "NO"
                print(f"{name:<12} {ref_s:9.3f} {compile_s:10.3f} {mod_s:9.3f} {mod_s / ref_s:7.2f}  {same}")
            else:
                print(f"{name:<12} {'(none)':>9} {compile_s:10.3f} {mod_s:9.3f} {'-':>7}  (rs274 not installed)")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
