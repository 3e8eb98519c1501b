"""arc_inches.ngc, compiled by ngc2py 0.1.0. Edit the .ngc, not this file."""

from runtime import Machine, SourceMap, run_cli
from runtime.codes import G0, G2, G3, G90, M2


def main(m: Machine) -> None:
    """The main program."""
    p, g, v = m.params, m.globals, m.locals
    # 1: G20 G90 F10
    m.block(1, G90, f=10.0)
    # 2: G0 X1 Y0
    m.block(2, G0, x=1.0, y=0.0)
    # 3: G3 X0 Y1 I-1 J0
    m.block(3, G3, x=0.0, y=1.0, i=-1.0, j=0.0)
    # 4: G2 X-1 Y0 R1
    m.block(4, G2, x=-1.0, y=0.0, r=1.0)
    # 5: M2
    m.block(5, M2)
    # end of file, no program end
    m.fail(5, "File ended with no percent sign or program end")


__ngc__ = SourceMap(
    ("golden/arcs/arc_inches.ngc",),
    "11,0,1;13,0,2;15,0,3;17,0,4;19,0,5;21,0,5",
    ("G20 G90 F10\nG0 X1 Y0\nG3 X0 Y1 I-1 J0\nG2 X-1 Y0 R1\nM2",),
    {},
    (5, False),
)


def run(canon=None, **options):
    """Run the program against ``canon`` (default: the rs274 trace)."""
    return Machine(canon, source=__ngc__, **options).run(main)


if __name__ == "__main__":
    raise SystemExit(run_cli(main, __ngc__))
