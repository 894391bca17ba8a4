"""The scenario generator of the track-existence study (:func:`motionsig_cli.existence.slrt.generate`),
vectorised across runs, scans and sensors:

1. batch independence: a run's data (truth, initial track, clutter counts, every measurement) are the
   same to the bit alone, in a small batch or in a larger one, in any order, for the default and the agile
   scenario (each run draws from its own ``trial_rng(seed, r)``);
2. against the loop it replaced, kept here as the oracle :func:`_generate_reference`: the draw order
   changed, so the two are compared in distribution (detections per scan and sensor, clutter counts,
   clutter positions, target-originated measurement errors, the truth and the initial track), each
   statistic within 4 standard errors, over a few hundred runs with fixed seeds;
3. the edge cases: no clutter, p_D = 1, no target, missed detections, a target outside a sensor's field
   of view (range–bearing and Cartesian), no runs at all.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pytest

from motionsig_cli.detection.track_existence import ScanData
from motionsig_cli.existence import slrt
from motionsig_cli.models.radar import cv_model, wrap_angle
from motionsig_cli.rng import trial_rng

AGILE = slrt.SlrtScenario(target_motion="agile")
N_STAT = 300  # runs per generator in the statistical comparisons
Z4 = 4.0  # the band, in standard errors: a false failure once in ~16 000 for one normal statistic


# ------------------------------------------------------------------------------------------- the oracle
def _step_reference(
    sc: slrt.SlrtScenario, x: np.ndarray, k: int, kind: np.ndarray, value: np.ndarray
) -> np.ndarray:
    """The deterministic transition of one state (4,) as the loop generator computed it."""
    T = sc.T
    if kind[k] == 1:
        w = value[k]
        s, c = math.sin(w * T), math.cos(w * T)
        a, b = (s / w, (1.0 - c) / w) if w != 0.0 else (T, 0.0)
        return np.array([x[0] + a * x[1] - b * x[3], c * x[1] - s * x[3],
                         x[2] + b * x[1] + a * x[3], s * x[1] + c * x[3]])  # fmt: skip
    if kind[k] == 2:
        acc = value[k]
        speed = math.hypot(x[1], x[3])
        u = np.array([x[1], x[3]]) / speed
        dpos, dvel = (speed * T + 0.5 * acc * T * T) * u, acc * T * u
        return np.array([x[0] + dpos[0], x[1] + dvel[0], x[2] + dpos[1], x[3] + dvel[1]])
    return cv_model(T, 0.0)[0] @ x


def _generate_reference(sc: slrt.SlrtScenario, runs: Sequence[int], seed: int) -> slrt.Generated:
    """The generator before vectorisation (a Python loop over runs, scans and sensors, one draw at a time
    from the run's stream), verbatim but for :func:`_step_reference`: the oracle of the statistics."""
    F, Q = cv_model(sc.T, sc.q)
    kind, value = sc.schedule()
    agile = bool(kind.any())
    meas = sc.measurement()
    sensors = sc.sensors
    LQ = np.linalg.cholesky(Q + 1e-12 * np.eye(4))
    LR = np.linalg.cholesky(meas.R)
    p, v = sc.p0_sd
    L0 = np.diag([p, v, p, v])
    S, K = sc.n_sensors, sc.scans
    truth = np.empty((len(runs), K, 4))
    m0 = np.empty((len(runs), 4))
    per_run: list[list[list[np.ndarray]]] = []
    counts = np.zeros((len(runs), K, S), dtype=int)
    for i, r in enumerate(runs):
        g = trial_rng(seed, r)
        x = np.asarray(sc.x0, dtype=float)
        m0[i] = x + L0 @ g.standard_normal(4)
        zs: list[list[np.ndarray]] = []
        for k in range(K):
            if agile:
                x = _step_reference(sc, x, k, kind, value) + LQ @ g.standard_normal(4)
            else:
                x = F @ x + LQ @ g.standard_normal(4)
            truth[i, k] = x
            row = []
            for s in range(S):
                n_fa = g.poisson(sc.clutter_rate)
                counts[i, k, s] = n_fa
                z = meas.clutter(g, n_fa, sensors[s])
                detect = g.random() < sc.pd_true
                noise = LR @ g.standard_normal(2)
                if sc.target and detect:
                    zt = meas.h(x, sensors[s]) + noise
                    if meas.angular is not None:
                        zt[1] = wrap_angle(zt[1])
                    if meas.in_fov(zt, sensors[s]):
                        z = np.vstack([zt[None, :], z])
                row.append(z)
            zs.append(row)
        per_run.append(zs)
    scans = []
    for k in range(K):
        Zs, Vs = [], []
        for s in range(S):
            M = max(len(per_run[i][k][s]) for i in range(len(runs)))
            Z = np.zeros((len(runs), M, 2))
            V = np.zeros((len(runs), M), dtype=bool)
            for i in range(len(runs)):
                z = per_run[i][k][s]
                Z[i, : len(z)] = z
                V[i, : len(z)] = True
            Zs.append(Z)
            Vs.append(V)
        scans.append(ScanData(tuple(Zs), tuple(Vs)))
    return slrt.Generated(truth, m0, scans, counts)


# ------------------------------------------------------------------------------------------------ helpers
def _lists(gen: slrt.Generated, i: int) -> list[list[np.ndarray]]:
    """Run i's measurements per scan and sensor (the valid rows, padding dropped)."""
    return [[z[i][v[i]] for z, v in zip(scan.Z, scan.valid, strict=True)] for scan in gen.scans]


def _assert_same_run(a: slrt.Generated, i: int, b: slrt.Generated, j: int) -> None:
    """Run i of a equals run j of b to the bit: truth, initial track, clutter counts, measurements (in order)."""
    np.testing.assert_array_equal(a.truth[i], b.truth[j])
    np.testing.assert_array_equal(a.m0[i], b.m0[j])
    np.testing.assert_array_equal(a.clutter_counts[i], b.clutter_counts[j])
    for row_a, row_b in zip(_lists(a, i), _lists(b, j), strict=True):
        for za, zb in zip(row_a, row_b, strict=True):
            assert za.shape == zb.shape
            np.testing.assert_array_equal(za, zb)


def _target_count(gen: slrt.Generated) -> np.ndarray:
    """(R, K, S) target-originated measurements (0 or 1): the valid ones less the false alarms."""
    valid = np.stack([np.stack([v.sum(axis=1) for v in scan.valid], axis=-1) for scan in gen.scans], axis=1)
    return valid - gen.clutter_counts


def _target_errors(sc: slrt.SlrtScenario, gen: slrt.Generated) -> np.ndarray:
    """(n, 2) errors z − h(x) of every target-originated measurement (bearing wrapped)."""
    meas, sensors = sc.measurement(), sc.sensors
    n_t = _target_count(gen)
    out = []
    for k, scan in enumerate(gen.scans):
        for s, z in enumerate(scan.Z):
            hit = n_t[:, k, s] == 1
            e = z[hit, 0] - meas.h(gen.truth[hit, k], sensors[s])
            if meas.angular is not None:
                e[:, 1] = wrap_angle(e[:, 1])
            out.append(e)
    return np.concatenate(out)


def _clutter_points(gen: slrt.Generated, sensor: int) -> np.ndarray:
    """(n, 2) false alarms of one sensor over every run and scan (after the target's measurement, if any)."""
    n_t = _target_count(gen)
    out = []
    for k, scan in enumerate(gen.scans):
        z, v = scan.Z[sensor], scan.valid[sensor]
        slot = np.arange(z.shape[1])
        clutter = v & (slot >= n_t[:, k, sensor, None])
        out.append(z[clutter])
    return np.concatenate(out)


def _within(a: float, b: float, se: float, what: str) -> None:
    assert abs(a - b) <= Z4 * se, f"{what}: {a} vs {b}, {abs(a - b) / se:.2f} standard errors"


# ----------------------------------------------------------------------------------- batch independence
@pytest.mark.parametrize("sc", [slrt.SlrtScenario(), AGILE], ids=["default", "agile"])
def test_a_run_is_the_same_alone_and_in_any_batch(sc: slrt.SlrtScenario) -> None:
    pair = slrt.generate(sc, [3, 7], 5)
    batch = slrt.generate(sc, range(10), 5)
    reverse = slrt.generate(sc, [7, 3], 5)
    for i, r in enumerate((3, 7)):
        alone = slrt.generate(sc, [r], 5)
        _assert_same_run(pair, i, alone, 0)
        _assert_same_run(pair, i, batch, r)
        _assert_same_run(pair, i, reverse, 1 - i)
    # the padding follows the batch: each scan and sensor padded to the batch's most measurements
    for scan in batch.scans:
        for z, v in zip(scan.Z, scan.valid, strict=True):
            assert z.shape[:2] == v.shape and z.shape[1] == v.sum(axis=1).max()
            assert not z[~v].any()  # the padding is zeros


def test_other_seeds_and_runs_draw_other_numbers() -> None:
    sc = slrt.SlrtScenario(scans=5)
    a, b, c = slrt.generate(sc, [0, 1], 5), slrt.generate(sc, [0], 6), slrt.generate(sc, [2], 5)
    assert not np.any(a.truth[0] == a.truth[1])
    assert not np.any(a.truth[0] == b.truth[0]) and not np.any(a.truth[0] == c.truth[0])


# -------------------------------------------------------------------- against the loop it replaced
@pytest.fixture(scope="module", params=["default", "agile", "cartesian"])
def pair(request: pytest.FixtureRequest) -> tuple[slrt.SlrtScenario, slrt.Generated, slrt.Generated]:
    """(scenario, vectorised, reference) over N_STAT runs each, from different seeds (independent samples)."""
    sc = {
        "default": slrt.SlrtScenario(scans=12, pd_true=0.7, pd_filter=0.7),
        "agile": slrt.SlrtScenario(target_motion="agile", pd_true=0.7, pd_filter=0.7),
        "cartesian": slrt.SlrtScenario(scans=12, meas_model="cartesian", clutter_rate=3.0),
    }[request.param]
    return sc, slrt.generate(sc, range(N_STAT), 101), _generate_reference(sc, range(N_STAT), 202)


def test_detections_per_scan_and_sensor_match_the_reference(pair) -> None:
    sc, new, ref = pair
    for gen, name in ((new, "vectorised"), (ref, "reference")):
        frac = _target_count(gen).mean(axis=0)  # (K, S): the target is always well inside the FoV here
        se = math.sqrt(sc.pd_true * (1 - sc.pd_true) / N_STAT)
        for (k, s), f in np.ndenumerate(frac):
            _within(float(f), sc.pd_true, se, f"{name} detections, scan {k + 1}, sensor {s}")
    a, b = _target_count(new).mean(axis=0), _target_count(ref).mean(axis=0)
    pooled = (a + b) / 2
    se = np.sqrt(np.maximum(pooled * (1 - pooled), 1e-12) * 2 / N_STAT)
    assert np.all(np.abs(a - b) <= Z4 * se)


def test_clutter_counts_and_positions_match_the_reference(pair) -> None:
    sc, new, ref = pair
    lam, meas = sc.clutter_rate, sc.measurement()
    means = {}
    for gen, name in ((new, "vectorised"), (ref, "reference")):
        counts = gen.clutter_counts
        n = counts.size
        means[name] = float(counts.mean())
        _within(means[name], lam, math.sqrt(lam / n), f"{name} Poisson mean")
        # a Poisson variance equals its mean: the sample variance's SE is about sqrt((lam + 2 lam²) / n)
        _within(
            float(counts.var(ddof=1)), lam, math.sqrt((lam + 2 * lam * lam) / n), f"{name} Poisson variance"
        )
        for s in (0, sc.n_sensors - 1):
            pts = _clutter_points(gen, s)
            assert len(pts) == counts[:, :, s].sum()
            assert np.all(meas.in_fov(pts, sc.sensors[s]))
            if sc.meas_model == "range_bearing":
                assert np.all((pts[:, 1] >= -math.pi) & (pts[:, 1] < math.pi))
                centre, half = np.array([sc.fov_range / 2, 0.0]), np.array([sc.fov_range / 2, math.pi])
            else:
                centre, half = sc.sensors[s], np.array([sc.fov_range, sc.fov_range])
            se = half / math.sqrt(3.0 * len(pts))  # uniform on centre ± half: sd half / sqrt(3)
            for c in range(2):
                _within(
                    float(pts[:, c].mean()),
                    float(centre[c]),
                    float(se[c]),
                    f"{name} clutter mean, sensor {s}",
                )
    _within(
        means["vectorised"], means["reference"], math.sqrt(2 * lam / new.clutter_counts.size), "Poisson means"
    )


def test_target_measurement_errors_match_the_reference(pair) -> None:
    sc, new, ref = pair
    R = sc.measurement().R
    sd = np.sqrt(np.diag(R))
    got = {}
    for gen, name in ((new, "vectorised"), (ref, "reference")):
        e = _target_errors(sc, gen)
        n = len(e)
        assert n > 1000
        got[name] = e
        for c in range(2):
            _within(float(e[:, c].mean()), 0.0, sd[c] / math.sqrt(n), f"{name} error mean {c}")
            # the sample variance of a normal: SE sigma² sqrt(2 / (n - 1))
            _within(
                float(e[:, c].var(ddof=1)), R[c, c], R[c, c] * math.sqrt(2 / (n - 1)), f"{name} error var {c}"
            )
        cov = float(np.cov(e.T)[0, 1])
        _within(cov, R[0, 1], sd[0] * sd[1] / math.sqrt(n), f"{name} error covariance")
    a, b = got["vectorised"], got["reference"]
    for c in range(2):
        _within(
            float(a[:, c].mean()), float(b[:, c].mean()), sd[c] * math.sqrt(1 / len(a) + 1 / len(b)), "means"
        )


def test_truth_and_initial_track_match_the_reference(pair) -> None:
    sc, new, ref = pair
    p, v = sc.p0_sd
    sd0 = np.array([p, v, p, v])
    for gen, name in ((new, "vectorised"), (ref, "reference")):
        for c in range(4):
            _within(float(gen.m0[:, c].mean()), sc.x0[c], sd0[c] / math.sqrt(N_STAT), f"{name} m0 mean {c}")
            _within(float(gen.m0[:, c].var(ddof=1)), sd0[c] ** 2, sd0[c] ** 2 * math.sqrt(2 / (N_STAT - 1)),
                    f"{name} m0 var {c}")  # fmt: skip
    # the truth at every scan: the two samples' means agree within 4 SE of their difference
    a, b = new.truth, ref.truth
    se = np.sqrt(a.var(axis=0, ddof=1) / N_STAT + b.var(axis=0, ddof=1) / N_STAT)
    assert np.all(np.abs(a.mean(axis=0) - b.mean(axis=0)) <= Z4 * se)
    if sc.target_motion == "cv":  # and the spread of the last scan is the white-noise acceleration's
        F, Q = cv_model(sc.T, sc.q)
        P = np.zeros((4, 4))
        for _ in range(sc.scans):
            P = F @ P @ F.T + Q
        var = a[:, -1].var(axis=0, ddof=1)
        for c in range(4):
            _within(float(var[c]), P[c, c], P[c, c] * math.sqrt(2 / (N_STAT - 1)), f"truth var {c}")
        _within(float(a[:, -1, 0].mean()), sc.x0[0] + sc.scans * sc.T * sc.x0[1], math.sqrt(P[0, 0] / N_STAT),
                "truth x")  # fmt: skip


# ------------------------------------------------------------------------------------------- edge cases
def test_no_clutter_and_certain_detection_give_one_measurement_each() -> None:
    sc = slrt.SlrtScenario(scans=6, clutter_rate=0.0, pd_true=1.0, pd_filter=1.0)
    gen = slrt.generate(sc, range(20), 3)
    assert not gen.clutter_counts.any()
    for scan in gen.scans:
        for z, v in zip(scan.Z, scan.valid, strict=True):
            assert z.shape == (20, 1, 2) and v.all()
    e = _target_errors(sc, gen)
    assert len(e) == 20 * 6 * 4 and np.all(np.abs(e) < 6 * np.sqrt(np.diag(sc.measurement().R)))


def test_no_clutter_and_missed_detections_give_empty_lists() -> None:
    sc = slrt.SlrtScenario(scans=6, clutter_rate=0.0, pd_true=0.3, pd_filter=0.3)
    n_t = _target_count(slrt.generate(sc, range(50), 3))
    assert set(np.unique(n_t)) == {0, 1} and 0.15 < n_t.mean() < 0.45


def test_no_target_gives_the_same_clutter_and_no_target_measurement() -> None:
    with_target = slrt.generate(slrt.SlrtScenario(scans=6), range(8), 4)
    without = slrt.generate(slrt.SlrtScenario(scans=6, target=False), range(8), 4)
    assert not _target_count(without).any()
    np.testing.assert_array_equal(without.truth, with_target.truth)
    np.testing.assert_array_equal(without.m0, with_target.m0)
    for i in range(8):
        for k, (row_a, row_b) in enumerate(zip(_lists(with_target, i), _lists(without, i), strict=True)):
            for s, (za, zb) in enumerate(zip(row_a, row_b, strict=True)):
                n_t = len(za) - with_target.clutter_counts[i, k, s]
                np.testing.assert_array_equal(za[n_t:], zb)  # the same false alarms, target's dropped


@pytest.mark.parametrize("meas_model", ["range_bearing", "cartesian"])
def test_a_target_outside_the_field_of_view_is_not_measured(meas_model: str) -> None:
    # sensors at ±13 km on the x axis with a 14 km field of view; the target flies from the origin towards
    # +x at 150 m/s: sensor 1 (at -13 km) loses it after about 7 s, sensor 0 keeps it
    sc = slrt.SlrtScenario(n_sensors=2, scans=20, clutter_rate=0.0, pd_true=1.0, pd_filter=1.0, q=0.0,
                           x0=(0.0, 150.0, 0.0, 0.0), fov_range=14_000.0, meas_model=meas_model)  # fmt: skip
    gen = slrt.generate(sc, range(10), 2)
    n_t = _target_count(gen)
    dist = np.abs(gen.truth[..., 0, None] - sc.sensors[:, 0])  # (R, K, S): along x, y stays 0
    margin = 6 * sc.sigma_r
    assert np.all(n_t[dist < sc.fov_range - margin] == 1)
    assert np.all(n_t[dist > sc.fov_range + margin] == 0)
    assert n_t[:, :, 0].all() and not n_t[:, -5:, 1].any()


def test_bearings_are_wrapped() -> None:
    # the target on the negative x axis, seen from a sensor at the origin: bearings near ±π, wrapped into (−π, π]
    sc = slrt.SlrtScenario(n_sensors=1, radius=0.0, scans=5, clutter_rate=0.0, pd_true=1.0, pd_filter=1.0,
                           x0=(-5_000.0, 0.0, 0.0, 0.0), sigma_phi_deg=5.0)  # fmt: skip
    gen = slrt.generate(sc, range(50), 1)
    phi = np.concatenate([scan.Z[0][:, 0, 1] for scan in gen.scans])
    assert np.all((phi > -math.pi) & (phi <= math.pi))
    assert (phi > 0).any() and (phi < 0).any()  # both sides of the cut


def test_no_runs() -> None:
    gen = slrt.generate(slrt.SlrtScenario(scans=3), [], 1)
    assert gen.truth.shape == (0, 3, 4) and gen.m0.shape == (0, 4) and gen.clutter_counts.shape == (0, 3, 4)
    assert all(z.shape == (0, 0, 2) for scan in gen.scans for z in scan.Z)
