"""On-disk cache of generated modules (Mako's idea: regenerate on change).

An entry is keyed by a hash of the source bytes, the compiler (version and
a hash of its sources) and the options that change the output (the ini
file's path and content, and the folders it makes rs274 look in for
external subroutines). Not by the program's name or folder: the module
names its file in one place, its source map's first file, which
:func:`load_cached` sets to the name the program is run by, so the same
program under another name (a CAM tool's temporary file, a copy in another
folder) is not converted again. (A program that finds itself as an
external subroutine file, under the very name it was given, shares that
name's place in the source map: such an entry is keyed by the name too.)
Not by the current directory either: subroutine files found there are
named relative to it, so a copy of a folder (a golden check's scratch
copy) hits the same entry. Next to the module a small JSON file records
the external-subroutine paths that were probed; a hit is only used if each
still exists (or not) with the same content hash.

Entries are written atomically (temporary file + ``os.replace``) so a
concurrent reader never sees half a module. The directory is
``$NGC2PY_CACHE`` or ``<user cache dir>/ngc2py``.

An entry's bytecode is kept in ``__pycache__`` beside it, where Python
keeps a module's, and in Python's format -- also where Python is told not to
write bytecode (``PYTHONDONTWRITEBYTECODE``, usual in containers): an entry
never changes (its name is its key), and compiling a 100k-line program's
module again would take 50 ms of every run.
"""

from __future__ import annotations

import os
import sys

# A cached `ngc2py run` does little but this module's work before the
# program runs, so it stays off pathlib, typing, json and OpenSSL's hashlib
# (together about 10 ms of imports): paths are strings, BLAKE2 is CPython's
# own module, and an entry's probes are read as JSON only when there are any.
try:
    from _blake2 import blake2b as _hash
except ImportError:  # not CPython
    from hashlib import blake2b as _hash

from ngc2py import __version__
from ngc2py.bytecode import QuickLoader, compile_module
from ngc2py.compiler import compile_program, subroutine_dirs
from runtime.atomic import file_mode, temporary_beside

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import List, Optional, Tuple, Union

ENV = "NGC2PY_CACHE"
#: The cache's size limit (ngc2py/cache_sweep.py reads it).
SIZE_ENV = "NGC2PY_CACHE_SIZE"


def cache_dir() -> str:
    """Where entries live: ``$NGC2PY_CACHE``, else the user's cache dir."""
    override = os.environ.get(ENV)
    if override:
        return override
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(
        os.path.expanduser("~"), ".cache"
    )
    return os.path.join(base, "ngc2py")


def _digest(data: bytes) -> str:
    return _hash(data, digest_size=32).hexdigest()


def _file_digest(path: str) -> Optional[str]:
    try:
        with open(path, "rb") as handle:
            return _digest(handle.read())
    except OSError:
        return None


_FINGERPRINT: List[str] = []

#: The cache folder's note of the last fingerprint worked out: the
#: compiler files' stamp (names, sizes, times) and their hash.
_FINGERPRINT_NOTE = "compiler-fingerprint"


def compiler_fingerprint() -> str:
    """The version plus a hash of the compiler's own sources, so a changed
    (even unreleased) compiler never reuses modules the old one wrote."""
    if not _FINGERPRINT:
        package = os.path.dirname(os.path.realpath(__file__))
        _FINGERPRINT.append(sources_fingerprint(package, cache_dir()))
    return _FINGERPRINT[0]


def sources_fingerprint(package: str, folder: str) -> str:
    """The version plus a hash of ``package``'s sources (its .py and .c
    files: ngc2py/_rowtext.c is a pass of the compiler too).

    Hashing ngc2py's 700 kB is 2-3 ms of every run, as long as a small
    program's whole run: so the hash is noted in the cache ``folder`` with a
    stamp of the files (each one's name, size and time, as Python checks
    its own bytecode against a source) and read back while the stamp is the
    same. A changed stamp (an edit, a reinstall) hashes them again."""
    names = sorted(n for n in os.listdir(package) if n.endswith((".py", ".c")))
    paths = [os.path.join(package, name) for name in names]
    stamp = _digest(
        repr(
            (__version__, package, tuple(names))
            + tuple((s.st_size, s.st_mtime_ns) for s in map(os.stat, paths))
        ).encode("utf-8", "surrogateescape")
    )
    note = os.path.join(folder, _FINGERPRINT_NOTE)
    known = _noted(note, stamp)
    if known is None:
        digest = _hash(__version__.encode(), digest_size=32)
        for path in paths:
            with open(path, "rb") as handle:
                digest.update(handle.read())
        known = digest.hexdigest()
        try:
            write_atomic(note, "%s %s\n" % (stamp, known))
        except OSError:  # (a cache folder not to be written: hashed each run)
            pass
    return known


def _noted(note: str, stamp: str) -> Optional[str]:
    """The fingerprint ``note`` keeps for ``stamp``, or None."""
    try:
        with open(note, "rb") as handle:
            text = handle.read(200).decode("ascii")
    except (OSError, UnicodeDecodeError):
        return None
    parts = text.split()
    if len(parts) != 2 or parts[0] != stamp or len(parts[1]) != 64:
        return None
    try:
        int(parts[1], 16)
    except ValueError:
        return None
    return parts[1]


def cache_key(path: str, ini: Optional[str], block_delete: bool = False) -> str:
    """The entry name for compiling ``path``'s content (with ``ini``, for
    ``block_delete``) now, whatever its name."""
    with open(path, "rb") as handle:
        source = handle.read()
    parts = [
        compiler_fingerprint(),
        _digest(source),
        ini or "",
        (_file_digest(ini) or "") if ini else "",
        # where subroutine files are looked for (relative ones: in the
        # current directory, whichever it is; the probes say what was found)
        "\1".join(subroutine_dirs(ini)) if ini else "",
    ]
    if block_delete:  # (the key of every other entry stays as it was)
        parts.append("-b")
    return _digest("\0".join(parts).encode("utf-8", "surrogateescape"))


def _named_key(key: str, path: str) -> str:
    """The entry name of :func:`cache_key`'s ``key`` for ``path`` alone (see
    the module's doc)."""
    return _digest(("%s\0%s" % (key, path)).encode("utf-8", "surrogateescape"))


def write_atomic(target, data: Union[str, bytes]) -> None:
    """Write ``data`` (text is UTF-8) to ``target`` so that readers see the
    old file or the new one, never half of one; the file keeps its mode. A
    device or a pipe (``-o /dev/null``) is written to, not replaced."""
    from runtime.atomic import special_file

    target = os.fspath(target)
    if special_file(target):
        with open(target, "wb") as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
        return
    folder = os.path.dirname(target) or "."
    os.makedirs(folder, exist_ok=True)
    # (".tmp-": what a sweep knows a crashed write's leftovers by)
    fd, temp = temporary_beside(target, ".tmp-", os.path.splitext(target)[1])
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(data.encode("utf-8") if isinstance(data, str) else data)
        os.chmod(temp, file_mode(target))
        os.replace(temp, target)
    except BaseException:
        try:
            os.unlink(temp)
        except OSError:
            pass
        raise


def _probes_current(probes: List[Tuple[str, Optional[str]]]) -> bool:
    return all(_file_digest(path) == digest for path, digest in probes)


def module_probes(module: str) -> List[Tuple[str, Optional[str]]]:
    """The external-subroutine paths probed when ``module`` (a path
    :func:`cached_module` returned) was compiled, each with the digest of
    the file found there (None: no file)."""
    import json

    # m_<key>.py or m_<key>_<probes>.py: the probes are in m_<key>.json
    name = os.path.basename(module)[: -len(".py")]
    meta = os.path.join(
        os.path.dirname(module), name.split("_")[0] + "_" + name.split("_")[1]
    )
    with open(meta + ".json", encoding="utf-8") as handle:
        return [tuple(p) for p in json.loads(handle.read())]


def cached_module(
    path: str, ini: Optional[str] = None, block_delete: bool = False
) -> str:
    """The path of an up-to-date generated module for ``path``, compiling
    (and storing) it on a miss. Raises ``compiler.CompileError`` (an
    ``OpenError`` when ``path`` cannot be read). ``block_delete``: see
    ``compiler.compile_program``."""
    from ngc2py.compiler import open_failure

    try:
        key = cache_key(path, ini, block_delete)
    except OSError as error:
        raise open_failure(path, error) from None
    if os.environ.get(SIZE_ENV, "").strip():
        from ngc2py.cache_sweep import size_limit

        # a bad setting fails every run, not only one that writes an entry
        # (read only where it is set: its module is not imported otherwise)
        size_limit()
    folder = cache_dir()
    for entry in (key, _named_key(key, path)):
        module = _current_entry(folder, entry)
        if module is not None:
            return module
    import json

    from ngc2py.cache_sweep import maybe_sweep, size_limit

    limit = size_limit()  # (a bad setting fails the run before it writes)
    # (its G-code text as it is: the entry's bytecode is compiled without
    # tokenizing it, and compressing it would cost a large file's first run)
    compiled = compile_program(path, ini, block_delete, pack=False)
    probes = [(p, _file_digest(p) if found else None) for p, found in compiled.probes]
    if path in (p for p, found in compiled.probes if found):
        key = _named_key(key, path)  # it finds itself under its own name
    text = json.dumps(probes)
    module = _module_path(folder, key, text)
    write_atomic(module, compiled.text)
    # its bytecode now, compiled without tokenizing its tables' text
    # (ngc2py/bytecode.py): the import that follows reads it
    try:
        code = compile_module(compiled.text, module)
    except (SyntaxError, ValueError):
        pass  # (the import tells what is wrong)
    else:
        _keep_bytecode(module, compiled.text.encode("utf-8"), code)
        # and kept for this process's import of it (load_cached), which
        # need not read back and unmarshal what was just written (a
        # 100k-arc module's bytecode is 8 MB: 10-15 ms)
        _COMPILED.clear()
        _COMPILED[module] = code
    write_atomic(os.path.join(folder, "m_%s.json" % key), text)
    maybe_sweep(folder, limit)  # (now and then: the cache keeps to its size)
    return module


#: The code of the entry this process compiled last, by its module's path,
#: until :func:`load_cached` takes it (one entry: a library's checks
#: compile many and import none).
_COMPILED: dict = {}


def _current_entry(folder: str, key: str) -> Optional[str]:
    """The module of entry ``key``, if there is one and the external
    subroutine files it probed are as they were."""
    meta = os.path.join(folder, "m_%s.json" % key)
    try:
        with open(meta, encoding="utf-8") as handle:
            text = handle.read()
        if text == "[]":  # no external subroutine probed: the usual case
            probes = []
        else:
            import json

            probes = [tuple(p) for p in json.loads(text)]
        module = _module_path(folder, key, text)
        if os.path.isfile(module) and _probes_current(probes):
            _touch(meta)
            return module
    except (OSError, ValueError, TypeError):
        pass
    return None


def _touch(meta: str) -> None:
    """Mark an entry used now (ngc2py/cache_sweep.py keeps the entries used
    last): its ``.json``'s mtime, not the module's, which its bytecode is
    checked against. A cache that cannot be written is only read."""
    try:
        os.utime(meta)
    except OSError:
        pass


def _module_path(folder: str, key: str, probes: str) -> str:
    """The module of an entry whose probes (as JSON text) are ``probes``.
    Programs with the same source but other subroutine files share a key;
    naming the module by its probes too means that runs compiling such
    programs at the same time can never pair one's probes with the
    other's module (each file is written atomically, the pair is not)."""
    if probes == "[]":
        return os.path.join(folder, "m_%s.py" % key)
    return os.path.join(folder, "m_%s_%s.py" % (key, _digest(probes.encode())[:24]))


def load_cached(module: str, program: Optional[str] = None):
    """Import the entry ``module`` (a path :func:`cached_module` returned)
    under a private name, its bytecode kept (see the module's doc); its
    source map names the program ``program`` (the name it is run by, which
    may not be the name it was compiled by)."""
    loader = _KeepingLoader("ngc2py_program", module)
    loader.compiled = _COMPILED.pop(module, None)
    loaded = loader.load()
    source = loaded.__ngc__
    if program is not None and source.files[:1] != (program,):
        source.files = (program,) + source.files[1:]
    return loaded


class _KeepingLoader(QuickLoader):
    """Python's loader (it reads a valid ``__pycache__`` file, whatever
    ``sys.dont_write_bytecode`` says), writing the bytecode it compiles
    where Python would not; or the code :func:`cached_module` compiled
    for the entry in this process (``compiled``), as it is."""

    compiled = None

    def get_code(self, fullname):
        code, self.compiled = self.compiled, None
        return code if code is not None else super().get_code(fullname)

    def source_to_code(self, data, path, *, _optimize=-1):
        code = super().source_to_code(data, path, _optimize=_optimize)
        if sys.dont_write_bytecode:
            _keep_bytecode(path, data, code)
        return code


def _keep_bytecode(path: str, source: bytes, code) -> None:
    """Write ``code`` as Python's own timestamp-checked ``.pyc`` of
    ``path`` (PEP 552: magic, flags 0, the source's mtime and size)."""
    import marshal
    from importlib.util import MAGIC_NUMBER, cache_from_source

    try:
        mtime = int(os.stat(path).st_mtime) & 0xFFFFFFFF
        header = (
            MAGIC_NUMBER
            + bytes(4)
            + mtime.to_bytes(4, "little")
            + (len(source) & 0xFFFFFFFF).to_bytes(4, "little")
        )
        write_atomic(cache_from_source(path), header + marshal.dumps(code))
    except (OSError, NotImplementedError, ValueError):
        pass  # the entry still works, compiled on each run
