"""``track-sat solve`` on a nearly planar ground network (6 stations within 50 km, the transmitter 3 km up, a
1 ms clock offset, 10 ns timing noise, 20 epochs): every epoch converges, to the weighted least-squares
minimum (≤ 0.5 m from scipy's Levenberg-Marquardt started at the truth); the same record as time differences
against a reference station (TDOA) gives the same fixes."""

from __future__ import annotations

from decimal import Decimal

import numpy as np
import pytest
from scipy.optimize import least_squares

from motionsig_cli.geodesy import ecef_to_geodetic, enu_to_ecef
from tests.cli.helpers import one_line_error, run, table

C = 299_792_458.0
E, K, SIGMA_S = 20, 6, 10e-9


@pytest.fixture(scope="module")
def network(tmp_path_factory):
    d = tmp_path_factory.mktemp("network")
    rng = np.random.default_rng(2036)
    lat0, lon0 = 50.03, 8.57
    r = 25e3 * np.sqrt(rng.uniform(0.1, 1.0, K))
    a = np.sort(rng.uniform(0, 2 * np.pi, K))
    S = enu_to_ecef(np.c_[r * np.cos(a), r * np.sin(a), rng.uniform(80, 300, K)], lat0, lon0, 0.0)
    la, lo, al = ecef_to_geodetic(S)
    names = [f"ST{k}" for k in range(K)]
    (d / "stations.csv").write_text(
        "station,latitude,longitude,altitude\n"
        + "".join(
            f"{n},{float(x)!r},{float(y)!r},{float(z)!r}\n"
            for n, x, y, z in zip(names, la, lo, al, strict=True)
        )
    )
    P = enu_to_ecef(np.c_[rng.uniform(-30e3, 30e3, (E, 2)), np.full(E, 3000.0)], lat0, lon0, 0.0)
    toa = 1e-3 + np.linalg.norm(P[:, None] - S, axis=-1) / C + SIGMA_S * rng.standard_normal((E, K))
    lines = ["epoch,time,station,toa"]
    tdoa = ["epoch,station,tdoa"]
    for e in range(E):
        t = 5000 + e
        for k in range(K):
            lines.append(f"{e},{t},{names[k]},{Decimal(t) + Decimal(repr(float(toa[e, k])))}")
            tdoa.append(f"{e},{names[k]},{Decimal(repr(float(toa[e, k]))) - Decimal(repr(float(toa[e, 0])))}")
    (d / "toa.csv").write_text("\n".join(lines) + "\n")
    (d / "tdoa.csv").write_text("\n".join(tdoa) + "\n")
    return d, S, P


def _minimum(S, rho, x0):
    """The independent minimiser: scipy's Levenberg-Marquardt (MINPACK) started at the truth, tight
    tolerances, about the stations' centroid."""
    o = S.mean(axis=0)
    fit = least_squares(lambda x: rho - np.linalg.norm(x[:3] - (S - o), axis=1) - x[3], np.r_[x0[:3] - o, x0[3]],
                        method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=10_000)  # fmt: skip
    return np.r_[fit.x[:3] + o, fit.x[3]]


def _fixes(capsys, tmp_path, *args):
    rc, out, err = run(capsys, "track-sat", "solve", *args)
    assert rc == 0, err
    t = table(out, tmp_path)
    rows = [dict(zip(t.columns, r, strict=True)) for r in t.rows]
    return t, rows, np.array([[float(r[c]) for c in ("x_m", "y_m", "z_m")] for r in rows])


def test_every_epoch_converges_to_the_wls_minimum(capsys, tmp_path, network):
    d, S, P = network
    t, rows, pos = _fixes(
        capsys, tmp_path, str(d / "toa.csv"), "--receivers", str(d / "stations.csv"), "--sigma", "10ns"
    )
    assert all(r["converged"] in (True, "true") and r["status"] == "fix" for r in rows)
    assert all(int(r["iterations"]) <= 12 for r in rows)  # measured 3 to 11 (8 Gauss-Newton, then Newton)
    for e in range(E):  # the same TOAs, from the truth: the independent minimum
        text = open(d / "toa.csv").read().splitlines()[1 + e * K : 1 + (e + 1) * K]
        rho = np.array([float(Decimal(line.split(",")[3]) - Decimal(5000 + e)) for line in text]) * C
        ref = _minimum(S, rho, np.r_[P[e], C * 1e-3])
        assert np.linalg.norm(pos[e] - ref[:3]) < 0.5, (
            e
        )  # measured < 3 mm (the epochs outside the network are flat in height)
    assert t.meta["fixes"]["with_a_fix"] == E and t.meta["fixes"]["not_converged"] == 0


def test_time_differences_give_the_same_fixes(capsys, tmp_path, network):
    d, _, _ = network
    _, _, a = _fixes(
        capsys, tmp_path, str(d / "toa.csv"), "--receivers", str(d / "stations.csv"), "--sigma", "10ns"
    )
    t, _, b = _fixes(
        capsys, tmp_path, str(d / "tdoa.csv"), "--receivers", str(d / "stations.csv"), "--sigma", "10ns"
    )
    assert t.meta["measurement"] == "tdoa"
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-3)


def test_a_tdoa_epoch_without_its_reference_row_is_refused(capsys, tmp_path, network):
    d, _, _ = network
    lines = open(d / "tdoa.csv").read().splitlines()
    m = tmp_path / "t.csv"
    m.write_text("\n".join(line for i, line in enumerate(lines) if i != 1) + "\n")  # epoch 0's reference row
    err = one_line_error(capsys, "track-sat", "solve", str(m), "--receivers", str(d / "stations.csv"))
    assert "t.csv:2: column 'tdoa': this epoch has no reference row" in err, err


def test_toas_in_milliseconds_read_as_seconds_are_refused(capsys, tmp_path, network):
    """The differences of the TOAs exceed the light time between the stations (triangle inequality)."""
    d, _, _ = network
    lines = open(d / "toa.csv").read().splitlines()[1:]
    m = tmp_path / "ms.csv"
    m.write_text("epoch,station,toa\n" + "".join(
        f"{e},{st},{(Decimal(toa) - Decimal(t)) * 1000}\n" for e, t, st, toa in (x.split(",") for x in lines)))  # fmt: skip
    args = ("track-sat", "solve", str(m), "--receivers", str(d / "stations.csv"), "--toa-origin", "epoch")
    err = one_line_error(capsys, *args)
    assert (
        "ms.csv:2: column 'toa': the toa values do not fit the receivers' positions: at 20 of 20 epoch(s)"
        in err
    )
    assert "a unit mix-up? (label the unit, e.g. 'toa [ms]'" in err
    rc, _, err = run(capsys, *args, "--units", "toa=ms", "-q")
    assert rc == 0, err


def test_one_faulty_station_is_excluded_and_named(capsys, tmp_path, network):
    """A station 1 µs late at one epoch (300 m): excluded there, the other epochs untouched."""
    d, _, _ = network
    lines = open(d / "toa.csv").read().splitlines()
    lines[1 + 5 * K + 2] = ",".join(
        [
            *lines[1 + 5 * K + 2].split(",")[:3],
            str(Decimal(lines[1 + 5 * K + 2].split(",")[3]) + Decimal("1e-6")),
        ]
    )
    m = tmp_path / "f.csv"
    m.write_text("\n".join(lines) + "\n")
    t, rows, _ = _fixes(capsys, tmp_path, str(m), "--receivers", str(d / "stations.csv"), "--sigma", "10ns")
    assert [r["excluded"] or "" for r in rows] == [""] * 5 + ["ST2"] + [""] * (E - 6)
    assert t.meta["fault_exclusion"]["excluded_by_receiver"] == {"ST2": 1}
