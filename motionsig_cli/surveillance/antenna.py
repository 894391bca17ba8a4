"""The jammer's transmitter: a parabolic dish turning rf power into ERP (Table 1.1 of ATC-10: Schneider,
Stiglitz & Eckberg, MIT Lincoln Laboratory, 1972).

The report gives only the results (Table 1.1 and "33 dBW ERP … 30 watts of rf power and an antenna
with a 20° beamwidth"); the chain below is the standard one that reproduces them [A]:

    ERP[dBW] = P_rf[dBW] + G[dBi]                (lossless, ERP = EIRP)
    G        = η (π D / λ)²                      (aperture efficiency η)
    θ_3dB    = k λ / D  degrees                  (k = 70 for a parabolic dish)
    λ        = c / f

so G·θ² = k²π²η, about 26 600 deg² for η = 0.55. The report does not say which of P_rf or D the
designer fixes; :func:`jammer_antenna` takes either.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from motionsig_cli.config import ConfigError, in_range, positive

C_M_S = 299_792_458.0
FOOT_M = 0.3048


@dataclass(frozen=True, slots=True)
class DishAntenna:
    """Dish model (assumed, the report does not state it: f = 1.6 GHz, L band, "the centre of 1535–1660
    MHz"; aperture efficiency η = 0.55; beamwidth constant k = 70 degrees).

    Attributes:
        freq_hz: Carrier frequency f [Hz], > 0 with a finite wavelength c/f.
        efficiency: Aperture efficiency η in (0, 1] (a passive dish cannot exceed its aperture).
        beamwidth_const_deg: k of θ_3dB = k λ/D [degrees], > 0.
    """

    freq_hz: float = 1.6e9
    efficiency: float = 0.55
    beamwidth_const_deg: float = 70.0

    def __post_init__(self) -> None:
        positive("freq_hz", self.freq_hz, unit="Hz")
        in_range("efficiency", self.efficiency, 0.0, 1.0, lo_open=True)
        positive("beamwidth_const_deg", self.beamwidth_const_deg, unit="degrees")
        if not math.isfinite(C_M_S / self.freq_hz):
            raise ConfigError("freq_hz", self.freq_hz, "gives an infinite wavelength")

    def __str__(self) -> str:
        return f"f = {self.freq_hz:g} Hz, η = {self.efficiency:g}, k = {self.beamwidth_const_deg:g}"

    @property
    def wavelength_m(self) -> float:
        """λ = c/f."""
        return C_M_S / self.freq_hz

    def gain_dbi(self, diameter_m: float) -> float:
        """G = 10·log10 η + 20·log10(πD/λ)."""
        return 10 * math.log10(self.efficiency) + 20 * math.log10(math.pi * diameter_m / self.wavelength_m)

    def diameter_m(self, gain_dbi: float) -> float:
        """D = (λ/π)·√(G/η)."""
        return self.wavelength_m / math.pi * math.sqrt(10 ** (gain_dbi / 10) / self.efficiency)

    def beamwidth_deg(self, diameter_m: float) -> float:
        """θ_3dB = kλ/D in degrees."""
        return self.beamwidth_const_deg * self.wavelength_m / diameter_m


DEFAULT_DISH = DishAntenna()


@dataclass(frozen=True, slots=True)
class JammerTransmitter:
    """A jammer meeting an ERP: rf power, dish gain, diameter and beamwidth."""

    erp_dbw: float
    rf_dbw: float
    gain_dbi: float
    diameter_m: float
    beamwidth_deg: float

    @property
    def diameter_ft(self) -> float:
        """Dish diameter in feet (Table 1.1's unit)."""
        return self.diameter_m / FOOT_M

    @property
    def rf_w(self) -> float:
        """rf power in watts."""
        return 10 ** (self.rf_dbw / 10)


def jammer_antenna(
    erp_dbw: float,
    *,
    rf_dbw: float | None = None,
    diameter_m: float | None = None,
    antenna: DishAntenna = DEFAULT_DISH,
) -> JammerTransmitter:
    """Complete the chain from the ERP and exactly one of the rf power or the dish diameter.

    Inverse chain (rf power given): G = ERP − P_rf, then D, then θ. Forward chain (D given): G from
    D, then P_rf = ERP − G and θ. A bad argument, or a chain that leaves floating-point range or gives
    no dish, is a :class:`~motionsig_cli.config.ConfigError` naming the argument given (``rf_dbw`` or
    ``diameter_m``).
    """
    if rf_dbw is not None and diameter_m is not None:
        raise ConfigError("diameter_m", diameter_m, "is given with rf_dbw: give exactly one of the two")
    if rf_dbw is None and diameter_m is None:
        raise ConfigError("rf_dbw", None, "is missing, and so is diameter_m: give exactly one of the two")
    if not math.isfinite(erp_dbw):
        raise ConfigError("erp_dbw", erp_dbw, "is not a finite number of dBW")
    if diameter_m is not None:
        positive("diameter_m", diameter_m, unit="m")
    if rf_dbw is not None and not math.isfinite(rf_dbw):
        raise ConfigError("rf_dbw", rf_dbw, "is not a finite number of dBW")
    given, value = ("rf_dbw", rf_dbw) if rf_dbw is not None else ("diameter_m", diameter_m)
    try:
        if diameter_m is not None:
            gain = antenna.gain_dbi(diameter_m)
            rf = erp_dbw - gain
        else:
            assert rf_dbw is not None
            gain = erp_dbw - rf_dbw
            diameter_m = antenna.diameter_m(gain)
            rf = rf_dbw
        tx = JammerTransmitter(erp_dbw, rf, gain, diameter_m, antenna.beamwidth_deg(diameter_m))
        ok = all(math.isfinite(v) for v in (tx.rf_dbw, tx.gain_dbi, tx.diameter_m, tx.beamwidth_deg, tx.rf_w))
    except (OverflowError, ZeroDivisionError, ValueError):
        ok = False
    if not ok:
        raise ConfigError(given, value, "takes the antenna chain out of floating-point range")
    if tx.gain_dbi <= 0.0 or tx.beamwidth_deg > 180.0:
        raise ConfigError(
            given,
            value,
            f"gives no dish: gain {tx.gain_dbi:.3g} dBi, beamwidth {tx.beamwidth_deg:.3g} deg "
            "(the rf power must be below the ERP, the dish larger than a wavelength)",
        )
    return tx
