"""`motionsig mac-roc` (ATC-10 §3): figures' settings, CSV content, the printed values, bad input."""

import json
import math

import numpy as np
import pytest

from tests.cli.helpers import checkpoint_resume, engine_outputs, one_line_error, run, table, task_count


def _f(col):
    return np.array([float(v) if v not in ("", None) else np.nan for v in col])


def test_bounds_figure_3_3_rows_and_sandwich_with_exact(capsys, tmp_path):
    fig = tmp_path / "f33.png"
    rc, out, err = run(
        capsys,
        "mac-roc",
        "bounds",
        "--figure",
        "3.3",
        "--theta",
        "0.05:0.95:0.05",
        "--exact",
        "--plot",
        str(fig),
    )
    assert rc == 0 and fig.stat().st_size > 10_000 and "5 contour(s)" in err
    t = table(out, tmp_path)
    assert t.meta["density"] == "uniform" and t.meta["figure"] == "3.3" and t.meta["N"] == 100000
    assert len(t.rows) == 5 * 19
    assert sorted(set(_f(t.column("ell")))) == [4.0, 6.0, 8.0, 10.0, 12.0]
    up, lo, ex = _f(t.column("log10_pf_up")), _f(t.column("log10_pf_lo")), _f(t.column("log10_pf_exact"))
    ok = ~np.isnan(lo)
    assert np.all(ex <= up + 1e-9) and np.all(ex[ok] >= lo[ok] - 1e-9)
    pd_lo, pm_up = _f(t.column("pd_lo")), _f(t.column("pm_up"))
    assert np.allclose(pd_lo, 1 - pm_up, atol=1e-15)
    # the log10 columns carry the value where it is representable
    pf_up = _f(t.column("pf_up"))
    assert np.allclose(np.log10(pf_up), up, rtol=1e-12)


def test_bounds_two_point_reference_row(capsys, tmp_path):
    rc, out, _ = run(capsys, "mac-roc", "bounds", "--density", "C2", "--ell", "8", "--theta", "0.5", "-q")
    assert rc == 0
    t = table(out, tmp_path)
    (row,) = t.rows
    r = dict(zip(t.columns, row, strict=True))
    assert float(r["rho_star"]) == pytest.approx(18.248904, rel=1e-6)
    assert float(r["pf_up"]) == pytest.approx(5.950548e-3, rel=1e-6)
    assert float(r["pf_lo"]) == pytest.approx(3.654699e-11, rel=1e-6)
    rc, out, _ = run(
        capsys,
        "mac-roc",
        "bounds",
        "--density",
        "C2",
        "--ell",
        "8",
        "--theta",
        "0.5",
        "--lower-variant",
        "gallager",
        "-q",
    )
    r = dict(zip(*[table(out, tmp_path).columns, table(out, tmp_path).rows[0]], strict=True))
    assert float(r["pf_lo"]) == pytest.approx(1.158783e-10, rel=1e-6)


def test_bounds_at_pd_reference_values(capsys, tmp_path):
    rc, out, _ = run(
        capsys, "mac-roc", "bounds", "--density", "uniform", "--ell", "8", "--at-pd", "0.99", "--exact", "-q"
    )
    assert rc == 0
    t = table(out, tmp_path)
    r = dict(zip(t.columns, t.rows[0], strict=True))
    assert float(r["pf_up"]) == pytest.approx(7.5054e-3, rel=1e-4)  # the upper contour at p_d = 0.99
    assert float(r["pf_exact"]) == pytest.approx(4.8e-5, rel=0.05)  # the exact ROC at the same p_d
    assert float(r["pf_gauss"]) == pytest.approx(2.1e-6, rel=0.05)


def test_exact_all_inside_and_json(capsys, tmp_path):
    rc, out, err = run(
        capsys,
        "mac-roc",
        "exact",
        "--density",
        "laplace",
        "--ell",
        "6,10",
        "--theta",
        "0.1:0.9:0.1",
        "-f",
        "json",
    )
    assert rc == 0 and "0 outside the bounds" in err
    doc = json.loads(out)
    assert all(r["inside"] for r in doc["data"]) and len(doc["data"]) == 18


def test_montecarlo_reproducible_and_consistent(capsys, tmp_path):
    args = ("mac-roc", "montecarlo", "--ell", "8", "--trials", "2e5", "--seed", "4", "-q")
    rc1, out1, _ = run(capsys, *args)
    rc2, out2, _ = run(capsys, *args)
    assert rc1 == rc2 == 0 and out1 == out2
    _, out3, _ = run(capsys, *args[:-3], "--seed", "5", "-q")
    assert out3 != out1
    t = table(out1, tmp_path)
    z = _f(t.column("z_pf"))  # empty where no false alarm was seen (θ = 0.8: p_f = 2e-6, 2e5 trials)
    assert np.all(np.abs(z[~np.isnan(z)]) < 4) and all(v == "true" for v in t.column("inside"))
    pc = t.meta["power_check"][0]
    assert abs(pc["z"]) < 4 and pc["P"] == pytest.approx(0.020833125)


def test_montecarlo_importance_and_psk(capsys, tmp_path):
    rc, out, _ = run(
        capsys,
        "mac-roc",
        "montecarlo",
        "--ell",
        "20",
        "--theta",
        "0.8",
        "--importance",
        "--trials",
        "2e5",
        "-q",
    )
    assert rc == 0
    r = dict(zip(*[table(out, tmp_path).columns, table(out, tmp_path).rows[0]], strict=True))
    assert r["method"] == "importance" and abs(float(r["z_pf"])) < 4
    assert float(r["pf"]) == pytest.approx(float(r["pf_exact"]), rel=0.03)
    rc, out, _ = run(
        capsys,
        "mac-roc",
        "montecarlo",
        "--density",
        "psk",
        "--code",
        "gold:45,75:3",
        "--interferers",
        "family",
        "--theta",
        "0.5",
        "--trials",
        "1e5",
        "-q",
    )
    assert rc == 0
    t = table(out, tmp_path)
    assert t.meta["interferers"] == "family" and t.meta["chips"] == 31 and t.column("pf_exact") == [""]


def test_gaussian_exponent_densities_bandwidth_report(capsys, tmp_path):
    rc, out, _ = run(capsys, "mac-roc", "gaussian", "--figure", "3.8", "--ell", "8", "--theta", "0.5", "-q")
    r = dict(zip(*[table(out, tmp_path).columns, table(out, tmp_path).rows[0]], strict=True))
    assert rc == 0 and float(r["pf"]) == pytest.approx(2.659856e-4, rel=1e-6)
    assert float(r["d_prime"]) == pytest.approx(6.92824, rel=1e-6)
    rc, out, _ = run(
        capsys, "mac-roc", "exponent", "--figure", "3.9", "--N", "1e5", "--tau-over-alpha", "1e-5", "-q"
    )
    r = dict(zip(*[table(out, tmp_path).columns, table(out, tmp_path).rows[0]], strict=True))
    assert rc == 0 and float(r["Exp"]) == pytest.approx(3.302437, abs=1e-6)
    rc, out, _ = run(capsys, "mac-roc", "exponent", "--figure", "3.10", "-q")
    t = table(out, tmp_path)
    assert rc == 0 and len(t.rows) == 5 * 81
    rc, out, _ = run(capsys, "mac-roc", "densities", "-q")
    t = table(out, tmp_path)
    assert rc == 0 and all(
        v == pytest.approx(1 / 3, rel=1e-8) for v in t.meta["second_moment_check"].values()
    )
    assert _f(t.column("weight"))[~np.isnan(_f(t.column("weight")))].tolist() == [0.5, 0.5]
    rc, out, _ = run(capsys, "mac-roc", "bandwidth", "-q")
    t = table(out, tmp_path)
    W = dict(zip(t.column("code"), _f(t.column("W_tauc")), strict=True))
    assert W["barker13"] == pytest.approx(0.70028, abs=5e-6) and W["mseq31"] == pytest.approx(
        0.54151, abs=5e-6
    )
    rc, out, _ = run(capsys, "mac-roc", "report", "-q")
    t = table(out, tmp_path)
    rows = {r[0]: dict(zip(t.columns, r, strict=True)) for r in t.rows}
    assert float(rows["reference1_power"]["ours"]) == pytest.approx(50.0, rel=1e-4)  # the printed 50 is 1/p
    assert float(rows["reference1_exp"]["ours"]) == pytest.approx(9.702096, abs=1e-6)
    assert (
        8.5 < float(rows["reference1_exp"]["ours"]) < 10
        and 1.2 < float(rows["reference1_ratio"]["ours"]) < 1.5
    )
    assert rows["reference1_expg"]["status"] == "inconsistent"


def test_unrealisable_density_warns_but_computes(capsys, tmp_path):
    rc, out, err = run(capsys, "mac-roc", "bounds", "--ell", "0.5", "--theta", "0.5", "--density", "uniform")
    assert rc == 0 and "not realisable" in err
    assert table(out, tmp_path).meta["realisable"] is False
    assert math.isfinite(float(table(out, tmp_path).column("E_f")[0]))


def test_bounds_with_monte_carlo_overlay(capsys, tmp_path):
    fig = tmp_path / "b.svg"
    rc, out, _ = run(capsys, "mac-roc", "bounds", "--density", "C2", "--ell", "6", "--theta", "0.3,0.5", "--exact",
                     "--montecarlo", "1e5", "--seed", "3", "--plot", str(fig), "-q")  # fmt: skip
    assert rc == 0 and fig.exists()
    t = table(out, tmp_path)
    assert t.meta["montecarlo_trials"] == 100000 and t.meta["seed"] == 3
    mc, se, ex = _f(t.column("pf_mc")), _f(t.column("pf_mc_se")), _f(t.column("pf_exact"))
    assert np.all(np.abs(mc - ex) < 4 * se)


def test_psk_codes_from_encode(capsys, tmp_path):
    """`motionsig encode gold --all -o F` then `mac-roc --code file:F --interferers family`: the first code
    is the reference and the family the others; b is the (F.5) autocorrelation value of that family."""
    from motionsig_cli.signals.gold import gold_family
    from motionsig_cli.surveillance.time_bandwidth import b_from_autocorrelations

    codes = tmp_path / "gold.csv"
    rc, _, _ = run(
        capsys, "encode", "gold", "--poly1", "45", "--poly2", "75", "--all", "-o", str(codes), "-q"
    )
    assert rc == 0
    rc, out, _ = run(capsys, "mac-roc", "bounds", "--density", "psk", "--code", f"file:{codes}", "--interferers",
                     "family", "--theta", "0.5", "-q")  # fmt: skip
    assert rc == 0
    b = float(table(out, tmp_path).column("b")[0])
    _, bits = gold_family(0o45, 0o75)
    pm = 1 - 2 * bits.astype(int)
    assert b == pytest.approx(b_from_autocorrelations(pm[0], pm[1:]).mean(), rel=1e-12)
    bad = tmp_path / "bad.csv"
    bad.write_text("code,chip,value\na,0,2\n")
    rc, _, err = run(capsys, "mac-roc", "bounds", "--density", "psk", "--code", f"file:{bad}")
    assert rc == 2 and f"{bad}:2" in err


def test_exact_too_many_interferers_is_bad_input(capsys):
    rc, out, err = run(capsys, "mac-roc", "exact", "--N", "1e9", "--ell", "8", "--theta", "0.5")
    assert rc == 2 and "--N" in err and "too long" in err and out == ""
    rc, out, _ = run(
        capsys,
        "mac-roc",
        "montecarlo",
        "--N",
        "1e9",
        "--ell",
        "8",
        "--theta",
        "0.5",
        "--trials",
        "1000",
        "-q",
    )
    assert rc == 0  # the Monte Carlo still runs; the exact columns stay empty


def test_montecarlo_refuses_an_impossible_workload(capsys, tmp_path):
    rc, out, err = run(
        capsys,
        "mac-roc",
        "montecarlo",
        "--N",
        "1e12",
        "--ell",
        "8",
        "--theta",
        "0.5",
        "-o",
        str(tmp_path / "x.csv"),
    )
    assert rc == 2 and "--trials" in err and "amplitude draws" in err and out == ""
    assert not (tmp_path / "x.csv").exists()


def test_exponent_has_no_cancellation():
    from motionsig_cli.surveillance.quasi_optimal import exp_of_gaussian_exponent

    for n in (1e14, 1e20, 1e300):
        assert exp_of_gaussian_exponent(4.0, n, 1e-5) <= 4.0
    assert exp_of_gaussian_exponent(1e-14, 1e5, 1e-5) <= 1e-14


# --- the Monte Carlo engine: --workers, --scheduler, --checkpoint -----------------------------------------

ENGINE_CASES = {
    "plain": ("montecarlo", "--ell", "6,8", "--theta", "0.3,0.5", "--trials", "2e5", "--seed", "4"),
    "importance": ("montecarlo", "--importance", "--ell", "8", "--theta", "0.5,0.7", "--trials", "1.5e5"),
    "psk": ("montecarlo", "--density", "psk", "--code", "mseq31", "--theta", "0.5", "--trials", "7e4"),
    "bounds": ("bounds", "--density", "C2", "--ell", "6,8", "--theta", "0.3,0.5", "--montecarlo", "1.5e5"),
}


@pytest.mark.parametrize("case", list(ENGINE_CASES))
def test_monte_carlo_byte_identical_for_1_2_workers_and_dask(
    capsys, tmp_path, dask_address, many_tasks, case
):
    args = ("mac-roc", *ENGINE_CASES[case])
    outs = engine_outputs(capsys, tmp_path, dask_address, *args)
    assert outs["w1"] == outs["w2"] == outs["dask"]
    text = outs["w1"].decode()
    assert "workers" not in text and "scheduler" not in text and "checkpoint" not in text
    assert task_count(tmp_path, capsys, *args) >= 2


@pytest.mark.parametrize("case", ["plain", "importance"])
def test_monte_carlo_checkpoint_resumes_to_the_uninterrupted_result(capsys, tmp_path, many_tasks, case):
    args = ("mac-roc", *ENGINE_CASES[case])
    # an interrupted run: every other task is missing
    ckpt, n_tasks = checkpoint_resume(capsys, tmp_path, args, slice(1, None, 2))
    assert n_tasks >= 2
    err = one_line_error(
        capsys, *args, "--seed", "5", "--checkpoint", str(ckpt), "-o", str(tmp_path / "x.csv")
    )
    assert "--checkpoint" in err and "seed" in err and not (tmp_path / "x.csv").exists()
    # the same directory for another command is refused too
    err = one_line_error(capsys, "mac-roc", *ENGINE_CASES["bounds"], "--checkpoint", str(ckpt), "-q")
    assert "another command" in err


def test_option_defaults_are_the_core_constants():
    from motionsig_cli.atc10 import mac_roc as exp
    from motionsig_cli.cli import mac_roc as cli

    assert cli.REPORT_TAU_OVER_ALPHA == exp.REPORT_TAU_OVER_ALPHA and cli.FIG32_B == exp.FIG32_B


def test_the_command_module_imports_no_core_at_start():
    """The mac-roc command module imports the core (scipy, the experiment) only when a command runs."""
    import subprocess
    import sys

    code = "import sys, motionsig_cli.cli.mac_roc\nprint(any(m.startswith('scipy') or m.endswith('atc10.mac_roc') for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
