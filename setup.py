"""The one thing pyproject.toml cannot say: runtime's optional C extension.

``runtime._libm_trig`` computes SIN/COS/TAN as rs274 does, ten times faster
than the ctypes path of runtime/x87.py. It is optional: without a C compiler
and Python's headers the build skips it and the runtime uses ctypes.
"""

from setuptools import Extension, setup

setup(
    ext_modules=[
        Extension(
            "runtime._libm_trig",
            ["runtime/_libm_trig.c"],
            libraries=["m"],
            optional=True,
        )
    ]
)
