"""The monostatic radar equation: echo power, amplitude and signal-to-noise ratio of a point target.

Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*, give the carrier (10 GHz) and
the sampling rate (1 GHz) of their front end (Table I) but no power budget; every other value here is assumed
(typical of an X-band surveillance radar) and can be changed.

Received echo power of a target of radar cross-section σ at range r (the radar equation, e.g. Skolnik,
*Introduction to Radar Systems*, ch. 2):

    P_r = P_t G_t G_r λ² σ / ((4π)³ r⁴ L),    λ = c / f_c.

Noise: the receiver's system noise temperature is T_s = T₀ F (antenna at T₀ = 290 K, noise figure F; assumed),
one-sided noise power spectral density N₀ = k T_s. The real IF signal is sampled at f_s behind an ideal
anti-alias filter at f_s/2 (assumed), so the noise bandwidth is B = f_s/2 and each real sample has noise variance
σ_n² = N₀ B = k T_s f_s/2. Two signal-to-noise ratios follow:

* per sample (in B): SNR = P_r / (N₀ B) = (A²/2)/σ_n² for an IF sinusoid of amplitude A = √(2 P_r) (1 Ω);
* per pulse (energy): E/N₀ = n_p P_r T_p / N₀ for a pulse of duration T_p and n_p pulses integrated
  coherently (ideal integration, assumed: n_p = 1 by default). 2E/N₀ is the peak SNR of a matched filter.

All methods broadcast over arrays of ranges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from motionsig_cli.config import ConfigError, in_range, integer, positive

__all__ = ["BOLTZMANN", "C_LIGHT", "RadarEquation", "db", "undb"]

C_LIGHT = 299_792_458.0
"""Speed of light [m/s]."""
BOLTZMANN = 1.380_649e-23
"""Boltzmann's constant [J/K]."""
T0 = 290.0
"""Reference noise temperature [K]."""


def db(x: np.ndarray | float) -> np.ndarray:
    """10 log₁₀ x."""
    return 10.0 * np.log10(np.asarray(x, dtype=float))


def undb(x_db: np.ndarray | float) -> np.ndarray:
    """10^(x/10)."""
    return 10.0 ** (np.asarray(x_db, dtype=float) / 10.0)


@dataclass(frozen=True)
class RadarEquation:
    """A monostatic radar's power budget (module docstring). Every default but ``f_c`` and ``fs`` is assumed.

    Attributes:
        p_t: peak transmit power [W] (assumed 10 kW).
        g_t_db, g_r_db: transmit and receive antenna gains [dBi] (assumed 38 dBi each: a ≈ 2° pencil beam at
            10 GHz, G ≈ 4π·0.6/θ²).
        f_c: carrier frequency [Hz] (Table I: 10 GHz); λ = c/f_c.
        rcs: target radar cross-section σ [m²] (assumed 1 m², a small aircraft).
        loss_db: system losses L [dB] (assumed 6 dB: transmit, receive, atmospheric and processing).
        noise_figure_db: receiver noise figure F [dB] (assumed 3 dB); T_s = 290 K · F.
        fs: sampling rate of the real IF signal [Hz] (Table I: 1 GHz); noise bandwidth B = fs/2.
        n_pulses: pulses integrated coherently per measurement (assumed 1).
    """

    p_t: float = 10_000.0
    g_t_db: float = 38.0
    g_r_db: float = 38.0
    f_c: float = 10e9
    rcs: float = 1.0
    loss_db: float = 6.0
    noise_figure_db: float = 3.0
    fs: float = 1e9
    n_pulses: int = 1

    def __post_init__(self) -> None:
        positive("p_t", self.p_t, unit="W")
        in_range("g_t_db", self.g_t_db, -30.0, 80.0, unit="dBi")
        in_range("g_r_db", self.g_r_db, -30.0, 80.0, unit="dBi")
        in_range("f_c", self.f_c, 1e6, 1e12, unit="Hz")
        positive("rcs", self.rcs, unit="m²")
        in_range("loss_db", self.loss_db, 0.0, 100.0, unit="dB")
        in_range("noise_figure_db", self.noise_figure_db, 0.0, 50.0, unit="dB")
        in_range("fs", self.fs, 1e3, 1e12, unit="Hz")
        integer("n_pulses", self.n_pulses, 1, 10_000_000)

    @property
    def wavelength(self) -> float:
        """λ = c/f_c [m]."""
        return C_LIGHT / self.f_c

    @property
    def noise_psd(self) -> float:
        """N₀ = k T₀ F [W/Hz]."""
        return BOLTZMANN * T0 * float(undb(self.noise_figure_db))

    @property
    def noise_bandwidth(self) -> float:
        """B = fs/2 [Hz]: the Nyquist band of the real IF samples."""
        return self.fs / 2.0

    @property
    def noise_power(self) -> float:
        """σ_n² = N₀ B [W]: the noise variance of one real sample."""
        return self.noise_psd * self.noise_bandwidth

    def _gain(self) -> float:
        g = float(undb(self.g_t_db + self.g_r_db - self.loss_db))
        return self.p_t * g * self.wavelength**2 * self.rcs / (4.0 * math.pi) ** 3

    def _ranges(self, r: np.ndarray | float) -> np.ndarray:
        r = np.asarray(r, dtype=float)
        if r.size and (not np.all(np.isfinite(r)) or np.any(r <= 0)):
            bad = r[~(np.isfinite(r) & (r > 0))].flat[0]
            raise ConfigError("range", float(bad), "is not a finite number > 0 m")
        return r

    def received_power(self, r: np.ndarray | float) -> np.ndarray:
        """P_r(r) [W] of one pulse."""
        return self._gain() / self._ranges(r) ** 4

    def amplitude(self, r: np.ndarray | float) -> np.ndarray:
        """Peak amplitude A = √(2 P_r) [V across 1 Ω] of the IF echo."""
        return np.sqrt(2.0 * self.received_power(r))

    def snr(self, r: np.ndarray | float) -> np.ndarray:
        """Per-sample SNR P_r/(N₀ B) (linear) of one pulse."""
        return self.received_power(r) / self.noise_power

    def energy_snr(self, r: np.ndarray | float, duration: float) -> np.ndarray:
        """E/N₀ = n_p P_r T_p / N₀ (linear) for pulses of ``duration`` T_p [s]."""
        positive("duration", duration, unit="s")
        return self.n_pulses * self.received_power(r) * duration / self.noise_psd

    def range_for_energy_snr(self, energy_snr: np.ndarray | float, duration: float) -> np.ndarray:
        """The range [m] at which E/N₀ = ``energy_snr`` (linear) for pulses of ``duration``: the inverse of
        :meth:`energy_snr`."""
        positive("duration", duration, unit="s")
        e = np.asarray(energy_snr, dtype=float)
        if e.size and (not np.all(np.isfinite(e)) or np.any(e <= 0)):
            raise ConfigError("energy_snr", float(e.flat[0]), "is not a finite number > 0")
        return (self.n_pulses * self._gain() * duration / (self.noise_psd * e)) ** 0.25
