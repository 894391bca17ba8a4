"""The per-process cache of measurement-independent results: bounded in bytes, read-only entries, and a
detector that gives the same numbers (and the same progress) whether its fixed part was kept or computed."""

import numpy as np
import pytest

from motionsig_cli import cache
from motionsig_cli.cache import BytesLRU, clear_all, freeze, key_of
from motionsig_cli.detection import lmp
from motionsig_cli.detection.lmp import LMPConfig, lmp_detect, progress_steps
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.modesig.lmp1d import simulate_trials
from motionsig_cli.signals.correlation import to_bipolar
from motionsig_cli.signals.modes import corrected_codes

CHIPS = to_bipolar(corrected_codes()).astype(float)
N = 120


@pytest.fixture(autouse=True)
def cold():
    clear_all()
    yield
    clear_all()


def test_lru_keeps_hits_and_evicts_the_least_recently_used_by_bytes():
    c: BytesLRU[str] = BytesLRU(lambda: 100)
    built = []

    def value(name: str, size: int):
        def build():
            built.append(name)
            return name, size

        return build

    assert c.get("a", value("a", 40)) == ("a", False)
    assert c.get("b", value("b", 40)) == ("b", False)
    assert c.get("a", value("a", 40)) == ("a", True)  # a is now the most recently used
    assert c.get("c", value("c", 40)) == ("c", False)  # 120 > 100: b goes, not a
    assert c.get("a", value("a", 40))[1] and not c.get("b", value("b", 40))[1]
    assert c.nbytes <= 100 and built == ["a", "b", "c", "b"]
    assert c.get("big", value("big", 101)) == ("big", False)  # larger than the bound: returned, not kept
    assert not c.get("big", value("big", 101))[1]
    assert (c.hits, c.misses) == (2, 6)


def test_a_bound_of_zero_keeps_nothing(monkeypatch):
    monkeypatch.setenv("MOTIONSIG_CACHE_MB", "0")
    c: BytesLRU[int] = BytesLRU()
    c.get("a", lambda: (1, 8))
    assert len(c) == 0 and not c.get("a", lambda: (1, 8))[1]


@pytest.mark.parametrize(
    ("text", "want"), [("1", 2**20), ("0", 0), ("-3", cache.DEFAULT_BYTES), ("x", cache.DEFAULT_BYTES)]
)
def test_the_bound_comes_from_the_environment(monkeypatch, text, want):
    monkeypatch.setenv("MOTIONSIG_CACHE_MB", text)
    assert cache.cache_bytes() == want


def test_keys_tell_arrays_apart_by_dtype_shape_and_bytes():
    a = np.arange(6.0)
    keys = {
        key_of(a),
        key_of(a.reshape(2, 3)),
        key_of(a.astype(np.float32)),
        key_of(a + 1e-15 * (a == 5)),
        key_of(a, 1),
        key_of(a, 1.0),
    }
    assert len(keys) == 6
    assert key_of(a.copy()) == key_of(a) and key_of(np.asfortranarray(a.reshape(2, 3))) == key_of(
        a.reshape(2, 3)
    )


def test_frozen_arrays_refuse_writes():
    a, b = np.zeros(3), np.ones((2, 2))
    assert freeze([a, b]) == a.nbytes + b.nbytes
    with pytest.raises(ValueError, match="read-only"):
        a[0] = 1.0


def _records(n_records: int, R: float = 1e-2, missing: bool = False) -> tuple[np.ndarray, Vehicle1D]:
    vehicle = Vehicle1D(R=R)
    y, _ = simulate_trials(vehicle, CHIPS, 20, 1.0, N, 7, list(range(n_records)))
    if missing:
        y[:, 30:35] = np.nan
    return y, vehicle


@pytest.mark.parametrize(
    ("cfg", "missing"),
    [(LMPConfig(), False), (LMPConfig(center="h0-noise"), False), (LMPConfig(weights="exact"), True)],
)
def test_kept_and_computed_banks_give_the_same_numbers_and_progress(cfg, missing):
    y, vehicle = _records(3, missing=missing)
    hz = [60, N]
    runs = []
    for _ in range(2):  # the first computes the bank's fixed part, the second finds it kept
        steps: list[int] = []
        res = lmp_detect(y, CHIPS, vehicle, 20, cfg, hz, progress=steps.append)
        runs.append((res, sum(steps)))
    assert lmp._GAINS.hits >= 1 and lmp._REPLICAS.hits >= 1
    (cold_res, cold_steps), (warm_res, warm_steps) = runs
    assert cold_steps == warm_steps == progress_steps(N, cfg)
    for name in ("J0", "J_cos", "J_sin", "Lambda"):
        assert np.array_equal(getattr(cold_res, name), getattr(warm_res, name)), name
    clear_all()  # and a bank computed in a fresh process (nothing kept) agrees bit for bit too
    fresh = lmp_detect(y, CHIPS, vehicle, 20, cfg, hz)
    assert np.array_equal(fresh.Lambda, warm_res.Lambda)


def test_each_variance_and_missing_pattern_has_its_own_entry():
    y, vehicle = _records(2)
    lmp_detect(y, CHIPS, vehicle, 20, LMPConfig(), [N])
    y2, vehicle2 = _records(2, R=1e-1, missing=True)
    res = lmp_detect(y2, CHIPS, vehicle2, 20, LMPConfig(), [N])
    assert len(lmp._GAINS) == 2 and len(lmp._REPLICAS) == 1
    clear_all()
    assert np.array_equal(lmp_detect(y2, CHIPS, vehicle2, 20, LMPConfig(), [N]).Lambda, res.Lambda)


def test_kept_gains_are_read_only():
    y, vehicle = _records(1)
    lmp_detect(y, CHIPS, vehicle, 20, LMPConfig(), [N])
    ((g, _),) = lmp._GAINS._items.values()
    for a in (g.g1.K, g.g1.S_inv, g.g0.logdet_2pi_S):
        with pytest.raises(ValueError, match="read-only"):
            a.flat[0] = 0.0
