"""``motionsig simulate``: every configuration check reaches the user as one usage line naming the option
that set the field; options of the other example are refused; the record-reader helpers of ``detect``."""

import pytest
import typer

from tests.cli.helpers import run, table


@pytest.mark.parametrize(
    ("args", "option", "text"),
    [
        (["--tau", "1", "--tau-chips", "2"], "--tau-chips", "not both"),
        (["--tau", "9007199254740993"], "--tau", "2^53"),
        (["--tau-chips", "1125899906842624"], "--tau-chips", "2^53"),
        (["--mrho", "0"], "--mrho", "integer >= 1"),
        (["--fc", "-1"], "--fc", "is not in [0, inf)"),
        (["--a-sig", "-1"], "--a-sig", "is not in [0, inf)"),
        (["--a-r", "nan"], "--a-r", "is not in [0, inf)"),
        (["--f-r", "-0.1"], "--f-r", "is not in [0, inf)"),
        (["--sigma-a", "-1"], "--sigma-a", "is not in [0, inf)"),
        (["--pole-wn", "0"], "--pole-wn", "> 0"),
        (["--pole-zeta", "1"], "--pole-zeta", "is not in (0, 1)"),
        (["--T", "1e-300"], "--T", "pole placement"),
        (["--T", "inf"], "--T", "> 0"),
        (["--K", "1,nan"], "--K", "finite"),
        (["--theta", "inf"], "--theta", "not a finite number"),
        (["--theta", "abc"], "--theta", "could not convert"),
        (["--zdot", "foo"], "--zdot", "is not one of analytic, finite-difference"),
        (["--duration", "1e6"], "--duration", "more than 1000000"),
        (["--duration", "0.01"], "--duration", "shorter than one sample"),
        (["--anr-db", "nan"], "--anr-db", "not a finite number"),
        (["--anr-db", "1e6"], "--anr-db", "too large"),
        (["--a-sig", "0", "--anr-db", "40"], "--a-sig", "is not > 0"),
        (["--K", "1e9,1e9", "--duration", "20"], "--K", "unstable"),
        (["--R-range", "1"], "--R-range", "applies to --example 2d only"),
        (["--R-bearing", "1"], "--R-bearing", "applies to --example 2d only"),
        (["--anr-pair", "2"], "--anr-pair", "applies to --example 2d only"),
        (["--start", "1,2"], "--start/--sig-axes", "applies to --example 2d only"),
        (["--sig-axes", "x"], "--start/--sig-axes", "applies to --example 2d only"),
        (["--example", "2d", "--R", "1e-3"], "--R", "applies to --example 1d"),
        (["--example", "2d", "--anr-db", "40"], "--anr-db", "applies to --example 1d"),
        (["--example", "2d", "--anr-pair", "5"], "--anr-pair", "ANR pairs 1-4"),
        (["--example", "2d", "--anr-pair", "2", "--R-range", "1e-3"], "--anr-pair", "not both"),
        (["--example", "2d", "--R-range", "0", "--R-bearing", "1e-3"], "--R-range", "> 0"),
        (["--example", "2d", "--R-range", "1e-3", "--R-bearing", "-1"], "--R-bearing", "> 0"),
        (["--example", "2d", "--a-sig", "0"], "--a-sig", "is not > 0"),
        (["--example", "2d", "--start", "0,0"], "--start", "origin"),
        (["--example", "2d", "--start", "1,2,3"], "--start", "two finite coordinates"),
        (["--example", "2d", "--start", "a,b"], "--start", "comma-separated"),
        (
            ["--example", "2d", "--R-range", "100", "--R-bearing", "1e-3", "--duration", "3"],
            "--R-range",
            "radar",
        ),
        (["--example", "2d", "--start", "-5,-5", "--duration", "60"], "--start", "too close to the radar"),
        (["--example", "2d", "--K", "1e9,1e9", "--duration", "20"], "--K", "unstable"),
    ],
)
def test_bad_options_name_the_option(capsys, args, option, text):
    rc, out, err = run(capsys, "simulate", *args)
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert f"Invalid value for {option}:" in err.replace("'", "") and text in err, err


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
