"""Progress bars on stderr for long conversions, runs and batches (tqdm).

Shown only when stderr is a terminal and the user did not ask for ``-q``:
piped or captured output (scripts, CI, parity checks against rs274) never
contains a bar. A bar that is shown is cleared when it closes, so what
stays on the terminal is the same as without it. The runtime never imports
this module: generated programs stay standard-library only; the CLI
watches the trace canon's count from a thread instead (:func:`watch_run`).
"""

from __future__ import annotations

import sys

TYPE_CHECKING = False  # the run path imports this: no typing
if TYPE_CHECKING:
    from typing import IO, Optional


def wanted(quiet: bool = False, stream: Optional[IO] = None) -> bool:
    """Whether to draw a bar: stderr is a terminal and not ``-q``."""
    if quiet:
        return False
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


class _Quiet:
    """Stands in for a bar that is not shown."""

    def update(self, n: int = 1) -> None:
        pass

    def set_description(self, text: str) -> None:
        pass

    def write(self, text: str, error: bool = False) -> None:
        stream = sys.stderr if error else sys.stdout
        stream.write(text + "\n")

    def close(self) -> None:
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()


class _Bar(_Quiet):
    def __init__(self, total: Optional[int], description: str, unit: str):
        from tqdm import tqdm

        self._tqdm = tqdm(
            total=total,
            desc=description,
            unit=unit,
            leave=False,
            file=sys.stderr,
            dynamic_ncols=True,
            mininterval=0.2,
        )

    def update(self, n: int = 1) -> None:
        self._tqdm.update(n)

    def set_description(self, text: str) -> None:
        self._tqdm.set_description(text, refresh=False)

    def write(self, text: str, error: bool = False) -> None:
        from tqdm import tqdm

        # above the bar, which is redrawn below it
        tqdm.write(text, file=sys.stderr if error else sys.stdout)

    def close(self) -> None:
        self._tqdm.close()


def progress(total: Optional[int], description: str, unit: str, quiet: bool = False):
    """A bar (context manager) counting ``unit``s up to ``total`` (None: no
    known end), or a silent stand-in when no bar is wanted."""
    if not wanted(quiet):
        return _Quiet()
    try:
        return _Bar(total, description, unit)
    except ImportError:  # tqdm missing: work without a bar
        return _Quiet()


def watch_run(canon, quiet: bool = False):
    """A bar for a run against ``canon`` (the trace), or a silent stand-in
    when no bar is wanted; ``close()`` it when the run ends.

    The bar counts the lines the canon has written (its ``_count``), read
    five times a second from a thread of its own. The canon is not wrapped:
    the machine's fast paths choose by the canon's class (the trace's own
    text paths, batches for canons that take them), and a wrapper would
    send every move down the slow path or past a batch method it lacks."""
    if not wanted(quiet):
        return _Quiet()
    try:
        bar = _Bar(None, "running", "line")
    except ImportError:
        return _Quiet()
    return _Watcher(canon, bar)


class _Watcher:
    """Updates ``bar`` with ``canon._count`` until closed."""

    #: Seconds between two looks at the count.
    PERIOD = 0.2

    def __init__(self, canon, bar) -> None:
        import threading

        self._canon = canon
        self._bar = bar
        self._shown = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, daemon=True)
        self._thread.start()

    def _look(self) -> None:
        count = getattr(self._canon, "_count", 0)
        if isinstance(count, int) and count > self._shown:
            self._bar.update(count - self._shown)
            self._shown = count

    def _watch(self) -> None:
        while not self._stop.wait(self.PERIOD):
            self._look()

    def close(self) -> None:
        self._stop.set()
        self._thread.join()
        self._look()
        self._bar.close()


class spinner:
    """A bar with no count for one long step (a conversion): it shows the
    step and the time spent, redrawn from a background thread, and is
    cleared when the step ends. Silent unless :func:`wanted`."""

    def __init__(self, description: str, quiet: bool = False):
        self._description = description
        self._quiet = quiet
        self._stop = None
        self._thread = None

    def __enter__(self) -> "spinner":
        if not wanted(self._quiet):
            return self
        import threading

        try:
            from tqdm import tqdm
        except ImportError:
            return self
        bar = tqdm(
            total=None,
            desc=self._description,
            bar_format="{desc} {elapsed}",
            leave=False,
            file=sys.stderr,
            delay=0.5,  # quick steps draw nothing at all
        )
        stop = threading.Event()

        def refresh() -> None:
            while not stop.wait(0.25):
                bar.refresh()
            bar.close()

        self._stop = stop
        self._thread = threading.Thread(target=refresh, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        if self._stop is not None:
            self._stop.set()
            self._thread.join()
