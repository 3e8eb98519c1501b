"""Tests for runtime.varfile, with comparisons against rs274 (marked rs274)."""

from __future__ import annotations

import io
import os
import re
import subprocess
from pathlib import Path

import pytest

import rs274 as harness
from runtime.errors import GCodeError
from runtime.varfile import (
    REQUIRED_PARAMETERS,
    default_parameters,
    initial_parameters,
    read_parameter_file,
    save_parameter_file,
)


def _write(tmp_path: Path, text: str) -> str:
    path = tmp_path / "a.var"
    path.write_text(text)
    return str(path)


def test_sscanf_like_lines(tmp_path):
    path = _write(tmp_path, "100.5 3\nabc\n101 x\n 5221\t2.5e1 junk\n\n")
    assert read_parameter_file(path) == {100: 0.5, 5221: 25.0}


@pytest.mark.parametrize(
    "text, message",
    [
        ("5220 1\n5220 3\n", "Parameter file out of order"),
        ("5399 3\n5220 1\n", "Parameter file out of order"),
        ("0 1\n", "Parameter number out of range"),
        ("5602 3\n", "Parameter number out of range"),
    ],
)
def test_bad_files(tmp_path, text, message):
    with pytest.raises(GCodeError, match=message):
        read_parameter_file(_write(tmp_path, text))


def test_missing_file_is_empty(tmp_path):
    assert read_parameter_file(str(tmp_path / "none.var")) == {}


def test_defaults():
    assert default_parameters() == {5220: 1.0, 5599: 1.0}
    assert len(REQUIRED_PARAMETERS) == 119 and REQUIRED_PARAMETERS[-1] == 5390


@pytest.mark.parametrize(
    "value, expected", [("0", 1.0), ("10", 1.0), ("0.9999", 0.9999), ("9.5", 9.5)]
)
def test_coordinate_system_index_is_repaired(tmp_path, value, expected):
    assert initial_parameters(_write(tmp_path, f"5220 {value}\n"))[5220] == expected


def test_start_clears_tool_parameters_after_saving(tmp_path):
    path = _write(tmp_path, "5220 1\n5400 3\n5600 2\n")
    values = initial_parameters(path)
    assert 5400 not in values and 5600 not in values
    saved = read_parameter_file(path)
    assert (saved[5400], saved[5600]) == (3.0, 2.0)
    assert Path(path + ".bak").read_text() == "5220 1\n5400 3\n5600 2\n"


def test_save_keeps_listed_and_required(tmp_path):
    path = _write(tmp_path, "100 3\n5220 1\n")
    save_parameter_file(path, {100: 5.0, 101: 6.0, 5220: 1.0, 5221: 2.5})
    lines = Path(path).read_text().splitlines()
    assert lines[0] == "100\t5.000000"
    assert "5221\t2.500000" in lines and not any(
        line.startswith("101\t") for line in lines
    )
    assert len(lines) == 1 + len(REQUIRED_PARAMETERS)
    assert Path(path + ".bak").read_text() == "100 3\n5220 1\n"
    assert [p.name for p in Path(tmp_path).iterdir() if p.name.endswith(".new")] == []


def test_save_creates_a_missing_file_and_reports_it(tmp_path):
    path = str(tmp_path / "new.var")
    report = io.StringIO()
    save_parameter_file(path, {5161: 2.0}, stderr=report)
    lines = Path(path).read_text().splitlines()
    assert lines[0] == "5161\t2.000000" and len(lines) == len(REQUIRED_PARAMETERS)
    assert report.getvalue().startswith("link (updating variable file): ")
    assert not Path(path + ".bak").exists()


def test_save_in_a_missing_folder_does_nothing(tmp_path):
    path = tmp_path / "no" / "such" / "a.var"
    report = io.StringIO()
    save_parameter_file(str(path), {5161: 2.0}, stderr=report)
    assert report.getvalue() == "" and not path.parent.exists()


@pytest.mark.rs274
def test_missing_file_report_matches_rs274(tmp_path):
    # rs274 reads /dev/null in place of the missing file: harness.rs274_path()
    # refuses machines where that is not the null device (it made this
    # comparison fail at random).
    (tmp_path / "rs274").mkdir()
    _, err = _rs274(tmp_path / "rs274", "M2\n")
    report = io.StringIO()
    save_parameter_file(str(tmp_path / "a.var"), {}, stderr=report)
    assert report.getvalue() == err + "\n"


def test_rs274_is_refused_where_dev_null_is_a_regular_file(tmp_path, monkeypatch):
    fake = tmp_path / "null"
    fake.write_text("5220 1\n5161 3\n")  # what a reader of that file would see
    monkeypatch.setattr(harness.os, "devnull", str(fake))
    problem = harness.null_device_problem()
    assert problem and str(fake) in problem and "mknod" in problem
    if harness.shutil.which("rs274"):
        monkeypatch.delenv("RS274", raising=False)
        with pytest.raises(RuntimeError, match="not the null device"):
            harness.rs274_path()


def test_a_character_device_is_accepted_as_the_null_device(monkeypatch):
    monkeypatch.setattr(harness.os, "devnull", "/dev/zero")
    assert harness.null_device_problem() is None


# --------------------------------------------------------------------------
# Comparison with rs274
# --------------------------------------------------------------------------

_PROBED = (100, 101, 5161, 5220, 5221, 5230, 5399, 5400, 5413, 5414, 5599, 5600, 5601)
_ASSIGNED = {100: 5.0, 102: 7.25, 5162: -1.5, 5221: 2.0, 5414: 9.0}
_FILES = [
    "100 3\n5220 1\n5221 10\n",
    "100.5 3\nabc\n101 x\n 5221\t2.5e1 junk\n",
    "5220 10\n5400 3\n5413 2\n5414 3\n5599 1\n5600 2\n5601 3\n",
    "\n# comment\n5220 2\n\n5390 4",
    "5220 1\n5220 3\n",
    "5220 1\n5602 3\n",
    "",
]


def _rs274(folder: Path, program: str):
    (folder / "p.ngc").write_text(program)
    home = folder / "home"
    home.mkdir(exist_ok=True)
    done = subprocess.run(
        [harness.rs274_path(), "-v", "a.var", "-g", "p.ngc"],
        cwd=folder,
        capture_output=True,
        text=True,
        env={**os.environ, "HOME": str(home)},
        timeout=60,
    )
    return done.stdout, harness.first_error_line(done.stderr)


@pytest.mark.rs274
@pytest.mark.parametrize("text", _FILES)
def test_files_match_rs274(tmp_path, text):
    theirs, ours = tmp_path / "rs274", tmp_path / "ours"
    for folder in (theirs, ours):
        folder.mkdir()
        (folder / "a.var").write_text(text)
    probe = "(DEBUG," + " ".join(f"#{n}" for n in _PROBED) + ")\n"
    assign = "".join(f"#{n}={v}\n" for n, v in _ASSIGNED.items())
    # Percent signs end the program without M2, which would reset #5220.
    stdout, err = _rs274(theirs, "%\n" + probe + assign + "%\n")
    try:
        values = initial_parameters(str(ours / "a.var"))
    except GCodeError as error:
        assert err == error.message
        assert (theirs / "a.var").read_text() == text
        return
    assert err == ""
    expected_probe = " ".join(f"{values.get(n, 0.0):.6f}" for n in _PROBED)
    assert re.search(r'MESSAGE\("(.*)"\)', stdout).group(1) == expected_probe
    save_parameter_file(str(ours / "a.var"), {**values, **_ASSIGNED})
    for name in ("a.var", "a.var.bak"):
        assert (ours / name).read_text() == (theirs / name).read_text(), name


@pytest.mark.rs274
def test_defaults_match_rs274_without_v(tmp_path):
    probe = "(DEBUG," + " ".join(f"#{n}" for n in _PROBED) + ")\nM2\n"
    result = harness.run_rs274(tmp_path / "p.ngc", text=probe)
    expected = " ".join(f"{default_parameters().get(n, 0.0):.6f}" for n in _PROBED)
    assert re.search(r'MESSAGE\("(.*)"\)', result.stdout.decode()).group(1) == expected


def test_new_file_is_created_like_any_file_and_backup_keeps_old_mode(tmp_path):
    """rs274 writes FILE.new with fopen (0666 & ~umask), links the old file
    to FILE.bak (so it keeps its mode) and renames FILE.new over FILE."""
    path = tmp_path / "a.var"
    path.write_text("5161 1\n")
    os.chmod(path, 0o640)
    save_parameter_file(str(path), {5161: 2.0})
    umask = os.umask(0)
    os.umask(umask)
    assert oct(path.stat().st_mode & 0o777) == oct(0o666 & ~umask)
    assert oct((tmp_path / "a.var.bak").stat().st_mode & 0o777) == oct(0o640)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.var", "a.var.bak"]


def _rs274_with_var(folder: Path, var: str):
    """rs274's stdout and stderr (without "executing") for a tiny program."""
    (folder / "p.ngc").write_text("G0 X1\nM2\n")
    home = folder / "home"
    home.mkdir()
    done = subprocess.run(
        [harness.rs274_path(), "-v", var, "-g", "p.ngc"],
        cwd=folder,
        capture_output=True,
        text=True,
        env={**os.environ, "HOME": str(home)},
        timeout=60,
    )
    return done.returncode, done.stderr.replace("executing\n", "")


@pytest.mark.rs274
def test_directory_as_var_file_matches_rs274(tmp_path, capsys):
    """A folder given as -v reads as an empty file; both saves report the
    failed link and rename (perror's words) and leave FILE.new behind."""
    if harness.rs274_path() is None:
        pytest.skip("rs274 not on PATH")
    theirs, ours = tmp_path / "rs274", tmp_path / "ours"
    for folder in (theirs, ours):
        folder.mkdir()
        (folder / "a.var").mkdir()
    status, expected_err = _rs274_with_var(theirs, "a.var")
    capsys.readouterr()
    values = initial_parameters(str(ours / "a.var"))  # the start-up save
    save_parameter_file(str(ours / "a.var"), values)  # the save at exit
    assert status == 0
    assert capsys.readouterr().err == expected_err
    new = "a.var" + ".new"
    assert (ours / new).read_text() == (theirs / new).read_text()
