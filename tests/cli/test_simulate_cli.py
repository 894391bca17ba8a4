"""``motionsig simulate``: every configuration check reaches the user as one usage line naming the option
that set the field; options of the other example are refused; the record-reader helpers of ``detect``."""

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
    from motionsig_cli.experiments import lmp_record, record_reading

    assert records.finite_column is record_reading.finite_column
    assert records.uniform_times is record_reading.uniform_times
    assert records.truth_of is record_reading.truth_of and records.sigma_meta is lmp_record.sigma_meta
    with pytest.raises(AttributeError):
        records.no_such_name  # noqa: B018
