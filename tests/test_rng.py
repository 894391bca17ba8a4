"""Per-trial streams depend on (seed, trial) only."""

import numpy as np

from motionsig_cli.rng import trial_rng


def test_trial_stream_equals_spawned_child():
    """trial_rng(seed, t) is SeedSequence(seed).spawn(n)[t] for any n > t (NumPy SeedSequence docs)."""
    for n in (5, 50):
        children = np.random.SeedSequence(123).spawn(n)
        for t in (0, 3, 4):
            a = trial_rng(123, t).standard_normal(5)
            b = np.random.default_rng(children[t]).standard_normal(5)
            assert np.array_equal(a, b)


def test_order_independence():
    forward = [trial_rng(9, t).random() for t in range(10)]
    backward = [trial_rng(9, t).random() for t in reversed(range(10))][::-1]
    assert forward == backward
    assert len(set(forward)) == 10
