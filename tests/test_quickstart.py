"""The README's quick start, as a new user follows it: ``make demo``, then ``motionsig`` on the PATH (activate
``.venv``, or the ``./motionsig`` wrapper), then ``make docs``.

``make demo`` itself (a virtual environment and a package install) is not run here; what it promises is
checked piece by piece: the wrapper runs the checkout's ``.venv/bin/motionsig`` with the arguments intact and
says what to do when there is none; the activation line names the environment the Makefile creates; every
command of the demo writes its table to a file under ``$(OUT)`` (the terminal gets a short story), and every
file the final lines of the story name is one the demo writes.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MAKEFILE = (ROOT / "Makefile").read_text()
README = (ROOT / "README.md").read_text()


def _demo_recipe() -> list[str]:
    return MAKEFILE.split("\ndemo:", 1)[1].split("\n\n", 1)[0].splitlines()[1:]


def _quick_start() -> str:
    return README.split("## Quick start", 1)[1].split("\n## ", 1)[0]


def _wrapper_in(tmp_path: Path, with_venv: bool) -> Path:
    """A copy of the checkout's ./motionsig wrapper in a directory with (or without) a .venv whose
    bin/motionsig prints its arguments, one per line."""
    shutil.copy(ROOT / "motionsig", tmp_path / "motionsig")
    if with_venv:
        (tmp_path / ".venv" / "bin").mkdir(parents=True)
        fake = tmp_path / ".venv" / "bin" / "motionsig"
        fake.write_text(f"#!/bin/sh\nexec {shlex.quote(sys.executable)} -c 'import sys; print(*sys.argv[1:], sep=chr(10))' \"$@\"\n")
        fake.chmod(0o755)
    return tmp_path / "motionsig"


def test_the_wrapper_runs_the_checkouts_venv_with_the_arguments_intact(tmp_path):
    wrapper = _wrapper_in(tmp_path, with_venv=True)
    p = subprocess.run([str(wrapper), "detect", "a file.csv", "--pfa", "0.01"], capture_output=True, text=True,
                       cwd="/", check=False)  # fmt: skip
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines() == ["detect", "a file.csv", "--pfa", "0.01"]


def test_the_wrapper_without_a_venv_says_to_run_make_demo(tmp_path):
    wrapper = _wrapper_in(tmp_path, with_venv=False)
    p = subprocess.run([str(wrapper), "--help"], capture_output=True, text=True, check=False)
    assert p.returncode == 2 and p.stdout == ""
    assert len(p.stderr.splitlines()) == 1 and "make demo" in p.stderr, p.stderr


def test_the_wrapper_runs_the_real_command_line_when_the_venv_has_it(tmp_path):
    """With a .venv whose motionsig is this checkout's command line, ./motionsig --version answers."""
    wrapper = _wrapper_in(tmp_path, with_venv=False)
    (tmp_path / ".venv" / "bin").mkdir(parents=True)
    exe = tmp_path / ".venv" / "bin" / "motionsig"
    exe.write_text(f"#!/bin/sh\nexec {shlex.quote(sys.executable)} -m motionsig_cli \"$@\"\n")
    exe.chmod(0o755)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.run([str(wrapper), "--version"], capture_output=True, text=True, env=env, check=False)
    assert p.returncode == 0, p.stderr
    assert re.search(r"\d+\.\d+", p.stdout), p.stdout


def test_the_quick_start_activates_the_venv_the_makefile_creates_and_names_make_docs():
    quick = _quick_start()
    venv = re.search(r"^VENV\s*:=\s*(\S+)", MAKEFILE, flags=re.M).group(1)
    steps = [s for s in ("make demo", f"source {venv}/bin/activate", "motionsig --help", "make docs", "site/index.html")
             if s in quick]  # fmt: skip
    assert steps == ["make demo", f"source {venv}/bin/activate", "motionsig --help", "make docs", "site/index.html"]
    assert quick.index("make demo") < quick.index("source") < quick.index("make docs")
    assert "./motionsig" in quick
    site_dir = re.search(r"^site_dir:\s*(\S+)", (ROOT / "mkdocs.yml").read_text(), flags=re.M).group(1)
    assert f"{site_dir}/index.html" in quick
    assert re.search(r"^docs:", MAKEFILE, flags=re.M)


def test_every_demo_command_writes_its_table_to_a_file_under_out():
    """The terminal gets the story; each command's table goes to -o $(OUT)/NAME (none to stdout), and each
    command is announced by an echo naming that file."""
    recipe = _demo_recipe()
    commands = [line.strip().lstrip("@") for line in recipe if "$(BIN)/motionsig" in line]
    assert len(commands) > 10
    written = []
    for cmd in commands:
        last = cmd.split("|")[-1]
        m = re.search(r"-o \$\(OUT\)/(\S+\.csv)\b", last)
        assert m, f"the table of this demo command goes to the terminal: {cmd}"
        written.append(m.group(1))
        assert ">" not in cmd and "grep" not in cmd, cmd
    story = "\n".join(line for line in recipe if line.strip().startswith("@echo"))
    for name in written:
        assert name in story, f"the story does not say where {name} went"
    assert len(set(written)) == len(written)
