"""ngc2py: compile LinuxCNC G-code into readable Python modules."""

__version__ = "0.1.0"


def parse(filename, canon, *args, **options):
    """LinuxCNC's ``gcode.parse``, on ngc2py: see :mod:`ngc2py.preview`."""
    from ngc2py.preview import parse as run

    return run(filename, canon, *args, **options)


def strerror(code):
    """The message of the last error :func:`parse` returned (``gcode.strerror``)."""
    from ngc2py.preview import strerror as message

    return message(code)


def toolpath(program, **options):
    """A program's moves as NumPy arrays: see :mod:`ngc2py.moves`."""
    from ngc2py.moves import toolpath as run

    return run(program, **options)
