"""Every command of the README's and the documentation site's ```bash blocks runs, at reduced size.

The commands are read from the pages themselves (README.md and docs/*.md): every line of a ```bash block
that is not a comment is a command, continuation lines (a trailing backslash) joined. A command is run
when each stage of its pipeline is `motionsig …`; the others (`make`, `pip`, `git`, a virtual
environment) and the commands that need a cluster we do not have are listed in SKIPPED with the reason,
and a test checks that SKIPPED is exactly what is skipped — a new command is run or listed, never
silently dropped.

Sizes are cut by REWRITES: each sets one option of one command (trials, runs, null trials, worker
processes) to a smaller value, or adds it where the page relies on a large default. That is the same code
path at a reduced size: the commands' Monte Carlo loops are vectorised over trials or runs, and a trial's
draws do not depend on how many there are. Every rewrite must apply to some command (a test), so the table
does not outlive the pages.

The input files the commands name (export.csv, dets.csv, radars.csv, stations.csv) are written here with
numpy and csv in the formats the page "Data formats" documents; a file an earlier command of the same
block writes (track.csv) is made by running that command first, as a reader of the page would.

Each command runs in a fresh temporary directory as `python -m motionsig_cli …` under bash's pipefail
(so a failing first stage of a pipe fails the command); it must exit 0, write a table to stdout (or to
its -o file), and write every file it names with -o/--out/--plot.
"""

from __future__ import annotations

import csv
import itertools
import os
import re
import shlex
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md")), *sorted((ROOT / "docs" / "howto").glob("*.md"))]
# Files shipped in the repository that a page's command may name by their path from the repository root
# (the how-to guides run from there): the command's directory gets these folders as links to the checkout.
SHIPPED = ("tests/data", "docs/howto/data")

# Commands that are not run, keyed by the command as printed (continuations joined, comment dropped).
SKIPPED: dict[str, str] = {
    "make demo": "installs the package into .venv and runs every demo at full size (make demo itself)",
    "make test": "the whole test suite, of which this test is a part",
    "source .venv/bin/activate": "activates the environment make demo creates (tests/test_quickstart.py)",
    "make docs": "the strict docs build (make test runs it)",
    "pip install 'motionsig_cli[dask]'": "installs from a package registry",
    "motionsig slrt --runs 1000 --scheduler tcp://10.0.0.5:8786 -o slrt.csv": (
        "needs a running Dask scheduler at that address; --scheduler is tested in tests/test_engine.py"
    ),
    "git clone <this repository> motionsig && cd motionsig": "a placeholder URL",
    "python3.11 -m venv venv && . venv/bin/activate": "creates a virtual environment",
    "pip install /path/to/motionsig": "installs from a placeholder path",
    "motionsig detect --montecarlo --workers N --scheduler ...": "a template (N, ...), not a command",
    "motionsig maneuver <file> --view events": "a template (<file>), not a command",
    "motionsig slrt <detections> --sensor-table <sensors>": "a template (<detections>, <sensors>), not a command",
}


@dataclass(frozen=True)
class Rewrite:
    """Set `option` to `value` in each stage `motionsig COMMAND …` that `when` matches (and `unless` does
    not): replaced where the page gives a larger value, added where the page relies on the default."""

    when: str  # a regex on the stage, without its leading "motionsig "
    option: str
    value: str
    why: str
    unless: str | None = None


# fmt: off
REWRITES: tuple[Rewrite, ...] = (
    Rewrite(r"^detect\b.*--(montecarlo|calibrate)", "--trials", "2",
            "Monte Carlo trials per (f_r, R) cell: the same bank over fewer trials (default 50)"),
    Rewrite(r"^detect\b.*--(calibrate|pfa)", "--null-trials", "100",
            "null records of the threshold calibration (default 20/P = 2000 at P = 0.01)"),
    Rewrite(r"^detect\b.*--workers", "--workers", "2", "a process pool of 2 instead of 8 (2 cores here)"),
    Rewrite(r"^detect\b.*--montecarlo.*--example 2d", "--horizons", "10,20",
            "the radar Monte Carlo's bank over 20 s instead of 80 s (default every 10 s to 80 s)"),
    Rewrite(r"^simulate\b.*--example 2d", "--duration", "20",
            "a 20 s radar record instead of 80 s: the same 187-filter sigma-point bank, 4x fewer steps"),
    Rewrite(r"^encode ebpsk\b.*--ber", "--trials", "2", "records per Eb/N0 of the BER curve (default 100)"),
    Rewrite(r"^mac-roc montecarlo\b", "--trials", "4096", "Monte Carlo trials (default and the page's 1e6)"),
    Rewrite(r"^slrt\b", "--runs", "2", "Monte Carlo runs per case (default 50; the pages give 20 to 1000)",
            unless=r"--input|--sensor-table|--view (detections|sensors)"),
    Rewrite(r"^maneuver\b", "--runs", "2", "Monte Carlo runs (default 500, the paper's; the pages give up to 5000)",
            unless=r"--input|--view measurements|--view front-end"),
    Rewrite(r"^track-sat simulate\b", "--runs", "20", "Monte Carlo runs (default 2000)"),
)
# fmt: on


@dataclass(frozen=True)
class DocCommand:
    page: str  # relative to the repository root
    line: int  # of the command's first line
    text: str  # as printed: continuations joined, a trailing comment dropped

    def __str__(self) -> str:
        return f"{self.page}:{self.line}: {self.text}"


def _drop_comment(line: str) -> str:
    """The line without a trailing shell comment (a '#' that starts a word outside quotes)."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i].rstrip()
    return line.rstrip()


def _fenced(page: Path, text: str) -> list[DocCommand]:
    """The commands of the page's ```bash blocks (every line that is not a comment), and the `motionsig`
    lines of its blocks without a language (examples shown beside a file's contents)."""
    found = []
    for block in re.finditer(r"^```(\w*)[ \t]*\n(.*?)^```", text, flags=re.S | re.M):
        if block.group(1) not in ("bash", ""):
            continue
        first = text.count("\n", 0, block.start(2)) + 1
        pending, start = "", 0
        for k, raw in enumerate(block.group(2).splitlines()):
            line = _drop_comment(raw.strip())
            if not pending and (not line or (block.group(1) == "" and not line.startswith("motionsig "))):
                continue
            start = start if pending else first + k
            pending = f"{pending} {line}".strip()
            if pending.endswith("\\"):
                pending = pending[:-1].rstrip()
                continue
            found.append(DocCommand(str(page.relative_to(ROOT)), start, pending))
            pending = ""
        assert not pending, f"{page.name}:{first}: a code block ends with a continuation line"
    return found


def _inline(page: Path, text: str) -> list[DocCommand]:
    """The inline code spans of the page's prose that are whole commands: `motionsig COMMAND …` with an
    option or `-` (`motionsig mac-roc`, a name, and `motionsig <command>: error: …`, a message, are not).
    A span may break across lines."""
    found = []
    prose = re.sub(r"^```.*?^```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S | re.M)
    for span in re.finditer(r"`(motionsig [^`]*)`", prose):
        cmd = " ".join(span.group(1).split())
        if re.match(r"motionsig [a-z][a-z-]*(\s|$)", cmd) and re.search(r"(?<!\S)-", cmd):
            found.append(DocCommand(str(page.relative_to(ROOT)), prose.count("\n", 0, span.start()) + 1, cmd))
    return found


def doc_commands() -> list[DocCommand]:
    """Every command of the README and the site's pages, in page order (code blocks, then inline spans)."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        found += sorted(_fenced(page, text) + _inline(page, text), key=lambda c: c.line)
    return found


def stages(text: str) -> list[str]:
    """The stages of a pipeline (no '|' inside quotes in the pages' commands: checked)."""
    parts = [p.strip() for p in text.split("|")]
    for p in parts:
        shlex.split(p)  # an unbalanced quote would mean a '|' inside quotes
    return parts


def runnable(cmd: DocCommand) -> bool:
    """Each stage is `motionsig …` (or `.venv/bin/motionsig …`), none needs a remote cluster, and the command
    is not a template (`...`, `<placeholder>`)."""
    return not re.search(r"\.\.\.|…|<", cmd.text) and all(
        re.match(r"(\.venv/bin/)?motionsig(\s|$)", s) and not re.search(r"--scheduler[ =]tcp://", s)
        for s in stages(cmd.text)
    )


def _set_option(stage: str, option: str, value: str) -> str:
    """`stage` with `option` set to `value`: lowered where given larger, appended where absent (a list the
    page gives is kept)."""
    m = re.search(rf"(?<!\S){re.escape(option)}[ =](\S+)", stage)
    if m is None:
        return f"{stage} {option} {value}"
    try:
        if float(m.group(1)) <= float(value):
            return stage
    except ValueError:  # a list (--horizons 20,80): the page's own choice stays
        return stage
    return stage[: m.start(1)] + value + stage[m.end(1) :]


def rewrite(text: str) -> tuple[str, list[Rewrite]]:
    """The command at reduced size, and the rewrites that changed it."""
    used, out = [], []
    for stage in stages(text):
        body = re.sub(r"^(\.venv/bin/)?motionsig\s*", "", stage)
        for rw in REWRITES:
            if re.search(rw.when, body) and not (rw.unless and re.search(rw.unless, body)):
                new = _set_option(body, rw.option, rw.value)
                if new != body:
                    used.append(rw)
                body = new
        out.append(body)
    return " | ".join(f"{shlex.quote(sys.executable)} -m motionsig_cli {b}".rstrip() for b in out), used


# ---------------------------------------------------------------------------------------------------------
# The input files, in the formats of the page "Data formats"


def _mapping(words: list[str], option: str) -> dict[str, str]:
    """`--columns role=Name,...` (or `--units role=unit,...`) of a command as a dict."""
    given = [b for a, b in itertools.pairwise(words) if a == option]
    return dict(pair.split("=", 1) for text in given for pair in text.split(",") if "=" in pair)


_KM = {"km": 1e-3, "m": 1.0}


def _detect_export(path: Path, words: list[str]) -> None:
    """A 1-D record for `detect export.csv …`: the time and position columns under the names `--columns`
    maps (else `timestamp`, `y`), the position in the unit `--units` gives (else m); ISO 8601 times at
    T = 0.1 s with one sample absent and the last blank; 40 s of mode 1's signature (a_sig = 0.5, m_rho = 10,
    f_c = 0.5 Hz: the README's --mrho 10 --fc 0.5) in noise of variance 1e-3 m²."""
    from motionsig_cli.signals.modes import table1_code

    names, units = {"time": "timestamp", "y": "y", **_mapping(words, "--columns")}, _mapping(words, "--units")
    g = np.random.default_rng(1)
    n = 400
    t = np.arange(n) * 0.1
    chips = np.repeat(2.0 * table1_code(1) - 1.0, 10)  # bit 1 → +1, bit 0 → −1; m_rho = 10 samples per chip
    z = np.resize(chips, n) * np.cos(2 * np.pi * 0.5 * t)  # eq 1 at f_c = 0.5 Hz, theta = 0
    y = (0.5 * z + g.standard_normal(n) * np.sqrt(1e-3)) * _KM[units.get("y", "m")]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([names["time"], names["y"]])
        for k in range(n):
            if k == 2:
                continue  # an absent sample: a predict-only step
            stamp = f"2026-05-01T12:{int(t[k]) // 60:02d}:{t[k] % 60:06.3f}Z"
            w.writerow([stamp, "" if k == n - 1 else f"{y[k]:.12g}"])


def _maneuver_export(path: Path, words: list[str]) -> None:
    """A track for `maneuver --input export.csv …`: the columns under the names `--columns` maps (else
    `timestamp`, `east`, `north`, aliases of time, x, y), positions in the unit `--units` gives (else m);
    ISO 8601 times 1 s apart with a few ms of jitter, one scan absent and one blank; 120 s of a target at
    300 m/s that turns through 90° at 3°/s, with 100 m noise."""
    names = {"time": "timestamp", "x": "east", "y": "north", **_mapping(words, "--columns")}
    units = _mapping(words, "--units")
    g = np.random.default_rng(2)
    n = 120
    t = np.arange(n, dtype=float)
    heading = np.radians(np.clip(t - 60, 0, 30) * 3.0)
    pos = {"x": np.cumsum(300 * np.cos(heading)), "y": np.cumsum(300 * np.sin(heading))}
    pos = {r: (v + g.standard_normal(n) * 100) * _KM[units.get(r, "m")] for r, v in pos.items()}
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([names["time"], names["x"], names["y"]])
        for k in range(n):
            if k == 30:
                continue  # an absent scan: missed
            sec = t[k] + g.uniform(-0.003, 0.003)
            stamp = f"2026-05-01T12:{int(sec) // 60:02d}:{sec % 60:06.3f}Z"
            w.writerow([stamp, "", ""] if k == 50 else [stamp, f"{pos['x'][k]:.10g}", f"{pos['y'][k]:.10g}"])


def _slrt_files(dets: Path, radars: Path) -> None:
    """The two files of `slrt --input dets.csv --sensor-table radars.csv`: the sensors table of the page
    (two radars), and 10 scans of detections (T = 2 s, range and bearing in degrees) of a target moving at
    (100, 50) m/s from (0, 0), with the missed detections and one clutter detection per scan."""
    g = np.random.default_rng(3)
    sensors = {"north": (-12000.0, 4000.0, 30.0, 0.15, 0.9), "east": (14000.0, -2000.0, 45.0, 0.25, 0.8)}
    with open(radars, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["sensor", "x", "y", "sigma_r", "sigma_phi", "pd", "clutter", "fov"])
        for name, (sx, sy, sr, sp, pd) in sensors.items():
            w.writerow([name, sx, sy, sr, sp, pd, 4, 30000])
    with open(dets, "w", newline="") as f:
        f.write("# T: 2\n")
        w = csv.writer(f)
        w.writerow(["time", "sensor", "range", "bearing [deg]"])
        for k in range(10):
            tx, ty = 200.0 * k, 100.0 * k
            stamp = f"2026-05-01T12:00:{2 * k:02d}Z"
            for name, (sx, sy, sr, sp, pd) in sensors.items():
                if g.uniform() < pd:
                    r = np.hypot(tx - sx, ty - sy) + g.standard_normal() * sr
                    b = np.degrees(np.arctan2(ty - sy, tx - sx)) + g.standard_normal() * sp
                    w.writerow([stamp, name, f"{r:.1f}", f"{b:.3f}"])
                w.writerow([stamp, name, f"{g.uniform(100, 29000):.1f}", f"{g.uniform(-179, 179):.3f}"])


def _stations(path: Path) -> None:
    """Five ground stations 3-15 km around Munich airport (WGS-84 latitude, longitude [deg], altitude [m]),
    as the README's `track-sat … --receivers stations.csv --aircraft 48.3538,11.7861,3.45` describes them."""
    rows = [("MUC", 48.3538, 11.7861, 453.0), ("FRS", 48.3720, 11.9890, 480.0), ("ERD", 48.4260, 11.6240, 430.0),
            ("MOO", 48.2280, 11.8260, 510.0), ("NEU", 48.2730, 11.7050, 460.0)]  # fmt: skip
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["receiver", "latitude", "longitude", "altitude"])
        w.writerows(rows)


_WRITTEN_HERE = {"export.csv", "dets.csv", "radars.csv", "stations.csv"}


def _words(text: str) -> list[str]:
    return shlex.split(text.replace("|", " "))


def outputs(text: str) -> list[str]:
    """The files a command names with -o/--out/--plot/--plot-…."""
    w = _words(text)
    return [b for a, b in itertools.pairwise(w) if a in ("-o", "--out") or a.startswith("--plot")]


def _shipped(word: str) -> bool:
    return any(word.startswith(f"{d}/") for d in SHIPPED)


def prerequisites(cmd: DocCommand) -> list[DocCommand]:
    """The earlier commands of the same page that write a file `cmd` reads (other than the test's inputs
    and the files shipped in the repository): a .csv, .json or .gz file, or a directory (`ck/`) that an
    earlier command writes and this one names."""
    earlier = [c for c in COMMANDS[: COMMANDS.index(cmd)] if c.page == cmd.page]
    written_before = {name for e in earlier for name in outputs(e.text)}
    first = []
    for name in sorted(
        {w for w in _words(cmd.text) if w.endswith((".csv", ".json", ".gz")) or w in written_before}
        - _WRITTEN_HERE
        - set(outputs(cmd.text))
        - {w for w in _words(cmd.text) if _shipped(w)}
    ):
        maker = [e for e in earlier if name in outputs(e.text)]
        assert maker, f"{cmd}: reads {name}, which neither the test nor an earlier command of the page writes"
        first.append(maker[-1])
    return first


def write_inputs(cmd: DocCommand, where: Path) -> None:
    """Write the files of _WRITTEN_HERE that `cmd` names into `where`."""
    words = _words(cmd.text)
    if "export.csv" in words:
        (_detect_export if "detect" in words else _maneuver_export)(where / "export.csv", words)
    if {"dets.csv", "radars.csv"} & set(words):
        _slrt_files(where / "dets.csv", where / "radars.csv")
    if "stations.csv" in words:
        _stations(where / "stations.csv")
    for shipped in SHIPPED:
        if any(w.startswith(f"{shipped}/") for w in words) and not (where / shipped).exists():
            (where / shipped).parent.mkdir(parents=True, exist_ok=True)
            (where / shipped).symlink_to(ROOT / shipped, target_is_directory=True)


# ---------------------------------------------------------------------------------------------------------


def run_documented(cmd: DocCommand) -> str | None:
    """Run `cmd` (after its prerequisites) in a fresh directory; None if it did what the page says, else
    what went wrong."""
    env = {**os.environ, "COLUMNS": "120", "MPLBACKEND": "Agg"}
    with tempfile.TemporaryDirectory(prefix="docs_cmd_") as tmp:
        where = Path(tmp)
        for c in [*prerequisites(cmd), cmd]:
            write_inputs(c, where)
            line, _ = rewrite(c.text)
            p = subprocess.run(["bash", "-o", "pipefail", "-c", line], cwd=where, env=env,
                               capture_output=True, text=True, timeout=300)  # fmt: skip
            said = f"{c}\n  ran: {line}\n  "
            if p.returncode != 0:
                return f"{said}exit {p.returncode}: {p.stderr.strip()[-2000:]}"
            if not {"-o", "--out"} & set(_words(c.text)) and not p.stdout.strip():
                return f"{said}wrote nothing to stdout"
            for name in outputs(c.text):
                if not (where / name).is_file() or (where / name).stat().st_size == 0:
                    return f"{said}did not write {name}"
    return None


COMMANDS = doc_commands()


def test_the_pages_have_commands_and_every_skip_is_listed():
    """Every command is run or listed in SKIPPED, and every SKIPPED entry is a command of a page."""
    assert len(COMMANDS) > 50, len(COMMANDS)
    not_run = {c.text for c in COMMANDS if not runnable(c)}
    assert not_run - set(SKIPPED) == set(), (
        f"not run, but not listed in SKIPPED: {sorted(not_run - set(SKIPPED))}"
    )
    assert set(SKIPPED) - not_run == set(), (
        f"SKIPPED lists what no page has or what runs: {set(SKIPPED) - not_run}"
    )


def test_every_rewrite_applies_to_some_command():
    used = {rw for c in COMMANDS if runnable(c) for rw in rewrite(c.text)[1]}
    assert set(REWRITES) <= used, [rw.why for rw in REWRITES if rw not in used]


def test_rewrites_only_lower_sizes():
    """The rewrite sets a given value only downwards, and adds the option where it is absent."""
    assert _set_option("slrt --runs 1000", "--runs", "2") == "slrt --runs 2"
    assert _set_option("maneuver --runs 1", "--runs", "2") == "maneuver --runs 1"
    assert (
        _set_option("mac-roc montecarlo --ell 8", "--trials", "4096")
        == "mac-roc montecarlo --ell 8 --trials 4096"
    )
    assert (
        _set_option("mac-roc montecarlo --trials 1e6", "--trials", "4096")
        == "mac-roc montecarlo --trials 4096"
    )


@pytest.mark.slow
def test_every_documented_command_runs():
    todo = [c for c in COMMANDS if runnable(c)]
    unique = list({c.text: c for c in reversed(todo)}.values())[::-1]  # the same command on two pages: once

    with ThreadPoolExecutor(max_workers=2) as pool:
        failures = [f for f in pool.map(run_documented, unique) if f]
    assert not failures, "\n\n".join(failures)
