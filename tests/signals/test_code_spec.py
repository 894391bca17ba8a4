"""The code sets of ``--codes``: each form against an independent reference (Table I's stored codes, the
Gold family's three-valued correlations, the IS-GPS-200 first-chip octals, a table written by numpy), the
normalised text reading back to the same chips, and the refusals (ConfigError naming codes, InputError
naming a bad file)."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.errors import InputError
from motionsig_cli.signals import gps
from motionsig_cli.signals.code_spec import MAX_CODE_CHIPS, parse_codes
from motionsig_cli.signals.correlation import periodic_correlation, to_bipolar
from motionsig_cli.signals.gold import gold_code, gold_values
from motionsig_cli.signals.lfsr import m_sequence
from motionsig_cli.signals.modes import table1_codes


@pytest.mark.parametrize("variant", ["corrected", "printed"])
def test_table1(variant):
    c = parse_codes(variant)
    assert c.spec == variant and c.names == ("mode1", "mode2", "mode3")
    np.testing.assert_array_equal(c.chips, to_bipolar(table1_codes(variant)))
    assert c.chips.dtype == float and c.n_modes == 3 and c.n_chips == 31


def test_index_and_offset_give_table1s_corrected_codes():
    """Table I's corrected codes are members (9, 8), (13, 13), (25, 12) of the 45/75 family (the stored
    data): index@offset picks exactly them."""
    c = parse_codes("gold:45,75:9@8,13@13,25@12")
    np.testing.assert_array_equal(c.chips, parse_codes("corrected").chips)
    assert c.names == ("gold_k9_a8", "gold_k13_a13", "gold_k25_a12")


def test_the_whole_family_is_three_valued_in_encode_order():
    c = parse_codes("gold:45,75")
    assert c.n_modes == 33 and c.n_chips == 31 and c.names[:3] == ("gold_k-2", "gold_k-1", "gold_k0")
    r = periodic_correlation(c.chips.astype(np.int64))  # (M, M, N): every pair, every lag
    off_peak = (
        r[~np.eye(33, dtype=bool)].ravel().tolist() + r[np.arange(33), np.arange(33), 1:].ravel().tolist()
    )
    assert set(off_peak) <= set(gold_values(5))  # {-9, -1, 7}: a Gold family
    for i, k in enumerate((-2, -1, 0, 1, 2)):
        np.testing.assert_array_equal(c.chips[i], to_bipolar(gold_code(0o45, 0o75, k)))


@pytest.mark.parametrize(
    ("text", "indices"),
    [
        ("gold:45,75:3", [-2, -1, 0]),  # the first 3 of encode gold --all
        ("gold:45,75:0,3,7", [0, 3, 7]),
        ("gold:45,75:0-3,u", [0, 1, 2, 3, -2]),
        ("gold:45,75:v,-2", [-1, -2]),
        ("gold:x^5+x^2+1,x^5+x^4+x^3+x^2+1:2", [-2, -1]),  # exponents, as encode gold takes them
    ],
)
def test_gold_members(text, indices):
    c = parse_codes(text)
    want = np.stack([to_bipolar(gold_code(0o45, 0o75, k)) for k in indices])
    np.testing.assert_array_equal(c.chips, want)
    again = parse_codes(c.spec)  # the normalised text (octal) reads back to the same chips
    assert again.spec == c.spec and c.spec.startswith("gold:45,75")
    np.testing.assert_array_equal(again.chips, c.chips)


def test_mseq_and_shift():
    c = parse_codes("mseq:45,67@3")
    assert c.spec == "mseq:45,67@3" and c.names == ("mseq_45", "mseq_67_a3")
    np.testing.assert_array_equal(c.chips[0], to_bipolar(m_sequence(0o45)))
    np.testing.assert_array_equal(c.chips[1], np.roll(to_bipolar(m_sequence(0o67)), -3))


def test_gps_prns_match_the_interface_specification():
    """IS-GPS-200 Table 3-Ia: the first 10 chips of PRN 1, 2, 3 and 7 in octal are 1440, 1620, 1710, 1131."""
    c = parse_codes("gps:1-3,7")
    assert c.spec == "gps:1,2,3,7" and c.names == ("PRN1", "PRN2", "PRN3", "PRN7") and c.n_chips == 1023
    bits = (c.chips > 0).astype(np.uint8)
    assert [gps.first_chips_octal(b) for b in bits] == ["1440", "1620", "1710", "1131"]


def test_a_code_table_written_by_numpy(tmp_path):
    rng = np.random.default_rng(11)
    bits = rng.integers(0, 2, size=(5, 63))
    lines = ["code,chip,value"] + [f"m{i},{j},{b}" for i, row in enumerate(bits) for j, b in enumerate(row)]
    path = tmp_path / "codes.csv"
    path.write_text("\n".join(lines) + "\n")
    for text in (str(path), f"file:{path}"):
        c = parse_codes(text)
        np.testing.assert_array_equal(c.chips, 2.0 * bits - 1)
        assert c.names == tuple(f"m{i}" for i in range(5)) and c.spec == str(path)
    # a table as encode writes it (bipolar chips), with the chips of one code out of order
    order = rng.permutation(63)
    lines = ["code,chip,value"] + [f"a,{j},{2 * bits[0, j] - 1}" for j in order]
    lines += [f"b,{j},{2 * bits[1, j] - 1}" for j in range(63)]
    path.write_text("\n".join(lines) + "\n")
    np.testing.assert_array_equal(parse_codes(str(path)).chips, 2.0 * bits[:2] - 1)


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("gold", "neither a code set nor an existing file"),
        ("fancy:1,2", "is not a code set"),
        ("gold:45", "names 1 polynomial"),
        ("gold:45,51", "not a preferred partner"),
        ("gold:45,75:0", "asks for 0 members"),
        ("gold:45,75:34", "asks for 34 members"),
        ("gold:45,75:30,40", "names member 40"),
        ("gold:45,75:0,0", "lists member 0@0 twice"),
        ("gold:45,75:3@1,3@32", "lists member 3@32 twice"),  # offsets modulo the period
        ("gold:45,75:x", "bad member 'x'"),
        ("gold:45,75:1@y", "bad offset"),
        ("gold:45,75:1,,2", "empty member"),
        ("mseq:44", "not primitive"),
        ("mseq:45,103", "mixes degrees"),
        ("mseq:45,45", "twice"),
        ("mseq:3", "1 chip"),
        ("gps:0", "PRN 0"),
        ("gps:30-33", "PRN 30-33"),
        ("gps:1,1", "lists PRN 1 twice"),
        ("gps:a", "bad PRN 'a'"),
        ("-", "neither a code set"),
        (3, "is not text"),
    ],
)
def test_bad_text_is_a_config_error_naming_codes(text, reason):
    with pytest.raises(ConfigError) as exc:
        parse_codes(text)
    assert exc.value.field == "codes" and reason in exc.value.reason, exc.value


def test_size_limit():
    """Five 2^20 - 1 chip m-sequences (5.2e6 chips) are refused before any is built; one is fine."""
    poly = "4000011"  # x^20 + x^3 + 1, primitive
    text = "mseq:" + ",".join([poly] + [f"{poly}@{a}" for a in range(1, 5)])
    assert 5 * (2**20 - 1) > MAX_CODE_CHIPS
    with pytest.raises(ConfigError, match=f"more than {MAX_CODE_CHIPS} chips") as exc:
        parse_codes(text)
    assert exc.value.field == "codes"
    assert parse_codes(f"mseq:{poly}").chips.shape == (1, 2**20 - 1)


def test_a_bad_code_table_is_an_input_error_naming_the_file(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("code,chip,value\na,0,1\na,1,5\n")
    with pytest.raises(InputError, match=str(path)):
        parse_codes(str(path))
    path.write_text("name,chip,value\na,0,1\n")
    with pytest.raises(InputError, match="code"):
        parse_codes(str(path))


def test_a_text_that_is_data_never_names_a_file(tmp_path, monkeypatch):
    """files=False (a record's metadata, issue 39): a path, bare or as file:, is refused without being
    opened or even looked at; the built-in sets read as before, even beside a file of the same name."""
    import motionsig_cli.signals.code_sets as code_sets

    path = tmp_path / "codes.csv"
    path.write_text("code,chip,value\na,0,1\na,1,0\n")
    opened = []
    monkeypatch.setattr(code_sets, "load_codes", lambda p: opened.append(p))
    for text in (str(path), f"file:{path}", "file:/dev/zero", "/etc/passwd", "-"):
        with pytest.raises(ConfigError, match="never names a file") as exc:
            parse_codes(text, files=False)
        assert exc.value.field == "codes"
    assert opened == []
    monkeypatch.chdir(tmp_path)
    (tmp_path / "gold:45,75:3").write_text("code,chip,value\n")  # a file named like a set: still the set
    assert parse_codes("gold:45,75:3", files=False).n_modes == 3
    assert parse_codes("corrected", files=False).spec == "corrected"
