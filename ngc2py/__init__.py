"""ngc2py: compile LinuxCNC G-code into readable Python modules."""

__version__ = "0.1.0"
