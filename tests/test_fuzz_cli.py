"""Property-based fuzzing through the command line's entry point, in-process (issue 16).

Mutated setup, location, program and IGES files, and random argument lists, go through
``valterm.cli.main([...])``. For every input: no exception escapes (argparse's SystemExit is
an exit status), no traceback and no Python warning is printed, a failure exits non-zero,
and its message names the file (and ``:line`` where the reader has one).

The run is bounded: ``VALTERM_FUZZ_EXAMPLES`` scales the examples per property (default
1: about 1 000 inputs in all, a few seconds each); hypothesis draws a fresh seed every run
and prints it (``--hypothesis-seed=N`` reproduces) when a property fails.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shutil
import tempfile
import warnings
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from valterm.cli import main
from valterm.core.workspace import Workspace, bundled_workspace_files

SCALE = float(os.environ.get("VALTERM_FUZZ_EXAMPLES", "1"))
IGES_SAMPLES = Path(__file__).parent / "data" / "iges"


def fuzz(examples: int):  # type: ignore[no-untyped-def]
    return settings(max_examples=max(1, int(examples * SCALE)), deadline=None, derandomize=False,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.function_scoped_fixture])


# -- the harness ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def workspace() -> Iterator[Path]:
    root = Path(tempfile.mkdtemp(prefix="valterm-fuzz-"))
    Workspace.open(root)
    (root / "HELLO.DAT").write_text("    TYPE HELLO\n")
    yield root
    shutil.rmtree(root, ignore_errors=True)


def call(argv: list[str]) -> tuple[int, str, str]:
    """``main(argv)`` in-process: (status, stdout, stderr); a Python warning fails the test."""
    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err), _stdin(""):
        warnings.simplefilter("always")
        try:
            status = main(argv)
        except SystemExit as exit_:  # argparse: usage errors and --help
            status = exit_.code if isinstance(exit_.code, int) else 2
    assert not caught, f"{repr(argv)[:200]}: warning {caught[0].category.__name__}: {caught[0].message}"
    text = out.getvalue() + err.getvalue()
    assert "Traceback" not in text and "Warning:" not in text, f"{repr(argv)[:200]}: {text[-2000:]}"
    return status, out.getvalue(), err.getvalue()


@contextlib.contextmanager
def _stdin(text: str) -> Iterator[None]:
    import sys

    saved = sys.stdin
    sys.stdin = io.StringIO(text)
    try:
        yield
    finally:
        sys.stdin = saved


def assert_located(status: int, err: str, file_name: str) -> None:
    """A failure names the file, as ``NAME:LINE: reason`` or ``NAME: reason``."""
    if status == 0:
        return
    assert re.search(rf"{re.escape(file_name)}(:\d+)?: \S", err), f"unlocated message: {err[:300]!r}"


# -- mutations ----------------------------------------------------------------------------------

NASTY = ["1e400", "-1e308", "nan", "inf", "9" * 5000, "0x10", "1_0", "١٢", "²", ".", "-", "1e", "1.5D+02",
         "\x00", "\t", ",,", " ", "\n", "\r", "\u00e9", "\ufeff", "MM", "IN", "W", "S", "1,8", "1,9",
         "POINT", "; ", "1,2", "99999", "-0", "1e16", "A" * 300]
CHARS = st.characters(codec="utf-8", exclude_categories=["Cs"])


@st.composite
def mutated(draw: st.DrawFn, text: str, nasty: list[str] = NASTY) -> str:
    """``text`` with a few random edits: a character range replaced, lines dropped or doubled,
    a nasty token inserted, the end cut off."""
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["replace", "token", "lines", "cut"]))
        if not text:
            text = draw(st.text(CHARS, max_size=20))
            continue
        at = draw(st.integers(0, len(text) - 1))
        if kind == "replace":
            span = draw(st.integers(0, 8))
            text = text[:at] + draw(st.text(CHARS, max_size=8)) + text[at + span:]
        elif kind == "token":
            text = text[:at] + draw(st.sampled_from(nasty)) + text[at:]
        elif kind == "lines":
            lines = text.splitlines(keepends=True)
            i = draw(st.integers(0, len(lines) - 1))
            j = draw(st.integers(i, min(len(lines), i + 3)))
            lines[i:j] = draw(st.sampled_from([[], lines[i:j] * 2, lines[i:j][::-1]]))
            text = "".join(lines)
        else:
            text = text[:at]
    return text


def _bundled(name: str) -> str:
    return dict(bundled_workspace_files())[name].read_text()


def _write(folder: Path, name: str, data: str | bytes) -> Path:
    path = folder / name
    if isinstance(data, str):
        data = data.encode("utf-8", errors="surrogatepass")
    path.write_bytes(data)
    return path


# -- setup files ----------------------------------------------------------------------------------

@fuzz(300)
@given(text=st.one_of(mutated(_bundled("CONV.SET")), mutated(_bundled("PROCESS.SET")), mutated("1\nMM\nW\n1,8\n0 0 0\n")))
def test_mutated_setup_files(workspace: Path, text: str) -> None:
    path = _write(workspace, "FUZZ.SET", text)
    status, _, err = call(["--workspace", str(workspace), "cell", "show", str(path), "--json"])
    assert status in (0, 1)  # 1: a bad file (exit codes: 0 ok, 1 failure, 2 usage)
    assert_located(status, err, "FUZZ.SET")


# -- location files ---------------------------------------------------------------------------------

@fuzz(200)
@given(text=st.one_of(mutated(_bundled("PROCESS.LOC")), mutated(_bundled("CONV.LOC"))))
def test_mutated_location_files(workspace: Path, text: str) -> None:
    _write(workspace, "FUZZ.LOC", text)
    status, _, err = call(["--workspace", str(workspace), "run", "HELLO", "--loc", "FUZZ"])
    assert status in (0, 1)
    assert_located(status, err, "FUZZ.LOC")


# -- programs ------------------------------------------------------------------------------------

# Numbers too large for a double (`X = 1e400`) included: the expression parser refuses them.
PROGRAM_NASTY = [*NASTY, "CALL FUZZ", "GOTO 10", "10 ", "IF X THEN", "END"]


@fuzz(300)
@given(text=st.one_of(mutated(_bundled("PROCESS.DAT"), PROGRAM_NASTY), mutated(_bundled("CONV1.DAT"), PROGRAM_NASTY)))
def test_mutated_programs_checked(workspace: Path, text: str) -> None:
    path = _write(workspace, "FUZZ.DAT", text)
    status, out, err = call(["--workspace", str(workspace), "check", str(path)])
    assert status in (0, 1)
    if status == 1 and err.strip():  # the file itself: `FUZZ.DAT:LINE: reason`
        assert_located(status, err, "FUZZ.DAT")
    elif status == 1:  # the checker's findings: `FUZZ step N: reason`
        assert re.search(r"FUZZ step \d+", out) or "FUZZ:" in out, out[:300]


# -- IGES files ------------------------------------------------------------------------------------

def _iges(name: str) -> str:
    return (IGES_SAMPLES / name).read_text(encoding="latin-1")


IGES_NASTY = NASTY + ["H", "1H,", "2H;;", ";", "E+", "0.D0", "         1D", "S      1", "T      1", "P      1",
                      "110,", "126,", "144,", "100,", "116,", "124,"]


@fuzz(60)
@given(text=st.one_of(mutated(_iges("valterm-arcs.iges"), IGES_NASTY),
                      mutated(_iges("valterm-points-metres.igs"), IGES_NASTY)))
def test_mutated_iges_files(workspace: Path, text: str) -> None:
    path = _write(workspace, "fuzz.igs", text)
    status, _, err = call(["--workspace", str(workspace), "import", str(path), "--out", "IGESFUZZ", "--force"])
    assert status in (0, 1)
    assert_located(status, err, "fuzz.igs")


# -- arguments --------------------------------------------------------------------------------------

WORDS = ["kin", "fk", "ik", "cell", "show", "check", "run", "import", "--json", "--point", "--config",
         "--cell", "--loc", "--loops", "--out", "--force", "--units", "--system", "--parts", "--collisions",
         "PROCESS", "CONV", "CONV1", "PROCESS.SET", "PROCESS.LOC", "HELLO", "DATFILER", "CHECK.DAT",
         "../etc/passwd", "/etc/passwd", "/dev/zero", "CON", "~root", "A" * 10_000, "X\x00Y", "a b",
         "0", "-90", "90", "1e308", "-1", "3", "1000000", "LEFTY,ABOVE,NOFLIP", "RIGHTY", "MM", "IN", "W",
         "S", "--", "-", "", "\u00e9", "--help"]
FINITE_KIN = ["0", "-90", "90", "180", "1e6", "-1e6", "45.5", "1e-300", "x", "--json", "--point", "2",
              "--config", "LEFTY,BELOW,FLIP", "RIGHTY,ABOVE", "", "1,2"]


@fuzz(300)
@given(argv=st.one_of(
    st.lists(st.sampled_from(WORDS), min_size=1, max_size=8),
    st.tuples(st.sampled_from(["cell", "check", "run", "import"]),
              st.lists(st.sampled_from(WORDS), max_size=5)).map(lambda t: [t[0], *t[1]]),
    # kin with finite, moderate numbers only: `kin ... inf/nan/1e300` is helper "ship"'s (commands/kin.py)
    st.tuples(st.sampled_from(["fk", "ik"]), st.lists(st.sampled_from(FINITE_KIN), max_size=8))
    .map(lambda t: ["kin", t[0], *t[1]]),
))
def test_random_arguments(workspace: Path, argv: list[str]) -> None:
    if "--help" in argv or any(w in ("app", "demo", "bench") for w in argv[:1]):
        return
    status, out, err = call(["--workspace", str(workspace), *argv])
    shown = repr(argv)[:200]
    assert isinstance(status, int)
    if status != 0:
        assert (out + err).strip(), f"{shown}: failed without a message"
        if "usage:" in err:
            return  # argparse's own messages (the parser in cli.py is helper ship's)
        longest = max((len(line) for line in err.splitlines()), default=0)
        assert longest < 1000, f"{shown}: a {longest}-character message: {err[:300]!r}"


@pytest.mark.parametrize("argv", [["kin", "fk", "0", "inf", "0", "0", "0", "0"],
                                  ["kin", "ik", "nan", "inf", "1e308", "0", "0", "0"],
                                  ["kin", "ik", "0", "1e300", "0", "0", "0", "0"]], ids=["fk-inf", "ik-nan", "ik-1e300"])
def test_kin_non_finite_arguments(argv: list[str]) -> None:
    status, _, err = call(argv)  # no traceback, no warning
    assert status != 0 and ("inf" in err or "nan" in err or "1e300" in err)
