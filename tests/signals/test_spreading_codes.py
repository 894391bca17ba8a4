"""The tables of ``motionsig encode`` (signals.code_sets): contents, the round trip through a CSV
file, and a ConfigError naming the field for every checked parameter."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.signals import code_sets as sc
from motionsig_cli.signals import gold, modes
from motionsig_cli.signals.lfsr import MSequenceConfig
from motionsig_cli.signals.signature import MAX_SAMPLES, SignatureConfig
from motionsig_cli.tables import render


def _raises(field, fn, *args, **kwargs):
    with pytest.raises(ConfigError) as exc:
        fn(*args, **kwargs)
    assert exc.value.field == field, exc.value
    return exc.value


@pytest.mark.parametrize(
    ("field", "call"),
    [
        ("chips", lambda: sc.mseq_table(MSequenceConfig(), "ternary")),
        ("chips", lambda: sc.gps_table([1], True, "hex")),
        ("prn", lambda: sc.gps_table([1, 33])),
        ("codes", lambda: sc.table1_table("as-printed")),
        ("view", lambda: sc.table1_table("corrected", "everything")),
        ("chips", lambda: sc.table1_table("corrected", "summary", "hex")),
        ("index", lambda: sc.gold_table(gold.GoldConfig(), (31, 0))),
        ("degree", lambda: sc.pairs_table([5, 8])),
        ("degree", lambda: sc.pairs_table([5, 15])),
        ("degree", lambda: sc.pairs_table([2.5])),
        ("theta", lambda: sc.resolve_theta("abc", 1)),
        ("theta", lambda: sc.resolve_theta("nan", 1)),
        ("theta", lambda: sc.resolve_theta("-inf", 1)),
        ("mode", lambda: sc.signature_table(4, "corrected", SignatureConfig())),
        ("codes", lambda: sc.signature_table(1, "as-printed", SignatureConfig())),
        ("zdot", lambda: sc.signature_table(1, "corrected", SignatureConfig(), zdot="central")),
        ("length", lambda: sc.signature_table(1, "corrected", SignatureConfig(), length=0)),
        ("length", lambda: sc.signature_table(1, "corrected", SignatureConfig(), length=MAX_SAMPLES + 1)),
        ("length", lambda: sc.signature_table(1, "corrected", SignatureConfig(), length=2.5)),
        ("m_rho", lambda: sc.signature_table(1, "corrected", SignatureConfig(m_rho=10**9))),
        ("T", lambda: sc.signature_table(1, "corrected", SignatureConfig(T=1e308), length=3)),
    ],
)
def test_bad_parameter_names_its_field(field, call):
    _raises(field, call)


def test_pairs_are_checked_before_any_search():
    calls = []
    _raises("degree", sc.pairs_table, [5, 15], calls.append)
    assert calls == []
    table, note = sc.pairs_table([3, 5], calls.append)
    assert (
        calls == [1, 1]
        and [r[0] for r in table.rows].count(5) == 12
        and note.startswith("13 preferred pairs")
    )


def test_correlations_view_is_checked(tmp_path):
    codes = sc.CodeSet(["a"], np.array([[1, -1, 1]]), {})
    _raises("view", sc.correlations_table, codes, "-", "lags")


@pytest.mark.parametrize("chips", sc.CHIPS)
def test_gold_family_round_trip_through_a_file(tmp_path, chips):
    """gold_table → CSV file → load_codes gives back the family as ±1 chips, labels and provenance."""
    table = sc.gold_table(gold.GoldConfig(), None, chips)
    path = tmp_path / "gold.csv"
    path.write_text(render(table, "csv"))
    got = sc.load_codes(str(path))
    _, fam = gold.gold_family(0o45, 0o75)
    assert np.array_equal(got.codes, 2 * fam.astype(np.int64) - 1)
    assert got.labels[:3] == ["gold_k-2", "gold_k-1", "gold_k0"] and got.meta["command"] == "encode gold"
    table, note = sc.correlations_table(got, str(path), "values")
    assert [r[0] for r in table.rows] == [-9, -1, 7] and table.meta["within_gold_bound"] is True
    assert note.endswith("Gold bound t(5) = 9: within")


@pytest.mark.parametrize("view", sc.TABLE1_VIEWS)
@pytest.mark.parametrize("codes", modes.VARIANTS)
def test_table1_every_view(view, codes):
    table, warning = sc.table1_table(codes, view)
    assert table.meta["view"] == view and table.meta["source"].startswith("the mode-signature paper")
    assert len(table.rows) == (93 if view == "codes" else 3)
    assert bool(warning) == (codes == "printed" and view == "codes")


@pytest.mark.parametrize("view", sc.CORRELATION_VIEWS)
def test_correlation_views_of_table1(view):
    codes = sc.CodeSet(["m1", "m2", "m3"], modes.table1_codes().astype(np.int64) * 2 - 1, {})
    table, _ = sc.correlations_table(codes, "-", view)
    n_rows = {"summary": 6, "values": 3, "full": 6 * 31}[view]
    assert len(table.rows) == n_rows and table.meta["max_offpeak"] == 9


def test_resolve_theta():
    assert sc.resolve_theta("0.5", 1) == 0.5 and sc.resolve_theta(-1.25, 1) == -1.25
    a, b = sc.resolve_theta("random", 5), sc.resolve_theta(" Random ", 5)
    assert a == b and 0 <= a < 2 * math.pi and a != sc.resolve_theta("random", 6)


def test_signature_table_records_the_configuration():
    cfg = SignatureConfig(T=0.1, m_rho=5, theta=0.5, tau=3)
    table, sig = sc.signature_table(
        2, "printed", cfg, length=40, zdot="finite-difference", seed=9, theta_option="0.5"
    )
    assert len(table.rows) == 40 == sig.k.size
    meta = table.meta
    assert (meta["mode"], meta["codes"], meta["T"], meta["m_rho"], meta["tau"]) == (2, "printed", 0.1, 5, 3)
    assert meta["zdot"] == "finite-difference" and meta["seed"] == 9 and meta["theta_option"] == "0.5"
    assert "spec" not in meta["assumptions"] and "seed 000" not in meta["equations"]
