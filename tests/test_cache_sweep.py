"""The compile cache keeps to a size (ngc2py/cache_sweep.py): the entries
used least recently go, recent ones never, and a run never fails for it."""

from __future__ import annotations

import os
import time

import pytest

from ngc2py import cache, cache_sweep, loading
from ngc2py.cache_sweep import AFTER, GRACE, INTERVAL, STAMP, SizeError
from runtime.canon import RecordingCanon

PROGRAM = "G0 X1 Y2\nG1 Z-1 F100\nM2\n"


@pytest.fixture
def inline_sweeps(monkeypatch):
    """Sweeps run in this process, done when the miss returns (a run's own
    sweep is a process apart: test_a_sweep_runs_apart_from_the_run)."""
    monkeypatch.setattr(
        cache_sweep,
        "_spawn",
        lambda folder, limit: cache_sweep.main([folder, str(limit)]),
    )


def stamped(folder, age: float) -> None:
    """The cache's last sweep ``age`` seconds ago."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / STAMP).write_text("")
    when = time.time() - age
    os.utime(folder / STAMP, (when, when))


def fake_entry(folder, k: int, size: int, age: float) -> str:
    """An entry as cache.py writes one (module, probes, bytecode), ``size``
    bytes in all, last used ``age`` seconds ago; returns its key."""
    key = "%064x" % (k + 1)
    (folder / "__pycache__").mkdir(parents=True, exist_ok=True)
    parts = {
        folder / ("m_%s.py" % key): size - 2 - size // 2,
        folder / "__pycache__" / ("m_%s.cpython-311.pyc" % key): size // 2,
        folder / ("m_%s.json" % key): 2,
    }
    when = time.time() - age
    for path, length in parts.items():
        path.write_bytes(b"[]" if path.suffix == ".json" else b"x" * length)
        os.utime(path, (when, when))
    return key


def keys_in(folder) -> set:
    return {p.name[2:66] for p in folder.glob("m_*.json")}


def on_disk(folder, key: str) -> int:
    """An entry's size as the sweep counts it (its files' blocks)."""
    files = [p for p in folder.rglob("m_%s*" % key)]
    return sum(cache_sweep._disk_size(os.stat(p)) for p in files)


@pytest.mark.parametrize(
    "text, size",
    [
        ("", cache_sweep.DEFAULT_SIZE),
        ("0", 0),
        ("4096", 4096),
        ("500M", 500 << 20),
        ("2g", 2 << 30),
        ("1.5G", 3 << 29),
        (" 64 KB ", 64 << 10),
    ],
)
def test_the_size_limit(monkeypatch, text, size):
    monkeypatch.setenv(cache_sweep.SIZE_ENV, text)
    assert cache_sweep.size_limit() == size


@pytest.mark.parametrize("text", ["lots", "-1G", "2T", "1e9"])
def test_a_size_that_is_not_one_is_an_error_naming_the_variable(monkeypatch, text):
    monkeypatch.setenv(cache_sweep.SIZE_ENV, text)
    with pytest.raises(SizeError, match=cache_sweep.SIZE_ENV):
        cache_sweep.size_limit()


def test_the_least_recently_used_entries_go_down_to_a_part_of_the_limit(tmp_path):
    # ten entries of 1000 bytes, the first used longest ago
    keys = [fake_entry(tmp_path, k, 1000, GRACE + 1000 * (10 - k)) for k in range(10)]
    unit = on_disk(tmp_path, keys[0])
    removed = cache_sweep.sweep(str(tmp_path), 6 * unit, time.time())
    kept = int(6 * AFTER)
    assert removed == keys[: 10 - kept]
    assert keys_in(tmp_path) == set(keys[10 - kept :])
    # every file of a removed entry went, bytecode too
    assert not any(key in p.name for key in removed for p in tmp_path.rglob("m_*"))


def test_nothing_goes_while_the_entries_fit(tmp_path):
    keys = [fake_entry(tmp_path, k, 1000, GRACE * 10) for k in range(5)]
    limit = 5 * on_disk(tmp_path, keys[0])
    assert cache_sweep.sweep(str(tmp_path), limit, time.time()) == []
    assert keys_in(tmp_path) == set(keys)


def test_entries_used_lately_stay_even_over_the_limit(tmp_path):
    old = fake_entry(tmp_path, 0, 1000, GRACE * 10)
    recent = [fake_entry(tmp_path, k, 1000, GRACE / 10) for k in range(1, 5)]
    assert cache_sweep.sweep(str(tmp_path), 1, time.time()) == [old]
    assert keys_in(tmp_path) == set(recent)


def test_temporary_files_a_crashed_write_left_go_when_old(tmp_path):
    for name, age in ((".tmp-old.py", GRACE * 2), (".tmp-new.py", 0.0)):
        (tmp_path / name).write_text("x")
        when = time.time() - age
        os.utime(tmp_path / name, (when, when))
    cache_sweep.sweep(str(tmp_path), 1 << 30, time.time())
    assert [p.name for p in tmp_path.iterdir()] == [".tmp-new.py"]


def test_a_hit_marks_its_entry_used_and_leaves_its_bytecode_valid(
    tmp_path, monkeypatch
):
    monkeypatch.setenv(cache.ENV, str(tmp_path / "c"))
    program = tmp_path / "p.ngc"
    program.write_text(PROGRAM)
    module = cache.cached_module(str(program))
    cache.load_cached(module)
    meta = tmp_path / "c" / (os.path.basename(module)[:-3] + ".json")
    long_ago = time.time() - 10 * GRACE
    os.utime(meta, (long_ago, long_ago))
    module_time = os.stat(module).st_mtime
    assert cache.cached_module(str(program)) == module
    assert time.time() - os.stat(meta).st_mtime < GRACE
    assert os.stat(module).st_mtime == module_time  # (the bytecode's check)


def test_a_new_cache_is_stamped_and_swept_an_interval_later(tmp_path, monkeypatch):
    folder = tmp_path / "c"
    monkeypatch.setenv(cache.ENV, str(folder))
    monkeypatch.setattr(cache_sweep, "_spawn", lambda *args: pytest.fail("swept"))
    (tmp_path / "p.ngc").write_text(PROGRAM)
    cache.cached_module(str(tmp_path / "p.ngc"))
    assert time.time() - os.stat(folder / STAMP).st_mtime < GRACE


def test_a_miss_sweeps_the_cache_at_most_once_an_interval(
    tmp_path, monkeypatch, inline_sweeps
):
    folder = tmp_path / "c"
    monkeypatch.setenv(cache.ENV, str(folder))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, "4K")
    old = [fake_entry(folder, k, 1000, GRACE * (10 + k)) for k in range(8)]
    stamped(folder, INTERVAL + 1)
    for k in range(2):
        (tmp_path / ("p%d.ngc" % k)).write_text(PROGRAM + "(%d)\n" % k)
    new = cache.cached_module(str(tmp_path / "p0.ngc"))
    assert (folder / STAMP).exists()
    assert not keys_in(folder) & set(old[-2:])  # the oldest went
    assert os.path.exists(new)
    left = keys_in(folder)
    more = [fake_entry(folder, k, 1000, GRACE * 100) for k in range(20, 24)]
    cache.cached_module(str(tmp_path / "p1.ngc"))  # swept a moment ago: not now
    assert set(more) <= keys_in(folder) and left <= keys_in(folder)
    long_ago = time.time() - INTERVAL - 1
    os.utime(folder / STAMP, (long_ago, long_ago))
    (tmp_path / "p2.ngc").write_text(PROGRAM + "(2)\n")
    cache.cached_module(str(tmp_path / "p2.ngc"))
    assert not set(more) & keys_in(folder)


def test_no_limit_means_no_sweep(tmp_path, monkeypatch, inline_sweeps):
    folder = tmp_path / "c"
    monkeypatch.setenv(cache.ENV, str(folder))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, "0")
    old = [fake_entry(folder, k, 1000, GRACE * 10) for k in range(4)]
    stamped(folder, INTERVAL + 1)
    (tmp_path / "p.ngc").write_text(PROGRAM)
    cache.cached_module(str(tmp_path / "p.ngc"))
    assert set(old) <= keys_in(folder)


def test_an_entry_swept_before_it_is_loaded_is_compiled_again(tmp_path, monkeypatch):
    """Another run may sweep an entry between this run finding and loading
    it (only one not used for GRACE seconds, so this takes a long pause):
    the program is compiled again, the run goes on."""
    monkeypatch.setenv(cache.ENV, str(tmp_path / "c"))
    program = tmp_path / "p.ngc"
    program.write_text(PROGRAM)
    found = cache.cached_module(str(program))
    monkeypatch.setattr(cache, "_COMPILED", {})  # (a later run: a hit)
    finding = cache.cached_module
    lost = []

    def swept_meanwhile(*args, **options):
        module = finding(*args, **options)
        if not lost:
            lost.append(module)
            os.unlink(module)
            os.unlink(module[:-3] + ".json")
        return module

    monkeypatch.setattr(cache, "cached_module", swept_meanwhile)
    module = loading.load_program(str(program), None)
    assert lost == [found] and os.path.exists(found)
    assert module.__ngc__.files[0] == str(program)


def test_a_cache_far_over_its_limit_shrinks_a_sweep_at_a_time(
    tmp_path, monkeypatch, inline_sweeps
):
    """A sweep removes MOST entries at most (a cache grown large before it
    had a limit would take a run minutes to empty at once); then a miss
    AGAIN seconds later sweeps again, not an interval later."""
    folder = tmp_path / "c"
    monkeypatch.setenv(cache.ENV, str(folder))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, "1")
    monkeypatch.setattr(cache_sweep, "MOST", 3)
    old = [fake_entry(folder, k, 1000, GRACE * (10 + k)) for k in range(8)]
    stamped(folder, INTERVAL + 1)
    for k in range(3):
        (tmp_path / ("p%d.ngc" % k)).write_text(PROGRAM + "(%d)\n" % k)
        cache.cached_module(str(tmp_path / ("p%d.ngc" % k)))
        left = set(old[: max(0, 5 - 3 * k)])  # the oldest three a sweep
        assert set(old) & keys_in(folder) == left
        next_sweep = os.stat(folder / STAMP).st_mtime + INTERVAL - time.time()
        # soon while a sweep did all it may; after the last, an interval on
        assert 0 < next_sweep <= cache_sweep.AGAIN if k < 2 else next_sweep > GRACE
        earlier = time.time() - INTERVAL  # (as if AGAIN seconds went by)
        os.utime(folder / STAMP, (earlier, earlier))


def test_a_bad_size_fails_a_miss_before_anything_is_written(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, str(tmp_path / "c"))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, "lots")
    (tmp_path / "p.ngc").write_text(PROGRAM)
    with pytest.raises(SizeError):
        cache.cached_module(str(tmp_path / "p.ngc"))
    assert not (tmp_path / "c").exists()


def test_a_bad_size_fails_a_hit_too(tmp_path, monkeypatch):
    """The same setting fails every run, whether its program is cached."""
    monkeypatch.setenv(cache.ENV, str(tmp_path / "c"))
    (tmp_path / "p.ngc").write_text(PROGRAM)
    module = cache.cached_module(str(tmp_path / "p.ngc"))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, "lots")
    with pytest.raises(SizeError, match=cache_sweep.SIZE_ENV):
        cache.cached_module(str(tmp_path / "p.ngc"))
    monkeypatch.setenv(cache_sweep.SIZE_ENV, " 2G ")
    assert cache.cached_module(str(tmp_path / "p.ngc")) == module


def test_the_help_names_the_cache_settings_and_the_default(monkeypatch):
    from ngc2py import cli

    text = cli.build_parser().format_help()
    assert cache.ENV in text and cache_sweep.SIZE_ENV in text
    default = text.split("(default ")[-1].split(";")[0]
    monkeypatch.setenv(cache_sweep.SIZE_ENV, default)
    assert cache_sweep.size_limit() == cache_sweep.DEFAULT_SIZE


def test_an_entry_lost_again_is_compiled_into_a_temporary_module(tmp_path, monkeypatch):
    monkeypatch.setenv(cache.ENV, str(tmp_path / "c"))
    program = tmp_path / "p.ngc"
    program.write_text(PROGRAM)
    finding = cache.cached_module
    lost = []

    def always_swept(*args, **options):
        module = finding(*args, **options)
        lost.append(module)
        os.unlink(module)
        cache._COMPILED.clear()  # (nor is the code compiled for it at hand)
        return module

    monkeypatch.setattr(cache, "cached_module", always_swept)
    module = loading.load_program(str(program), None)
    assert len(lost) == 2
    assert module.__ngc__.files[0] == str(program)
    canon = RecordingCanon()
    module.run(canon)
    assert ("straight_traverse", (1.0, 2.0, 0.0, 0.0, 0.0, 0.0)) in [
        (name, args[:6]) for name, args in canon.calls
    ]


def test_a_sweep_tells_time_by_the_cache_s_file_system(tmp_path, inline_sweeps):
    """A network share's clock may not be this machine's: whether the last
    sweep is an interval old is told by the folder's mtime (an entry was
    just written into it), not by time.time()."""
    half = INTERVAL / 2  # by this machine's clock: recent
    stamped(tmp_path, half)
    ahead = time.time() + INTERVAL  # the share's clock: an hour ahead
    os.utime(tmp_path, (ahead, ahead))
    cache_sweep.maybe_sweep(str(tmp_path), 1 << 30)
    age = time.time() - os.stat(tmp_path / STAMP).st_mtime
    assert age < half / 2  # due: stamped anew


def test_a_sweep_runs_apart_from_the_run(tmp_path):
    """The sweep is a process of its own (it may take seconds): the miss
    returns at once, and the process, once done, has swept."""
    old = [fake_entry(tmp_path, k, 1000, GRACE * (10 + k)) for k in range(4)]
    stamped(tmp_path, INTERVAL + 1)
    os.utime(tmp_path, None)  # (an entry went in just now)
    process = cache_sweep.maybe_sweep(str(tmp_path), 1)
    assert process is not None and process.wait(timeout=60) == 0
    assert not set(old) & keys_in(tmp_path)
