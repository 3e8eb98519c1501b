"""The one thing pyproject.toml cannot say: runtime's optional C extensions.

``runtime._libm_trig`` computes SIN/COS/TAN as rs274 does, ten times faster
than the ctypes path of runtime/x87.py. ``runtime._fast_format`` makes trace
lines (``template % args``) without Python's general float formatting.
``runtime.fast._arc_row`` runs a contour's rows; ``runtime._arc_stats`` adds
up a batch of arcs for ``ngc2py stats``. ``runtime._call_rows`` makes a
batch's canon calls from its columns (the preview's). ``ngc2py._rowtext`` writes a CAM
file's table rows in one pass when it is converted. All are optional: without a C
compiler and Python's headers the build skips them and the runtime runs its
pure-Python equivalents, with identical results."""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "runtime._libm_trig",
            ["runtime/_libm_trig.c"],
            depends=["runtime/plain_decimal.h"],
            libraries=["m"],
            optional=True,
        ),
        Extension(
            "runtime._fast_format",
            ["runtime/_fast_format.c"],
            libraries=["m"],
            # p = x * 10000 must be rounded on its own: _fast_format.c takes
            # its exact error with fma().
            extra_compile_args=["-ffp-contract=off"],
            optional=True,
        ),
        Extension(
            "runtime.fast._arc_row",
            ["runtime/fast/_arc_row.c"],
            depends=["runtime/plain_decimal.h"],
            libraries=["m"],
            # rs274's arithmetic has no fused multiply-adds: neither may this
            extra_compile_args=["-ffp-contract=off"],
            optional=True,
        ),
        Extension("runtime._call_rows", ["runtime/_call_rows.c"], optional=True),
        Extension("ngc2py._rowtext", ["ngc2py/_rowtext.c"], optional=True),
        Extension(
            "runtime._arc_stats",
            ["runtime/_arc_stats.c"],
            libraries=["m"],
            # the same doubles as runtime/stats.py's Python: no fused steps
            extra_compile_args=["-ffp-contract=off"],
            optional=True,
        ),
    ]
)
