"""The exact distributed Kalman filter (DKF) in the track-existence test: local filters that use global
model knowledge, so that the product of their Gaussians is the centralised posterior at every scan and the
fusion centre's log LR equals the centralised filter's (Govaers & Koch, *Distributed Kalman filter fusion
at arbitrary instants of time*, FUSION 2010, and *An exact solution to track-to-track-fusion at arbitrary
communication rates*, IEEE Trans. AES 2012; Govaers, *Distributed Kalman Filter*, in *Kalman Filters:
Theory for Advanced Applications*, IntechOpen 2018; the product representation and the LR factor are those
of Govaers, *Evaluation of Distributed Detection Methods for Agile Targets*, Fraunhofer FKIE, slides).

**Where it is exact.** Every local update must be a Kalman update whose covariance does not depend on
the data, so that every node can run the *global* covariance recursion (the centralised filter's) itself:
linear sensors (``cartesian``: z = Hx + v, H constant, R_s known to every node), every sensor reporting
the target at every scan and nothing else (p_D = 1 for the filters, data without clutter, no gate; the
filters' clutter density ρ_F may be positive: it is the density of a measurement under h₀, which scales
the LR — log Λ gains log(p_D/ρ_F) per measurement — but not the update, a Kalman update with one
measurement and p_D = 1). With range–
bearing sensors H depends on the state estimate (the data), and with misses or clutter the PDA
posterior covariance depends on the association weights (the data), so no node knows the global
covariance: there the federated filter (``fkf``) is the distributed rule, as the slides say. The method
refuses those models (:func:`check_dkf`) and a scan in which a sensor reports more than one
measurement (impossible in data without clutter).

**The filter.** With the global predicted and filtered covariances P_{k|k−1} = F P_{k−1|k−1} Fᵀ + Q and
P_{k|k}⁻¹ = P_{k|k−1}⁻¹ + Σ_s H_sᵀ R_s⁻¹ H_s (computed here sensor by sensor in the Joseph form, no
inverse), local node s holds N(x; xˢ, S·P) (S sensors), so that ∏_s N(x; xˢ, S·P) ∝ N(x; x̄, P), x̄ the
mean of the xˢ — the product representation of the slides with every local covariance "globalised":

1. prediction: xˢ ← F xˢ; the global P_{k|k−1}; the local covariance S·P_{k|k−1}. As all local
   covariances are equal, the product of the predicted locals is the predicted product (the step that
   the federated filter only approximates, with the relaxed S·Q).
2. update with the local data (the PDA update, here a Kalman update): (xˢ₊, Pˢ₊, p̄ˢ).
3. fusion centre: log Λ(k) = log c_{k|k} − log c_{k|k−1} + Σ_s log p̄ˢ, with the constants of the products
   of the predicted and updated locals (the slides' formula). It is exact: ∏_s ℓ_s(x)·N(x; xˢ, S·P_{k|k−1})
   = ∏_s p̄ˢ N(x; xˢ₊, Pˢ₊) for linear Gaussian ℓ_s, and ∏_s N(x; xˢ, S·P_{k|k−1}) =
   c_{k|k−1} N(x; x̄, P_{k|k−1}); integrating both sides gives Λ(k) = ∫ ∏_s ℓ_s(x) N(x; x̄, P_{k|k−1}) dx,
   the centralised factor.
4. globalisation: each node keeps its information vector yˢ = (Pˢ₊)⁻¹xˢ₊ and replaces its information
   matrix by the global one divided by S: xˢ ← S·P_{k|k} yˢ = P_{k|k}(P_{k|k−1}⁻¹ xˢ_{k|k−1} + S H_sᵀR_s⁻¹zˢ)
   (the Govaers–Koch local update, here scaled by S because our product uses the mean of the xˢ where
   theirs uses the sum). As Σ_s (Pˢ₊)⁻¹ = P_{k|k}⁻¹ in the Kalman case, the product is unchanged:
   ∏_s N(x; xˢ, S·P_{k|k}) ∝ N(x; x_{k|k}, P_{k|k}), the centralised posterior. The xˢ are not estimates
   of the target (their mean is); only the fusion centre's mean is.

No feedback from the centre is needed: every node computes P_{k|k} from the model alone. Initialised at
xˢ = m₀ and the global P₀, the score equals the centralised filter's (CKF) to rounding (the tests check
1e-9 relative with sensors of different noise, where the federated filter without feedback differs).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.existence_model import (
    FusionOptions,
    ScanData,
    TrackExistenceModel,
    log_product_constant,
    sensor_update,
    stack_scan,
)

__all__ = ["check_dkf", "dkf_inapplicable", "score_dkf"]


def dkf_inapplicable(model: TrackExistenceModel, options: FusionOptions) -> str | None:
    """Why the exact DKF does not apply to this model, or None where it does (module docstring)."""
    why = []
    if model.meas.kind != "cartesian":
        why.append(f"{model.meas.kind.replace('_', '-')} sensors (their linearisation depends on the data)")
    if any(pd < 1.0 for pd in model.detection_probabilities()):
        why.append("p_D < 1")
    if options.gate_pg is not None and options.gate_pg < 1.0:
        why.append("a gate")
    if not why:
        return None
    return (
        "is exact only for linear (cartesian) sensors with p_D = 1, data without clutter and no gate, where "
        f"every node knows the global covariance; here: {', '.join(why)} (use fkf or fkf-feedback)"
    )


def check_dkf(model: TrackExistenceModel, options: FusionOptions) -> None:
    """:class:`~motionsig_cli.config.ConfigError` naming ``methods`` where the DKF does not apply."""
    why = dkf_inapplicable(model, options)
    if why is not None:
        raise ConfigError("methods", "dkf", why)


def _kalman_covariance(P: np.ndarray, H: np.ndarray, Rn: np.ndarray) -> np.ndarray:
    """The Kalman update of covariances P (R, 4, 4) by one linear sensor (H (2, 4), R (2, 2)), Joseph form."""
    S = H @ P @ H.T + Rn
    K = np.swapaxes(np.linalg.solve(S, H @ P), -1, -2)  # PHᵀS⁻¹
    IKH = np.eye(4) - K @ H
    P = IKH @ P @ np.swapaxes(IKH, -1, -2) + K @ Rn @ np.swapaxes(K, -1, -2)
    return 0.5 * (P + np.swapaxes(P, -1, -2))


def score_dkf(
    model: TrackExistenceModel, m0: np.ndarray, scans: Sequence[ScanData], options: FusionOptions
) -> np.ndarray:
    """DKF: local filters on the global covariance (S·P), fused through the product constants; equal to the
    CKF where it applies (:func:`check_dkf`); log LR (R, K)."""
    check_dkf(model, options)
    R, S = m0.shape[0], model.n_sensors
    F, Q = model.F, model.Q
    H = model.meas.jacobian(np.zeros(4), np.zeros(2))  # constant for linear sensors
    noises = [model.sensor(s)[0].R for s in range(S)]
    out = np.zeros((R, len(scans)))
    Pg = np.broadcast_to(model.m0_cov, (R, 4, 4)).copy()  # the global covariance, known to every node
    m = np.tile(m0, (S, 1))  # local means (S·R, 4), sensor-major
    sensor_rows = np.repeat(model.sensors, R, axis=0)
    total = np.zeros(R)
    for k, scan in enumerate(scans):
        counts = [int(v.sum(axis=1).max(initial=0)) for v in scan.valid]
        if max(counts) > 1:
            raise ConfigError(
                "methods", "dkf", f"needs at most one measurement per sensor and scan (no clutter): scan {k + 1} has "
                f"{max(counts)} from one sensor"
            )  # fmt: skip
        m, Pg = m @ F.T, F @ Pg @ F.T + Q
        P = S * np.tile(Pg, (S, 1, 1))  # every local covariance: the globalised S·P_{k|k−1}
        log_c_prior = log_product_constant(list(m.reshape(S, R, 4)), list(P.reshape(S, R, 4, 4)))
        Zs, Vs = stack_scan(scan, S, R)
        mp, Pp, lp = sensor_update(model, m, P, Zs, Vs, sensor_rows)
        log_c_post = log_product_constant(list(mp.reshape(S, R, 4)), list(Pp.reshape(S, R, 4, 4)))
        total = total + lp.reshape(S, R).sum(axis=0) + log_c_post - log_c_prior
        out[:, k] = total
        for s in range(S):  # global model knowledge: the centralised covariance recursion
            Pg = _kalman_covariance(Pg, H, noises[s])
        y = np.linalg.solve(Pp, mp[..., None])  # each node's information vector (Pˢ₊)⁻¹xˢ₊
        m = S * (np.tile(Pg, (S, 1, 1)) @ y)[..., 0]  # globalised: xˢ = S·P_{k|k}·yˢ
    return out
