"""``motionsig simulate``: every configuration check reaches the user as one usage line naming the option
that set the field; options of the other example are refused; the record-reader helpers of ``detect``."""

import math
from decimal import Decimal, localcontext

import pytest
import typer

from tests.cli.helpers import run, table


def test_zero_signature_amplitude_simulates(capsys, tmp_path):
    """a_sig = 0 is a record without a signature: its ANR in dB is absent, not an error."""
    rc, out, err = run(capsys, "simulate", "--a-sig", "0", "--duration", "1")
    meta = table(out, tmp_path).meta
    assert rc == 0 and meta["anr_linear"] == 0 and meta["anr_db_log10"] is None and "(ANR 0)" in err


def test_2d_record_metadata_options(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "simulate", "--example", "2d", "--anr-pair", "2", "--sig-axes", "x", "--duration", "2"
    )
    t = table(out, tmp_path)
    assert rc == 0 and t.meta["anr_pair"] == 2 and t.meta["seed_anr_pair_labels"] == [32.2, 60.2]
    assert t.meta["sig_axes"] == "x" and len(t.rows) == 40
    assert "spec" not in t.meta["assumptions"] and "does not state" in t.meta["assumptions"]


def test_parse_horizons_is_a_usage_error_naming_horizons():
    from motionsig_cli.cli.records import parse_horizons

    assert parse_horizons(None, 25.0, 0.05) == [10.0, 20.0] and parse_horizons("5,15", 20.0, 0.05) == [
        5.0,
        15.0,
    ]
    for text, reason in (("30", "longer than the record"), ("0", "> 0"), ("x", "comma-separated")):
        with pytest.raises(typer.BadParameter, match=reason) as exc:
            parse_horizons(text, 20.0, 0.05)
        assert exc.value.param_hint == "--horizons"


def test_old_names_of_the_record_reader_still_work():
    from motionsig_cli.cli import records
    from motionsig_cli.modesig import lmp_record, record_reading

    assert records.finite_column is record_reading.finite_column
    assert records.uniform_times is record_reading.uniform_times
    assert records.truth_of is record_reading.truth_of and records.sigma_meta is lmp_record.sigma_meta
    with pytest.raises(AttributeError):
        records.no_such_name  # noqa: B018


def _anr_record(capsys, tmp_path, *args: str):
    rc, out, err = run(capsys, "simulate", "--duration", "1", "-q", *args)
    assert rc == 0, err
    return table(out, tmp_path).meta


def test_anr_db_is_true_decibels_by_default(capsys, tmp_path):
    """--anr-db 21 is ANR = 10^2.1 = a_sig²/(2R): R = 0.25/(2·10^2.1), 10^2.1 computed here in 40-digit
    decimal arithmetic (the metadata's R is written with repr, so it round-trips exactly)."""
    with localcontext() as ctx:
        ctx.prec = 40
        expected = float(Decimal("0.25") / (2 * Decimal(10) ** Decimal("2.1")))
    meta = _anr_record(capsys, tmp_path, "--anr-db", "21")
    assert math.isclose(meta["R"], expected, rel_tol=1e-12)
    assert meta["db_convention"] == "log10" and meta["anr_db"] == 21.0
    assert meta["anr_db_log10"] == pytest.approx(21.0, abs=1e-9)
    assert meta["anr_db_paper_ln"] == pytest.approx(21.0 * math.log(10), abs=1e-9)  # 48.35
    keys = list(meta)
    assert keys.index("anr_db_paper_ln") + 1 == keys.index("anr_db") == keys.index("db_convention") - 1
    assert _anr_record(capsys, tmp_path, "--anr-db", "21", "--db-convention", "log10") == meta


def test_paper_ln_reads_the_paper_labels(capsys, tmp_path):
    """The paper's label 48.3 (10·ln of ANR) is R = 0.125·e^(-4.83) = 9.98e-4, the paper's R = 1e-3 up to
    the label's rounding (10·ln 125 = 48.283)."""
    meta = _anr_record(capsys, tmp_path, "--db-convention", "paper-ln", "--anr-db", "48.3")
    assert math.isclose(meta["R"], 0.125 * math.exp(-4.83), rel_tol=1e-12)
    assert meta["R"] == pytest.approx(1e-3, rel=2e-3) and meta["anr_db_paper_ln"] == pytest.approx(48.3)
    assert meta["db_convention"] == "paper-ln" and meta["anr_db"] == 48.3
    assert meta["anr_db_log10"] == pytest.approx(48.3 / math.log(10))  # 20.98 true dB


def test_records_from_R_name_no_convention(capsys, tmp_path):
    """A record simulated from --R (or the default R) carries no dB value to interpret: no convention key."""
    for args in ((), ("--R", "1e-3"), ("--db-convention", "paper-ln")):
        meta = _anr_record(capsys, tmp_path, *args)
        assert "db_convention" not in meta and "anr_db" not in meta
        assert meta["R"] == (1e-3 if args[:1] == ("--R",) else 1e-5)


def test_detect_reads_a_record_with_the_convention(capsys, tmp_path):
    path = tmp_path / "rec.csv"
    rc, _, err = run(
        capsys, "simulate", "--anr-db", "94.3", "--db-convention", "paper-ln", "--mode", "3", "--tau-chips",
        "7", "--duration", "10", "-q", "-o", str(path),
    )  # fmt: skip
    assert rc == 0, err
    rc, out, err = run(capsys, "detect", str(path), "--horizons", "10", "-q")
    t = table(out, tmp_path)
    assert rc == 0, err
    assert t.meta["input_meta"]["db_convention"] == "paper-ln" and t.column("mode_hat") == ["3"]
