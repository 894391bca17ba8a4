"""`motionsig encode`: outputs, pipes, metadata, exit codes, one-line errors, atomic writes."""

import io
import subprocess
import sys

import pytest

from motionsig_cli.cli.app import main
from motionsig_cli.tables import read_table


def run(capsys, *args, stdin=None, monkeypatch=None):
    if stdin is not None:
        monkeypatch.setattr(sys, "stdin", io.StringIO(stdin))
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def parse(text, tmp_path, name="o.csv"):
    p = tmp_path / name
    p.write_text(text)
    return read_table(p)


def test_mseq_matlab_vector(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "mseq", "--poly", "x^5+x^2+1", "--init", "00001")
    assert rc == 0
    t = parse(out, tmp_path)
    assert "".join(t.column("value")) == "1000010010110011111000110111010"
    assert t.meta["command"] == "encode mseq" and t.meta["poly_octal"] == "45" and t.meta["init"] == "00001"


def test_gold_member_is_table1_mode1(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "encode", "gold", "--poly1", "45", "--poly2", "75", "--index", "9", "--shift", "8"
    )
    assert rc == 0
    assert "".join(parse(out, tmp_path).column("value")) == "1100001010111001011011000011011"


def test_pipe_gold_family_into_correlations(capsys, tmp_path, monkeypatch):
    rc, out, _ = run(capsys, "encode", "gold", "--all", "--chips", "bipolar")
    assert rc == 0
    rc, out2, err = run(
        capsys, "encode", "correlations", "-", "--view", "values", stdin=out, monkeypatch=monkeypatch
    )
    assert rc == 0
    t = parse(out2, tmp_path)
    assert t.numeric("value", integer=True).tolist() == [-9, -1, 7]
    assert t.meta["within_gold_bound"] is True and t.meta["gold_bound"] == 9 and t.meta["codes"] == 33
    # the producer's provenance travels with the result
    assert t.meta["input_meta"]["command"] == "encode gold" and t.meta["input_meta"]["poly2"] == "75"
    assert "within" in err


def test_table1_printed_fails_bound(capsys, tmp_path, monkeypatch):
    _, out, err = run(capsys, "encode", "table1", "--codes", "printed")
    assert "not Gold codes" in err
    rc, out2, _ = run(capsys, "encode", "correlations", "-", stdin=out, monkeypatch=monkeypatch)
    t = parse(out2, tmp_path)
    assert rc == 0 and t.meta["within_gold_bound"] is False and t.meta["max_offpeak"] == 17


def test_table1_errata_view(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "table1", "--view", "errata")
    assert rc == 0
    t = parse(out, tmp_path)
    assert t.column("edit_distance") == ["0", "1", "2"] and t.column("matches_stored") == ["true"] * 3
    assert t.column("differences")[1] == "chip 15: Gold 0, printed 1"


def test_gps_summary(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "gps", "--prn", "1-3", "--summary", "--format", "json")
    assert rc == 0
    import json

    doc = json.loads(out)
    assert [r["first10_octal"] for r in doc["data"]] == ["1440", "1620", "1710"]
    assert doc["meta"]["prn"] == [1, 2, 3]


def test_pairs_degree5(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "pairs", "--degree", "5", "-q")
    t = parse(out, tmp_path)
    assert rc == 0 and len(t.rows) == 12


def test_check_pair(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "check-pair", "--poly1", "45", "--poly2", "51", "-q")
    assert rc == 0  # a non-preferred pair is a result here, not an error
    t = parse(out, tmp_path)
    assert t.column("preferred") == ["false"] and t.column("values") == ["-9 -5 -1 3 7 11"]


def test_signature_csv_and_plot(capsys, tmp_path):
    out_csv, out_png = tmp_path / "s.csv", tmp_path / "s.png"
    rc, out, _ = run(
        capsys,
        "encode",
        "signature",
        "--mode",
        "2",
        "--theta",
        "random",
        "--seed",
        "5",
        "--out",
        str(out_csv),
        "--plot",
        str(out_png),
    )
    assert rc == 0 and out == ""
    t = read_table(out_csv)
    assert len(t.rows) == 620 and t.meta["seed"] == 5 and 0 <= t.meta["theta"] < 6.2832
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # same seed -> same theta
    rc, out, _ = run(capsys, "encode", "signature", "--theta", "random", "--seed", "5", "--length", "3")
    assert parse(out, tmp_path).meta["theta"] == t.meta["theta"]


def test_missing_input_file(capsys):
    rc, _, err = run(capsys, "encode", "correlations", "/nonexistent.csv")
    assert rc == 2 and "/nonexistent.csv: cannot read" in err


def test_debug_shows_traceback(capsys):
    with pytest.raises(Exception, match="not primitive"):
        main(["encode", "mseq", "--poly", "44", "--debug"])


def test_failed_run_keeps_existing_file(capsys, tmp_path, monkeypatch):
    """Atomic write: an error while rendering leaves the previous file intact and no temp file."""
    target = tmp_path / "keep.csv"
    target.write_text("old\n")
    import motionsig_cli.tables as tables

    def boom(*a, **k):
        raise RuntimeError("disk full")

    monkeypatch.setattr(tables, "render", boom)  # the command layer renders through tables.render
    rc = main(["encode", "mseq", "--out", str(target)])
    assert rc == 1 and "internal error: RuntimeError: disk full" in capsys.readouterr().err
    assert target.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["keep.csv"]


def test_help_shows_example(capsys):
    rc = main(["encode", "gold", "--help"])
    out = capsys.readouterr().out
    assert rc == 0 and "Example:" in out and "motionsig encode gold --poly1 45" in out


def _sh(cmd):
    return subprocess.run(["bash", "-o", "pipefail", "-c", cmd], capture_output=True, text=True, timeout=120)


def test_real_pipe_and_module_entry():
    exe = f"{sys.executable} -m motionsig_cli"
    r = _sh(f"{exe} encode table1 | {exe} encode correlations - -q --view values")
    assert r.returncode == 0, r.stderr
    rows = [tuple(map(int, ln.split(","))) for ln in r.stdout.strip().splitlines()[-3:]]
    # same numbers as the core computed in-process (the pipe must not change them) ...
    import numpy as np

    from motionsig_cli.signals.correlation import periodic_correlation, to_bipolar
    from motionsig_cli.signals.modes import corrected_codes

    rr = periodic_correlation(to_bipolar(corrected_codes()))
    auto = np.concatenate([rr[i, i, 1:] for i in range(3)])
    cross = rr[np.triu_indices(3, 1)].ravel()
    assert rows == [(v, int(np.sum(auto == v)), int(np.sum(cross == v))) for v in (-9, -1, 7)]
    # ... and account for every lag: 3 codes x 30 off-peak auto lags, 3 pairs x 31 cross lags
    assert sum(a for _, a, _ in rows) == 90 and sum(c for _, _, c in rows) == 93


def test_closed_pipe_exits_quietly():
    """`| true` closes the pipe before anything is read, so the write must fail with EPIPE; with
    pipefail the pipeline's status is motionsig's own."""
    exe = f"{sys.executable} -m motionsig_cli"
    r = _sh(f"{exe} encode gps --prn 1-32 | true")
    assert r.returncode == 0 and r.stderr == "", r.stderr


def test_bom_and_strict_stdin_decoding():
    exe = f"{sys.executable} -m motionsig_cli"
    r = _sh(
        f"printf '\\xef\\xbb\\xbfcode,chip,value\\na,0,1\\na,1,0\\na,2,1\\n' | {exe} encode correlations - -q"
    )
    assert r.returncode == 0, r.stderr
    r = _sh(f"printf 'code,chip,value\\na,0,\\xff\\n' | {exe} encode correlations -")
    assert r.returncode == 2 and "not a UTF-8 text file" in r.stderr


def test_bad_out_leaves_no_plot(capsys, tmp_path):
    plot = tmp_path / "s.png"
    rc, _, err = run(
        capsys, "encode", "signature", "--plot", str(plot), "--out", str(tmp_path / "no" / "x.csv")
    )
    assert rc == 2 and "--out" in err and not plot.exists()


def test_out_follows_symlinks_and_spares_special_files(capsys, tmp_path):
    import os
    import stat

    real = tmp_path / "real.csv"
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    assert run(capsys, "encode", "mseq", "--out", str(link))[0] == 0
    assert link.is_symlink() and real.read_text().startswith("# command")
    before = os.stat("/dev/null").st_mode
    assert run(capsys, "encode", "mseq", "--out", "/dev/null")[0] == 0
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode) and os.stat("/dev/null").st_mode == before


def test_out_file_permissions_follow_umask(capsys, tmp_path):
    import os

    old = os.umask(0o022)
    try:
        assert run(capsys, "encode", "mseq", "--out", str(tmp_path / "p.csv"))[0] == 0
    finally:
        os.umask(old)
    assert (tmp_path / "p.csv").stat().st_mode & 0o777 == 0o644


def test_json_is_strict_even_with_nonfinite_input_meta(capsys, tmp_path):
    import json

    src = tmp_path / "c.csv"
    src.write_text("# x: NaN\n# y: Infinity\ncode,chip,value\na,0,1\na,1,0\na,2,1\n")
    rc, out, _ = run(capsys, "encode", "correlations", str(src), "-f", "json", "-q")
    doc = json.loads(out, parse_constant=lambda c: pytest.fail(f"non-strict JSON constant {c}"))
    assert rc == 0 and doc["meta"]["input_meta"]["x"] is None


def test_degree_list_is_deduplicated(capsys, tmp_path):
    rc, out, _ = run(capsys, "encode", "pairs", "--degree", "5,5,5", "-q")
    assert rc == 0 and len(parse(out, tmp_path).rows) == 12


def test_no_gold_bound_without_gold_family(capsys, tmp_path):
    src = tmp_path / "c.csv"
    src.write_text("code,chip,value\na,0,1\na,1,0\na,2,1\n")  # N = 3 = 2^2 - 1: no Gold family at n = 2
    rc, out, _ = run(capsys, "encode", "correlations", str(src), "-q")
    assert rc == 0 and parse(out, tmp_path).meta["gold_bound"] is None
