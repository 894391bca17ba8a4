"""The Earth's rotation during a signal's flight (the Sagnac correction) for anchors whose positions are given
in the Earth-fixed frame at the signal's transmission, as GNSS satellite positions computed from
ephemerides at the transmission time are.

The receiver's fix is in the Earth-fixed frame of the reception time t_r. A satellite at S (ECEF at the
transmission time t_r − τ) is, in the frame of t_r, at

    S' = R_z(ω_E τ) S,   R_z(θ) = [[cos θ, sin θ, 0], [−sin θ, cos θ, 0], [0, 0, 1]],   τ = ‖p − S'‖/c

(the frame has turned by ω_E τ about the z axis during the flight: the Earth-rotation correction of the
GPS user algorithm, IS-GPS-200). τ depends on S' only through the range, so a fixed-point iteration from
τ = ‖p − S‖/c converges at once: a change of the satellite's position by δ changes τ by at most δ/c, and
θ by ω_E δ/c ≈ 2·10⁻¹³ δ/m. For a GPS satellite τ ≈ 70 ms and ω_E τ R ≈ 130 m; the fix moves by up to
some tens of metres.
"""

from __future__ import annotations

import numpy as np

__all__ = ["OMEGA_E", "rotate_for_flight"]

OMEGA_E = 7.2921151467e-5
"""The Earth's rotation rate [rad/s] (WGS-84, as IS-GPS-200)."""
C_M_PER_S = 299_792_458.0


def rotate_for_flight(receivers: np.ndarray, position: np.ndarray, iterations: int = 2) -> np.ndarray:
    """The anchors' positions in the Earth-fixed frame of the reception (module docstring).

    Args:
        receivers: (E, K, 3) ECEF positions at the transmission [m].
        position: (E, 3) the receiving (or transmitting) point [m] (the current fix).
        iterations: fixed-point iterations of τ.

    Returns:
        (E, K, 3) the rotated positions [m] (NaN where an input is NaN).
    """
    S = np.asarray(receivers, float)
    p = np.asarray(position, float)[..., None, :]
    Sr = S
    for _ in range(iterations):
        theta = OMEGA_E * np.linalg.norm(p - Sr, axis=-1) / C_M_PER_S
        c, s = np.cos(theta), np.sin(theta)
        Sr = np.stack([c * S[..., 0] + s * S[..., 1], -s * S[..., 0] + c * S[..., 1], S[..., 2]], axis=-1)
    return Sr
