"""`motionsig simulate --example 2d | motionsig detect` (issue 4): the pipe, the Fig 7 Monte Carlo, and the
issue's bad-input list (range 0, degrees in a radians column, non-finite values, mismatched layout)."""

import math

import numpy as np
import pytest

from motionsig_cli.tables import read_table
from tests.cli.helpers import run, table


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    """A 12 s radar record (mode 2, tau 5 chips, best ANR pair)."""
    from motionsig_cli.cli.app import main

    p = tmp_path_factory.mktemp("radar") / "rec.csv"
    assert (
        main(
            [
                "simulate",
                "--example",
                "2d",
                "--mode",
                "2",
                "--tau-chips",
                "5",
                "--duration",
                "12",
                "-q",
                "-o",
                str(p),
            ]
        )
        == 0
    )
    return p


def _edit(record, tmp_path, fn, name="bad.csv"):
    lines = record.read_text().splitlines(keepends=True)
    out = tmp_path / name
    out.write_text("".join(fn(lines)))
    return out


def test_simulate_2d_metadata(record):
    t = read_table(record)
    assert t.meta["example"] == "2d" and t.meta["bearing_unit"] == "rad"
    assert t.meta["anr_pair"] == 4 and t.meta["seed_anr_pair_labels"] == [101.3, 129.2]
    assert t.meta["anr_angle_db_paper_ln"] == pytest.approx(101.27, abs=0.01)
    assert t.meta["start"] == [70.0, -20.0]
    rg, br = t.numeric("range"), t.numeric("bearing")
    x, y = t.numeric("x"), t.numeric("y")
    assert np.allclose(rg, np.hypot(x, y), atol=0.01)  # σ_κ = 5.5e-4 m
    assert np.all(np.abs(br) <= math.pi)
    assert x[0] == 70.0 and y[0] == -20.0


def test_detect_radar_record_finds_the_truth(record, capsys, tmp_path):
    rc, out, err = run(capsys, "detect", str(record), "--horizons", "6,12")
    assert rc == 0, err
    t = table(out, tmp_path)
    assert t.meta["filter"] == "ukf" and t.meta["n_filters"] == 187
    assert t.meta["covariance_repairs_state"] == 0
    assert [float(r[0]) for r in t.rows] == [6.0, 12.0]
    assert t.rows[-1][t.columns.index("correct")] == "true"  # ~100 % at 10 s in the Fig 7 Monte Carlo


def test_degrees_column_with_its_unit_gives_the_same_answer(record, capsys, tmp_path):
    t = read_table(record)
    bi = t.columns.index("bearing")

    def to_deg(lines):
        out = []
        for ln in lines:
            if ln.startswith("# bearing_unit"):
                out.append('# bearing_unit: "deg"\n')
            elif ln[:1].isdigit():
                f = ln.rstrip("\n").split(",")
                f[bi] = repr(math.degrees(float(f[bi])))
                out.append(",".join(f) + "\n")
            else:
                out.append(ln)
        return out

    deg = _edit(record, tmp_path, to_deg, "deg.csv")
    rc1, out1, _ = run(capsys, "detect", str(record), "--horizons", "12", "-q")
    rc2, out2, _ = run(capsys, "detect", str(deg), "--horizons", "12", "-q")
    assert rc1 == rc2 == 0
    s1 = float(table(out1, tmp_path, "a.csv").rows[0][6])
    s2 = float(table(out2, tmp_path, "b.csv").rows[0][6])
    assert s2 == pytest.approx(s1, rel=1e-9)


def _replace_field(record, tmp_path, column, row, value):
    cols = read_table(record).columns
    i = cols.index(column)
    seen = {"n": -1}

    def fn(lines):
        out = []
        for ln in lines:
            if ln[:1].isdigit() or ln[:1] == "-":
                seen["n"] += 1
                if seen["n"] == row:
                    f = ln.rstrip("\n").split(",")
                    f[i] = value
                    ln = ",".join(f) + "\n"
            out.append(ln)
        return out

    return _edit(record, tmp_path, fn)


@pytest.mark.parametrize(
    ("column", "value", "message"),
    [
        ("range", "0", "range 0 <= 0"),
        ("bearing", "57.3", "degrees in a column labelled radians"),
        ("range", "inf", "not finite"),
    ],
)
def test_bad_records_are_refused_with_file_and_line(record, capsys, tmp_path, column, value, message):
    bad = _replace_field(record, tmp_path, column, 7, value)
    rc, out, err = run(capsys, "detect", str(bad))
    assert rc == 2 and out == ""
    assert message in err and f"{bad}:" in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_layout_mismatches_are_refused(record, capsys, tmp_path):
    no_bearing = _edit(record, tmp_path, lambda ls: [ln.replace("range,bearing,", "range,brg,") for ln in ls])
    rc, _, err = run(capsys, "detect", str(no_bearing))
    assert rc == 2 and "column 'bearing'" in err
    unit = _edit(record, tmp_path, lambda ls: [ln.replace('"rad"', '"grad"') for ln in ls], "u.csv")
    rc, _, err = run(capsys, "detect", str(unit))
    assert rc == 2 and "bearing_unit" in err


@pytest.mark.parametrize(
    ("args", "hint"),
    [
        (("--filter", "kf"), "--filter"),
        (("--example", "1d"), "--example"),
        (("--Q0", "1,2,3,4"), "--Q0"),
        (("--Q1", "1,2"), "--Q1"),
        (("--alpha", "0"), "--alpha"),
        # found by review: 1-D options on a radar record
        (("--Qa", "5"), "--Qa"),
        (("--center", "h0-noise"), "--center"),
        (("--horizons", "0.01"), "--horizons"),
        (("--alpha", "1e-8"), "--alpha"),
    ],
)
def test_bad_options_on_a_radar_record_are_refused(record, capsys, args, hint):
    rc, out, err = run(capsys, "detect", str(record), *args)
    assert rc == 2 and out == "" and hint in err, (args, err)


def test_montecarlo_2d_table_and_determinism(capsys, tmp_path):
    args = (
        "detect",
        "--montecarlo",
        "--example",
        "2d",
        "--trials",
        "3",
        "--anr-pairs",
        "2,4",
        "--horizons",
        "4",
        "-q",
    )
    rc, out, err = run(capsys, *args, "--seed", "5")
    assert rc == 0, err
    t = table(out, tmp_path)
    assert [int(r[t.columns.index("anr_pair")]) for r in t.rows] == [2, 4]
    assert [float(r[t.columns.index("seed_angle_label")]) for r in t.rows] == [32.2, 101.3]
    assert all(int(r[t.columns.index("trials")]) == 3 for r in t.rows)
    _, out2, _ = run(capsys, *args, "--seed", "5")
    assert out2 == out
    rc, out, err = run(capsys, "detect", "--montecarlo", "--example", "2d", "--anr-pairs", "0")
    assert rc == 2 and "--anr-pairs" in err
    rc, out, err = run(capsys, "detect", "--montecarlo", "--example", "2d", "--filter", "kf")
    assert rc == 2 and "--filter" in err


def test_review_findings_are_refused(record, capsys, tmp_path):
    """Found by review: a path through the radar, runs too big, bad metadata types (1-D options on radar runs:
    test_bad_options_on_a_radar_record_are_refused)."""
    rc, out, err = run(capsys, "simulate", "--example", "2d", "--start", "-5,-5", "--duration", "60")
    assert rc == 2 and out == "" and "--start" in err  # passes 5 mm from the radar
    rc, _, err = run(capsys, "simulate", "--example", "2d", "--R-range", "1e4", "--duration", "10")
    assert rc == 2 and "--R-range" in err
    rc, _, err = run(capsys, "simulate", "--start", "1,2", "--duration", "1")
    assert rc == 2 and "--example 2d only" in err
    rc, _, err = run(
        capsys, "detect", "--montecarlo", "--example", "2d", "--trials", "1", "--horizons", "500000"
    )
    assert rc == 2 and "GB" in err
    for key, bad in (("start", '"12"'), ("f_c", '"abc"'), ("m_rho", "1.5")):
        p = _edit(
            record,
            tmp_path,
            lambda ls, k=key, b=bad: [f"# {k}: {b}\n" if ln.startswith(f"# {k}:") else ln for ln in ls],
            f"{key}.csv",
        )
        rc, _, err = run(capsys, "detect", str(p))
        assert rc == 2 and "bad metadata" in err and key in err, (key, err)


def test_anr_pair_keeps_its_anr_for_any_amplitude(capsys, tmp_path):
    _, out, _ = run(
        capsys, "simulate", "--example", "2d", "--a-sig", "1", "--anr-pair", "2", "--duration", "1", "-q"
    )
    t = table(out, tmp_path)
    assert t.meta["anr_angle_db_paper_ln"] == pytest.approx(32.19, abs=0.01)
    assert t.meta["anr_range_db_paper_ln"] == pytest.approx(60.2, abs=1e-9)
