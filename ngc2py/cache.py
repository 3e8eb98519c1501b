"""On-disk cache of generated modules (Mako's idea: regenerate on change).

An entry is keyed by a hash of the source bytes, the compiler (version and
a hash of its sources), the
options that change the output (the ini file's path and content, the
current directory, which is where rs274 looks for external subroutines) and
the file name (it appears in messages). Next to the module a small JSON file
records the external-subroutine paths that were probed; a hit is only used
if each still exists (or not) with the same content hash.

Entries are written atomically (temporary file + ``os.replace``) so a
concurrent reader never sees half a module. The directory is
``$NGC2PY_CACHE`` or ``<user cache dir>/ngc2py``.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import List, Optional, Tuple, Union

from ngc2py import __version__
from ngc2py.compiler import compile_program

ENV = "NGC2PY_CACHE"


def cache_dir() -> Path:
    """Where entries live: ``$NGC2PY_CACHE``, else the user's cache dir."""
    override = os.environ.get(ENV)
    if override:
        return Path(override)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(
        os.path.expanduser("~"), ".cache"
    )
    return Path(base) / "ngc2py"


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _file_digest(path: str) -> Optional[str]:
    try:
        with open(path, "rb") as handle:
            return _digest(handle.read())
    except OSError:
        return None


_FINGERPRINT: List[str] = []


def compiler_fingerprint() -> str:
    """The version plus a hash of the compiler's own sources, so a changed
    (even unreleased) compiler never reuses modules the old one wrote."""
    if not _FINGERPRINT:
        package = Path(__file__).resolve().parent
        digest = hashlib.sha256(__version__.encode())
        for source in sorted(package.glob("*.py")):
            digest.update(source.read_bytes())
        _FINGERPRINT.append(digest.hexdigest())
    return _FINGERPRINT[0]


def cache_key(path: str, ini: Optional[str]) -> str:
    """The entry name for compiling ``path`` (with ``ini``) now."""
    with open(path, "rb") as handle:
        source = handle.read()
    parts = [
        compiler_fingerprint(),
        _digest(source),
        path,
        os.getcwd(),
        ini or "",
        (_file_digest(ini) or "") if ini else "",
    ]
    return _digest("\0".join(parts).encode("utf-8", "surrogateescape"))


def _file_mode(target: Path) -> int:
    """The mode ``target`` gets: the one it has, or a new file's (0666 less
    the umask), not the private 0600 of a temporary file."""
    try:
        return target.stat().st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def write_atomic(target, data: Union[str, bytes]) -> None:
    """Write ``data`` (text is UTF-8) to ``target`` so that readers see the
    old file or the new one, never half of one; the file keeps its mode."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    import tempfile  # here: a cached `ngc2py run` never writes

    fd, temp = tempfile.mkstemp(
        dir=str(target.parent), prefix=".tmp-", suffix=target.suffix
    )
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
        os.chmod(temp, _file_mode(target))
        os.replace(temp, target)
    except BaseException:
        try:
            os.unlink(temp)
        except OSError:
            pass
        raise


def _probes_current(probes: List[Tuple[str, Optional[str]]]) -> bool:
    return all(_file_digest(path) == digest for path, digest in probes)


def cached_module(path: str, ini: Optional[str] = None) -> Path:
    """The path of an up-to-date generated module for ``path``, compiling
    (and storing) it on a miss. Raises ``compiler.CompileError`` (an
    ``OpenError`` when ``path`` cannot be read)."""
    from ngc2py.compiler import open_failure

    try:
        key = cache_key(path, ini)
    except OSError as error:
        raise open_failure(path, error) from None
    folder = cache_dir()
    module = folder / ("m_%s.py" % key)
    meta = folder / ("m_%s.json" % key)
    try:
        probes = [tuple(p) for p in json.loads(meta.read_text("utf-8"))]
        if module.is_file() and _probes_current(probes):
            return module
    except (OSError, ValueError, TypeError):
        pass
    compiled = compile_program(path, ini)
    probes = [(p, _file_digest(p) if found else None) for p, found in compiled.probes]
    write_atomic(module, compiled.text)
    write_atomic(meta, json.dumps(probes))
    return module
