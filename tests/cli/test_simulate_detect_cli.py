"""`motionsig simulate | motionsig detect`: pipe, metadata, determinism, bad input (issue's list)."""

import io
import sys

import pytest

from motionsig_cli.cli.app import main
from motionsig_cli.tables import read_table


def run(capsys, monkeypatch, *args, stdin=None):
    if stdin is not None:
        monkeypatch.setattr(sys, "stdin", io.StringIO(stdin))
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def table(text, tmp_path):
    p = tmp_path / "t.csv"
    p.write_text(text)
    return read_table(p)


@pytest.fixture(scope="module")
def record():
    """A short simulate record (20 s) shared by the tests."""
    import contextlib

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert (
            main(["simulate", "--mode", "3", "--tau-chips", "7", "--R", "1e-3", "--duration", "20", "-q"])
            == 0
        )
    return buf.getvalue()


def test_simulate_metadata_and_determinism(record, capsys, monkeypatch, tmp_path):
    t = table(record, tmp_path)
    assert t.meta["mode"] == 3 and t.meta["tau"] == 140 and t.meta["n_samples"] == 400
    assert t.meta["seed"] == 2008 and t.meta["anr_db_paper_ln"] == pytest.approx(48.283, abs=1e-3)  # spec E5
    assert len(t.rows) == 400
    rc, again, _ = run(
        capsys,
        monkeypatch,
        "simulate",
        "--mode",
        "3",
        "--tau-chips",
        "7",
        "--R",
        "1e-3",
        "--duration",
        "20",
        "-q",
    )
    assert rc == 0 and again == record  # same seed, same bytes


def test_anr_db_conventions(capsys, monkeypatch, tmp_path):
    """--anr-db is true decibels by default (94.3 dB is R ≈ 4.6e-11); the paper's 'dB' is 10·ln, read with
    --db-convention paper-ln: 94.3 'dB' ↔ R ≈ 1e-5."""
    _, out, _ = run(
        capsys, monkeypatch, "simulate", "--anr-db", "94.335", "--db-convention", "paper-ln", "--duration",
        "1", "-q",
    )  # fmt: skip
    assert table(out, tmp_path).meta["R"] == pytest.approx(1e-5, rel=1e-3)
    _, out, _ = run(capsys, monkeypatch, "simulate", "--anr-db", "94.3", "--duration", "1", "-q")
    assert table(out, tmp_path).meta["R"] == pytest.approx(4.6e-11, rel=2e-2)


def test_pipe_detects_truth(record, capsys, monkeypatch, tmp_path):
    rc, out, err = run(capsys, monkeypatch, "detect", "-", "--horizons", "10,20", stdin=record)
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.column("correct") == ["true", "true"] and t.column("mode_hat") == ["3", "3"]
    assert t.meta["input_meta"]["command"] == "simulate" and t.meta["n_filters"] == 187


def test_candidate_table(record, capsys, monkeypatch, tmp_path):
    rc, out, _ = run(capsys, monkeypatch, "detect", "-", "--horizons", "20", "--candidates", stdin=record)
    t = table(out, tmp_path)
    assert rc == 0 and len(t.rows) == 93
    lam = t.numeric("Lambda")
    j0, jc, js = t.numeric("J0"), t.numeric("J_cos"), t.numeric("J_sin")
    assert max(abs(lam - (2 * j0 - jc - js))) < 1e-9 * max(abs(lam))  # eq (52)


def test_threshold_decision(record, capsys, monkeypatch, tmp_path):
    rc, out, _ = run(
        capsys, monkeypatch, "detect", "-", "--horizons", "20", "--threshold", "-1e9", stdin=record
    )
    assert rc == 0 and table(out, tmp_path).column("signature_present") == ["true"]


def _split(record):
    lines = record.splitlines()
    first = next(i for i, ln in enumerate(lines) if not ln.startswith("#")) + 1  # first data row
    return lines, first


def drop_R_meta(lines, first):
    return [ln for ln in lines if not ln.startswith("# R:")]


def rename_y(lines, first):
    return [ln.replace("k,t,y,", "k,t,yy,") for ln in lines]


def repeat_a_row(lines, first):  # t goes 0.10, 0.10: not increasing
    return [*lines[: first + 3], lines[first + 2], *lines[first + 3 :]]


def drop_a_row(lines, first):  # a gap of 2T: one absent sample
    return [*lines[: first + 3], *lines[first + 4 :]]


def nan_measurement(lines, first):
    k, t, _y, rest = lines[first].split(",", 3)
    return [*lines[:first], f"{k},{t},nan,{rest}", *lines[first + 1 :]]


def bad_T_meta(lines, first):
    return [('# T: "fast"' if ln.startswith("# T:") else ln) for ln in lines]


def bad_mrho_meta(lines, first):
    return [("# m_rho: 0" if ln.startswith("# m_rho:") else ln) for ln in lines]


BAD_RECORDS = [
    (drop_R_meta, "missing metadata 'R'"),
    (bad_T_meta, "metadata 'T' must be a positive number"),
    (bad_mrho_meta, "bad metadata: m_rho = 0 is not in "),
    (rename_y, "missing column 'y'"),
    (repeat_a_row, "time is not increasing"),
]


def _edit(record, fn):
    return "\n".join(fn(*_split(record))) + "\n"


@pytest.mark.parametrize(("edit", "text"), BAD_RECORDS)
def test_bad_records(record, capsys, monkeypatch, tmp_path, edit, text):
    target = tmp_path / "o.csv"
    rc, out, err = run(capsys, monkeypatch, "detect", "-", "--out", str(target), stdin=_edit(record, edit))
    assert rc == 2 and len(err.strip().splitlines()) == 1 and text in err, err
    assert out == "" and not target.exists()


@pytest.mark.parametrize(
    ("edit", "where"), [(drop_a_row, "column 't': no row for t = "), (nan_measurement, "column 'y'")]
)
def test_missing_samples_are_predict_only_in_the_bank_and_refused_by_fft(
    record, capsys, monkeypatch, tmp_path, edit, where
):
    """A missing sample (an absent row, a NaN) is a predict-only step of the filter bank; the FFT path, which
    assumes every sample, refuses it naming the file, line and column."""
    rc, out, err = run(capsys, monkeypatch, "detect", "-", stdin=_edit(record, edit))
    assert rc == 0 and "1 of 400 samples missing (predict-only)" in err, err
    full = run(capsys, monkeypatch, "detect", "-", stdin=record)[1]
    assert out.splitlines()[-1].split(",")[2:4] == full.splitlines()[-1].split(",")[2:4]  # same mode and τ
    assert out.splitlines()[-1] != full.splitlines()[-1]  # but not the same statistic: a sample was skipped
    rc, out, err = run(capsys, monkeypatch, "detect", "-", "--method", "fft", stdin=_edit(record, edit))
    assert rc == 2 and out == "" and "<stdin>:" in err and where in err and "use --method bank" in err, err


BAD_OPTIONS = [
    (["--horizons", "30"], "--horizons", "longer than the record"),
    (["--horizons", "0"], "--horizons", "> 0"),
    (["--fc-grid", ","], "--fc-grid", "no frequency"),
    (["--Q0", "1,1,-1,1"], "--Q0", "PSD"),
    (["--Q0", "1,1,1"], "--Q0", "4 variances"),
    (["--Qa", "-1"], "--Qa", "PSD"),
    (["--c-r", "0"], "--c-r", "> 0"),
]


@pytest.mark.parametrize(("args", "option", "text"), BAD_OPTIONS)
def test_bad_detect_options(record, capsys, monkeypatch, args, option, text):
    rc, _, err = run(capsys, monkeypatch, "detect", "-", *args, stdin=record)
    assert rc == 2 and len(err.strip().splitlines()) == 1 and option in err and text in err, err


def test_montecarlo_small(capsys, monkeypatch, tmp_path):
    rc, out, _ = run(
        capsys,
        monkeypatch,
        "detect",
        "--montecarlo",
        "--trials",
        "3",
        "--fr-list",
        "0.01",
        "--R-list",
        "1e-1",
        "--horizons",
        "10,20",
        "-q",
    )
    t = table(out, tmp_path)
    assert rc == 0 and len(t.rows) == 2 and t.meta["trials"] == 3
    assert t.column("seed_anr_label") == ["2.2", "2.2"]
    assert t.meta["chance_pct"] == pytest.approx(100 / 93)
