"""The ``-b`` option every command takes, as rs274 takes it.

rs274's own option loop flips block delete at each ``-b`` (``-b -b`` is
off again), and so does a generated module's command line
(runtime.main.parse_options); the commands say the same.
"""

from __future__ import annotations

import argparse


class _Toggle(argparse.Action):
    """A flag whose every occurrence flips the setting."""

    def __init__(self, option_strings, dest, **kwargs) -> None:
        kwargs.setdefault("default", False)
        super().__init__(option_strings, dest, nargs=0, **kwargs)

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        setattr(namespace, self.dest, not getattr(namespace, self.dest))


def add_block_delete(parser: argparse.ArgumentParser, help: str) -> None:
    """``-b``: block delete, flipped at each occurrence as rs274 does."""
    parser.add_argument(
        "-b", dest="block_delete", action=_Toggle, help=help + " (each -b flips it)"
    )
