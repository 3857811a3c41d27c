"""Issue 38 item 8: a workspace one user cannot break for all. CHECK.DAT is never written with
more variables than its reader takes; a FIFO or a device in a file's place is refused at once by
every reader (a FIFO blocked ``check``, ``cell show`` and the monitor's EXECUTE for ever, and
/dev/zero as the keymap ate memory); a glTF's JSON nested 2000 deep is a message, not exit 70.

Each command runs in a process of its own with a timeout: a reader that blocks again fails the
test instead of hanging the suite."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from valterm.core.files.limits import MAX_VARIABLES
from valterm.core.files.variables import read_variables
from valterm.core.workspace import Workspace

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")

SECONDS = 60  # far above a refusal's fraction of a second; a blocked read never ends


def valterm(*args: str, stdin: str = "", env: dict[str, str] | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "valterm", *args], input=stdin, capture_output=True, text=True,
                          timeout=SECONDS, env={**os.environ, **(env or {})}, check=False)


@pytest.fixture
def workspace(tmp_path: Path) -> Path:
    Workspace.open(tmp_path / "ws")
    return tmp_path / "ws"


def assignments(first: str, count: int) -> str:
    return "".join(f"    {first}{n}={n}\n" for n in range(count))


def test_check_dat_is_never_written_with_more_variables_than_it_can_be_read_with(workspace: Path) -> None:
    (workspace / "ONE.DAT").write_text(assignments("A", 6000))
    (workspace / "TWO.DAT").write_text(assignments("B", 6000))
    (workspace / "SMALL.DAT").write_text("    C=1\n")
    assert valterm("run", "ONE", "--workspace", str(workspace)).returncode == 0
    second = valterm("run", "TWO", "--workspace", str(workspace))
    assert second.returncode != 0
    assert f"at most {MAX_VARIABLES}" in second.stderr and "CHECK.DAT" in second.stderr, second.stderr
    assert "Traceback" not in second.stderr
    kept = read_variables(workspace / "CHECK.DAT")  # still readable: the first run's variables
    assert len(kept) == 6000 and kept["A5999"] == 5999
    assert valterm("run", "SMALL", "--workspace", str(workspace)).returncode == 0  # the workspace still works
    assert read_variables(workspace / "CHECK.DAT")["C"] == 1


def test_writing_more_variables_than_the_limit_writes_nothing(tmp_path: Path) -> None:
    from valterm.core.files.errors import FileWriteError
    from valterm.core.files.variables import write_variables

    path = tmp_path / "CHECK.DAT"
    write_variables(path, {"X": 1.0})
    with pytest.raises(FileWriteError, match=f"{MAX_VARIABLES + 1} variables.*at most {MAX_VARIABLES}"):
        write_variables(path, {f"V{n}": float(n) for n in range(MAX_VARIABLES + 1)})
    assert read_variables(path) == {"X": 1.0}
    write_variables(path, {f"V{n}": float(n) for n in range(MAX_VARIABLES)})  # the limit itself is kept
    assert len(read_variables(path)) == MAX_VARIABLES


def test_a_fifo_named_like_a_program_is_refused_by_check(workspace: Path) -> None:
    os.mkfifo(workspace / "PIPE.DAT")
    done = valterm("check", "PIPE", "--workspace", str(workspace))
    assert done.returncode != 0 and "is a FIFO" in done.stderr + done.stdout, done


def test_a_fifo_named_like_a_setup_is_refused_by_cell_show(workspace: Path) -> None:
    os.mkfifo(workspace / "PIPE.SET")
    done = valterm("cell", "show", "PIPE", "--workspace", str(workspace))
    assert done.returncode != 0 and "is a FIFO" in done.stderr + done.stdout, done


def test_a_fifo_named_like_a_program_is_refused_by_the_monitors_execute(workspace: Path) -> None:
    os.mkfifo(workspace / "PIPE.DAT")
    done = valterm("monitor", "--workspace", str(workspace), stdin="EXECUTE PIPE\nTYPE 42\n")
    assert "IS A FIFO" in done.stdout.upper(), done
    assert done.stdout.rstrip().endswith("42")  # the prompt went on


def test_a_device_in_a_programs_place_is_refused(workspace: Path) -> None:
    os.symlink("/dev/zero", workspace / "ZERO.DAT")
    done = valterm("run", str(workspace / "ZERO.DAT"), "--workspace", str(workspace))
    assert done.returncode != 0 and "is a device" in done.stderr, done


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_a_special_keymap_file_is_refused_at_once(tmp_path: Path, kind: str) -> None:
    keymap = tmp_path / "keymap.toml"
    if kind == "fifo":
        os.mkfifo(keymap)
    else:
        os.symlink("/dev/zero", keymap)
    code = ("import sys\nfrom valterm.core.files.keymapfile import read_keymap\n"
            "from valterm.core.files.errors import FileProblem\n"
            "try:\n    read_keymap()\nexcept FileProblem as error:\n    print(error)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=SECONDS,
                          env={**os.environ, "VALTERM_KEYMAP": str(keymap)}, check=False)
    assert ("is a FIFO" if kind == "fifo" else "is a device") in done.stdout, done


def test_a_deeply_nested_gltf_is_a_message_not_a_recursion_error(tmp_path: Path, workspace: Path) -> None:
    deep = tmp_path / "deep.gltf"
    deep.write_text('{"asset": {"version": "2.0"}, "extras": ' + "[" * 2000 + "]" * 2000 + "}")
    done = valterm("import", str(deep), "--out", "DEEP.SET", "--workspace", str(workspace))
    assert done.returncode not in (0, 70) and "Traceback" not in done.stderr, done
    assert "nested" in done.stderr, done.stderr


@pytest.mark.parametrize("kind", ["fifo", "device"])
def test_a_special_key_script_or_cad_file_is_refused_at_once(tmp_path: Path, workspace: Path, kind: str) -> None:
    script, mesh = tmp_path / "MY.KEYS", tmp_path / "part.stl"
    for path in (script, mesh):
        if kind == "fifo":
            os.mkfifo(path)
        else:
            os.symlink("/dev/zero", path)
    said = "is a FIFO" if kind == "fifo" else "is a device"
    code = ("from valterm.core.files.demokeys import DemoScriptError, load_demo\n"
            f"try:\n    load_demo({str(script)!r})\nexcept DemoScriptError as error:\n    print(error)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=SECONDS, check=False)
    assert said in done.stdout, done
    done = valterm("import", str(mesh), "--out", "PART.SET", "--workspace", str(workspace))
    assert done.returncode != 0 and said in done.stderr, done


@pytest.mark.parametrize("name", ["part.igs", "part.step"])
def test_a_fifo_named_like_an_iges_or_step_file_is_refused_by_import(tmp_path: Path, workspace: Path,
                                                                     name: str) -> None:
    os.mkfifo(tmp_path / name)
    done = valterm("import", str(tmp_path / name), "--out", "PART.SET", "--workspace", str(workspace))
    assert done.returncode != 0 and "is a FIFO" in done.stderr, done


def test_the_one_read_path_refuses_a_link_when_asked_and_caps_the_size(tmp_path: Path) -> None:
    """What grading's confinement can ask of it: no link at all (``follow_links=False``)."""
    from valterm.core.files._text import read_bytes
    from valterm.core.files.errors import FileFormatError

    real = tmp_path / "REAL.DAT"
    real.write_bytes(b"    X=1\n")
    (tmp_path / "LINK.DAT").symlink_to(real)
    assert read_bytes(tmp_path / "LINK.DAT", "program") == b"    X=1\n"  # links are followed by default
    with pytest.raises(FileFormatError, match="LINK.DAT: is a symbolic link, not a program file"):
        read_bytes(tmp_path / "LINK.DAT", "program", follow_links=False)
    assert read_bytes(real, "program", follow_links=False) == b"    X=1\n"
    with pytest.raises(FileFormatError, match="REAL.DAT: 8 bytes is too large for a program file"):
        read_bytes(real, "program", limit=7)
