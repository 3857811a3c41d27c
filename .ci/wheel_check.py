"""CI: valterm as a user installs it. Builds the sdist and, from it, the wheel; checks both
carry the bundled data; installs the wheel into a fresh venv outside the checkout; then,
from another folder, runs the subcommands and the app and the museum demo under a
pseudo-terminal for a few seconds (they must still be running, no traceback). With --suite it
also runs the whole test suite from the unpacked sdist against that wheel (CI does).

Usage: python .ci/wheel_check.py [--keep] [--suite]   (python needs the ``build`` package: the
``test`` extra has it). Exit 0 when every check passed, 1 otherwise.
"""

from __future__ import annotations

import fcntl
import os
import pty
import re
import select
import shutil
import signal
import struct
import subprocess
import sys
import tarfile
import tempfile
import termios
import time
import tomllib
import zipfile
from pathlib import Path

CHECKOUT = Path(__file__).resolve().parent.parent
RUNNING_SECONDS = 6.0  # how long the app and the demo must stay up under the pty
ESCAPES = re.compile(rb"\x1b(\[[0-9;?<>=]*[ -/]*[@-~]|\][^\x07\x1b]*(\x07|\x1b\\)|[@-_])")

failures: list[str] = []


def check(ok: bool, what: str, detail: str = "") -> None:
    print(f"{'ok  ' if ok else 'FAIL'} {what}" + (f"\n{detail.rstrip()}" if detail and not ok else ""), flush=True)
    if not ok:
        failures.append(what)


def sh(*argv: str | Path, cwd: Path, env: dict[str, str] | None = None, timeout: float = 600) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(a) for a in argv], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout, stdin=subprocess.DEVNULL)


DATA_FOLDERS = ("assets", "cells", "programs")  # the top level's data (valterm/core/resources.py)


def bundled_files() -> list[str]:
    """Every file the wheel must carry besides its modules (paths inside the wheel): the top
    level's data under valterm/data/ (setup.py copies it there) and the styles."""
    data = [f"valterm/data/{p.relative_to(CHECKOUT)}" for folder in DATA_FOLDERS
            for p in (CHECKOUT / folder).rglob("*") if p.is_file() and "__pycache__" not in p.parts]
    styles = [str(p.relative_to(CHECKOUT)) for p in (CHECKOUT / "valterm").rglob("*.tcss")]
    return sorted(data + styles)


def repository_files() -> list[str]:
    """Every file the sdist must carry: it is the repository (data, docs, tests, CI)."""
    listed = subprocess.run(["git", "ls-files"], cwd=CHECKOUT, capture_output=True, text=True)
    if listed.returncode != 0:  # not a git checkout: the folders themselves
        return sorted(str(p.relative_to(CHECKOUT)) for folder in ("valterm", "tests", "docs", *DATA_FOLDERS)
                      for p in (CHECKOUT / folder).rglob("*") if p.is_file() and "__pycache__" not in p.parts)
    return sorted(name for name in listed.stdout.splitlines() if not name.startswith(".git"))


def build(dist: Path) -> tuple[Path, Path]:
    # the sdist first, then the wheel built from the unpacked sdist: a file missing from the
    # sdist is missing from the wheel too, and the checks below catch it
    result = sh(sys.executable, "-m", "build", "--outdir", dist, CHECKOUT, cwd=dist.parent)
    check(result.returncode == 0, "build the sdist and the wheel", result.stdout + result.stderr)
    sdists, wheels = sorted(dist.glob("*.tar.gz")), sorted(dist.glob("*.whl"))
    if not (sdists and wheels):
        raise SystemExit("no sdist or wheel was built")
    return sdists[0], wheels[0]


def check_archives(sdist: Path, wheel: Path) -> None:
    wanted = bundled_files()
    check(len(wanted) > 10 and any(w.endswith("PUMA.toml") for w in wanted), "the checkout has its data files")
    with tarfile.open(sdist) as tar:
        in_sdist = {name.split("/", 1)[1] for name in tar.getnames() if "/" in name}
    missing = [w for w in repository_files() if w not in in_sdist]
    check(not missing, "the sdist is the repository (every file git tracks)", "missing: " + " ".join(missing))
    with zipfile.ZipFile(wheel) as whl:
        in_wheel = set(whl.namelist())
    missing = [w for w in wanted if w not in in_wheel]
    check(not missing, f"the wheel holds valterm/data and the styles ({len(wanted)} files)", "missing: " + " ".join(missing))


def check_sdist_suite(sdist: Path, wheel: Path, top: Path) -> None:
    """The whole suite from the unpacked sdist, against the wheel built from it installed in a
    fresh venv with the test extras (issue 37: the sdist is the repository)."""
    with tarfile.open(sdist) as tar:
        tar.extractall(top / "sdist", filter="data")
    (source,) = (top / "sdist").iterdir()
    venv = top / "venv-tests"
    result = sh(sys.executable, "-m", "venv", venv, cwd=top)
    check(result.returncode == 0, "a fresh venv for the sdist's suite", result.stderr)
    result = sh(venv / "bin" / "python", "-m", "pip", "install", "-q", f"{wheel}[test]", cwd=top, timeout=1200)
    check(result.returncode == 0, "pip install the wheel with its test extras", result.stdout[-2000:] + result.stderr[-3000:])
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    chosen = os.environ.get("VALTERM_SDIST_TESTS", "").split()  # a few test files, to try this step alone
    result = sh(venv / "bin" / "python", "-I", "-m", "pytest", "-p", "no:cacheprovider", "-m", "slow or not slow", *chosen, cwd=source, env=env,
                timeout=2400)
    tail = "\n".join(result.stdout.splitlines()[-15:])
    print(f"the sdist's suite: {result.stdout.splitlines()[-1] if result.stdout else '(no output)'}", flush=True)
    check(result.returncode == 0, "the whole suite passes from the unpacked sdist (the wheel installed)",
          tail + result.stderr[-2000:])


def install(wheel: Path, venv: Path) -> Path:
    result = sh(sys.executable, "-m", "venv", venv, cwd=venv.parent)
    check(result.returncode == 0, "a fresh venv", result.stderr)
    result = sh(venv / "bin" / "python", "-m", "pip", "install", "-q", wheel, cwd=venv.parent)
    check(result.returncode == 0, "pip install the wheel into it", result.stdout + result.stderr)
    return venv / "bin" / "valterm"


def user_env(home: Path) -> dict[str, str]:
    """A user's environment: no checkout on the path, their own home and state folder."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VALTERM_WORKSPACE", "VIRTUAL_ENV")}
    return {**env, "HOME": str(home), "XDG_STATE_HOME": str(home / "state"), "TERM": "xterm-256color"}


def check_commands(valterm: Path, folder: Path, env: dict[str, str]) -> None:
    version = tomllib.loads((CHECKOUT / "pyproject.toml").read_text())["project"]["version"]
    ws = str(folder / "ws")

    def run(what: str, *argv: str, status: int = 0, out: str = "") -> None:
        result = sh(valterm, *argv, cwd=folder, env=env, timeout=300)
        text = result.stdout + result.stderr
        ok = result.returncode == status and out in result.stdout and "Traceback" not in text
        check(ok, f"{what}: `valterm {' '.join(argv)}` exits {status}",
              f"exit {result.returncode}\n--- stdout\n{result.stdout[-3000:]}\n--- stderr\n{result.stderr[-3000:]}")

    run("version", "--version", out=f"valterm {version}\n")
    run("help", "--help", out="VALTERM_WORKSPACE")
    run("cell show", "--workspace", ws, "cell", "show", "PROCESS.SET", out="PROCESS.SET: ")
    run("cell show (--workspace after)", "cell", "show", "CONV", "--workspace", ws, out="CONV.SET: ")
    run("run", "--workspace", ws, "run", "PROCESS.DAT", "--cell", "PROCESS.SET", "--loc", "PROCESS.LOC", out="WHERE")
    # CONV1 with CONV2 runs to its end under the 1985 rules; under the controller's the real wrist
    # meets JT4's stop in CONV2 (docs/MOTION.md; tests/test_case_studies.py): status 1
    run("run --json", "--workspace", ws, "run", "CONV1", "--cell", "CONV", "--loc", "CONV", "--json",
        out='"event": "end"')
    run("run --rules controller", "--workspace", ws, "run", "CONV1", "--cell", "CONV", "--loc", "CONV",
        "--rules", "controller", status=1, out="JOINT 4 BEYOND ITS STOP")
    run("check", "--workspace", ws, "check", "PROCESS.DAT", "CONV1", "CONV2", out="PROCESS: ")
    run("kin fk", "kin", "fk", "0", "-90", "90", "0", "0", "0", out="NOFLIP")
    run("kin ik", "kin", "ik", "0", "158.75", "990.6", "90", "-90", "0", "--json", out='"joints"')
    # the PUMA 560 from the robot file the wheel carries (assets/robot/PUMA560.toml)
    run("kin fk --robot PUMA560", "kin", "fk", "0", "90", "-90", "0", "0", "0", "--robot", "PUMA560", out="1535.43")
    run("run --robot PUMA560", "--workspace", ws, "run", "PROCESS.DAT", "--cell", "PROCESS.SET", "--loc",
        "PROCESS.LOC", "--robot", "PUMA560", status=1, out="BEYOND THE PUMA 560'S STOPS")
    run("a usage error", "kin", "fk", "1", "2", "3", status=2)
    run("a missing file", "--workspace", ws, "run", "NOSUCH", status=1)
    cube = folder / "cube.obj"
    cube.write_text("".join(f"v {x} {y} {z}\n" for x in (0, 50) for y in (0, 50) for z in (0, 50))
                    + "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n")
    run("import", "--workspace", ws, "import", str(cube), "--out", "CUBE", out="CUBE.SET written")
    run("cell show of the import", "--workspace", ws, "cell", "show", "CUBE", out="CUBE.SET: 1 object")
    # grading against the bundled PROCESS cell: a student who leaves part 1 where it is passes
    (folder / "TASK.toml").write_text('cell = "PROCESS"\nlocations = ["PROCESS"]\n'
                                      '[[part]]\nnumber = 1\nposition = [440, -50, -320]\n')
    (folder / "STAY.DAT").write_text("    READY\n")
    run("grade", "grade", "TASK.toml", "STAY.DAT", "--junit", "grades.xml", out="1 PASSED")
    check((folder / "grades.xml").is_file(), "grade --junit writes its file in the current folder")
    logs = sorted((Path(env["XDG_STATE_HOME"]) / "valterm").glob("*.log"))
    check(not logs, "no crash logs", "\n".join(str(p) for p in logs))


def under_pty(argv: list[str], cwd: Path, env: dict[str, str], seconds: float, quit_keys: bytes = b"",
              width: int = 80, height: int = 24) -> tuple[bool, int | None, str]:
    """Run ``argv`` in a terminal of the given size for ``seconds``: (still running then, its
    exit status, the screen text written without escape sequences). ``quit_keys`` are then
    typed and it has 10 s to end by itself (the status is None if it did not)."""
    pid, fd = pty.fork()
    if pid == 0:  # the child: a terminal of the asked size, then the program
        try:
            fcntl.ioctl(0, termios.TIOCSWINSZ, struct.pack("HHHH", height, width, 0, 0))
            os.chdir(cwd)
            os.execve(argv[0], argv, env)
        finally:
            os._exit(127)
    output = b""
    status: int | None = None
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if select.select([fd], [], [], 0.05)[0]:
            try:
                output += os.read(fd, 65536)
            except OSError:  # the terminal closed: the program ended
                pass
        ended, code = os.waitpid(pid, os.WNOHANG)
        if ended:
            status = os.waitstatus_to_exitcode(code)
            break
    running = status is None
    if running and quit_keys:
        os.write(fd, quit_keys)
        deadline = time.monotonic() + 10
        while status is None and time.monotonic() < deadline:
            if select.select([fd], [], [], 0.05)[0]:
                try:
                    output += os.read(fd, 65536)
                except OSError:
                    pass
            ended, code = os.waitpid(pid, os.WNOHANG)
            if ended:
                status = os.waitstatus_to_exitcode(code)
    while status is not None and select.select([fd], [], [], 0.2)[0]:  # what it wrote before it ended
        try:
            chunk = os.read(fd, 65536)
        except OSError:
            break
        if not chunk:
            break
        output += chunk
    if status is None:
        os.kill(pid, signal.SIGTERM)
        for _ in range(50):
            ended, _code = os.waitpid(pid, os.WNOHANG)
            if ended:
                break
            time.sleep(0.1)
        else:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
    os.close(fd)
    return running, status, ESCAPES.sub(b"", output).decode("utf-8", "replace")


def check_interactive(valterm: Path, folder: Path, env: dict[str, str]) -> None:
    ws = str(folder / "ws-app")
    state = Path(env["XDG_STATE_HOME"]) / "valterm"
    ctrl_q = b"\x11"
    for what, argv, expect, quit_keys in (
        ("the app", [str(valterm), "--workspace", ws, "--setup", "PROCESS"], "MAIN MENU", ctrl_q),
        ("the museum demo", [str(valterm), "--workspace", ws, "demo"], "VAL-II", b""),
    ):
        running, status, screen = under_pty(argv, folder, env, RUNNING_SECONDS, quit_keys)
        logs = sorted(state.glob("*.log"))
        ok = running and expect in screen and "Traceback" not in screen and "Error" not in screen and not logs
        label = f"{what} runs {RUNNING_SECONDS:g} s in an 80x24 terminal (`{' '.join(argv[1:])}`)"
        if quit_keys:
            label += ", then Ctrl-Q ends it with status 0"
            ok = ok and status == 0
        crash = "".join(f"--- {log}\n{log.read_text()[-3000:]}" for log in logs)
        check(ok, label,
              f"running: {running}, exit status: {status}\n--- screen text (last 2000 chars)\n{screen[-2000:]}\n{crash}")


def check_readme_example(python: Path, folder: Path, env: dict[str, str]) -> None:
    """The README's Pilot example (valterm.testing), run as written by the installed package."""
    readme = (CHECKOUT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.DOTALL)
    check(bool(blocks), "README.md has a python example")
    if not blocks:
        return
    script = folder / "readme_example.py"
    script.write_text(blocks[0], encoding="utf-8")
    result = sh(python, script, cwd=folder, env=env, timeout=300)
    check(result.returncode == 0 and ". WHERE" in result.stdout,
          "the README's valterm.testing example runs as written from the installed wheel",
          result.stdout[-2000:] + result.stderr[-3000:])


def main() -> int:
    keep = "--keep" in sys.argv[1:]
    top = Path(tempfile.mkdtemp(prefix="valterm-wheel-check-")).resolve()
    if top.is_relative_to(CHECKOUT):
        raise SystemExit("the temporary folder must lie outside the checkout")
    try:
        (top / "dist").mkdir()
        (top / "home").mkdir()
        (top / "elsewhere").mkdir()
        sdist, wheel = build(top / "dist")
        check_archives(sdist, wheel)
        if "--suite" in sys.argv[1:]:
            check_sdist_suite(sdist, wheel, top)
        valterm = install(wheel, top / "venv")
        env = user_env(top / "home")
        if valterm.exists():
            check_commands(valterm, top / "elsewhere", env)
            check_interactive(valterm, top / "elsewhere", env)
            check_readme_example(valterm.parent / "python", top / "elsewhere", env)
    finally:
        if keep:
            print(f"kept {top}")
        else:
            shutil.rmtree(top, ignore_errors=True)
    print(f"wheel check: {'FAILED: ' + '; '.join(failures) if failures else 'all passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
