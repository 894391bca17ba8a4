"""Reproducible random streams: trial t draws from child t of ``SeedSequence(seed)``.

``SeedSequence(seed, spawn_key=(t,))`` is exactly ``SeedSequence(seed).spawn(n)[t]`` for any n > t,
so a trial's numbers depend on (seed, t) only — not on how many trials run, in which order, or
on which worker.
"""

from __future__ import annotations

import numpy as np

DEFAULT_SEED = 2008


def trial_rng(seed: int, trial: int, *subsystem: int) -> np.random.Generator:
    """Generator for trial ``trial`` (and optional sub-stream keys, e.g. process vs measurement noise).

    Examples:
        The same seed and trial give the same draws, whatever was drawn before; another trial, others:

        >>> from motionsig_cli import trial_rng
        >>> a = trial_rng(42, 3).standard_normal(2)
        >>> b = trial_rng(42, 3).standard_normal(2)
        >>> bool((a == b).all()), bool((trial_rng(42, 4).standard_normal(2) != a).all())
        (True, True)
    """
    if seed < 0 or trial < 0 or any(s < 0 for s in subsystem):
        raise ValueError("seed, trial and subsystem keys must be non-negative integers")
    return np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(trial, *subsystem)))
