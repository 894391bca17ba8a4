"""The radar equation: a hand-computed budget, its scaling laws and inverse, and the checks of its fields."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models.radar_equation import RadarEquation, db, undb


def test_hand_computed_budget():
    # P_t = 1 kW, G = 30 dBi each, λ = 3 cm (f_c = 9.993 GHz ≈ c/0.03), σ = 2 m², L = 0 dB, r = 10 km
    eq = RadarEquation(p_t=1e3, g_t_db=30.0, g_r_db=30.0, f_c=299_792_458.0 / 0.03, rcs=2.0, loss_db=0.0,
                       noise_figure_db=0.0, fs=1e9)  # fmt: skip
    want = 1e3 * 1e3 * 1e3 * 0.03**2 * 2.0 / ((4 * math.pi) ** 3 * 1e4**4)
    assert float(eq.received_power(1e4)) == pytest.approx(want, rel=1e-12)
    n0 = 1.380649e-23 * 290.0
    assert eq.noise_psd == pytest.approx(n0, rel=1e-12)
    assert eq.noise_power == pytest.approx(n0 * 0.5e9, rel=1e-12)  # B = fs/2
    assert float(eq.snr(1e4)) == pytest.approx(want / (n0 * 0.5e9), rel=1e-12)
    assert float(eq.energy_snr(1e4, 1e-6)) == pytest.approx(want * 1e-6 / n0, rel=1e-12)
    assert float(eq.amplitude(1e4)) == pytest.approx(math.sqrt(2 * want), rel=1e-12)


def test_scaling_and_inverse():
    eq = RadarEquation()
    r = np.array([1e4, 2e4, 1e5])
    e = eq.energy_snr(r, 1.12e-6)
    np.testing.assert_allclose(db(e[0]) - db(e[1]), 40 * math.log10(2), rtol=1e-12)  # r⁻⁴
    np.testing.assert_allclose(eq.range_for_energy_snr(e, 1.12e-6), r, rtol=1e-12)
    # losses, noise figure and integrated pulses enter as stated
    e2 = RadarEquation(loss_db=9.0, noise_figure_db=6.0, n_pulses=8).energy_snr(r, 1.12e-6)
    np.testing.assert_allclose(db(e2) - db(e), -3.0 - 3.0 + 10 * math.log10(8), atol=1e-9)
    assert eq.wavelength == pytest.approx(0.0299792458)
    assert float(undb(db(123.0))) == pytest.approx(123.0)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"p_t": -1.0}, "p_t"),
        ({"rcs": 0.0}, "rcs"),
        ({"loss_db": -1.0}, "loss_db"),
        ({"noise_figure_db": float("nan")}, "noise_figure_db"),
        ({"f_c": 0.0}, "f_c"),
        ({"n_pulses": 0}, "n_pulses"),
        ({"g_t_db": 100.0}, "g_t_db"),
    ],
)
def test_bad_parameters(kwargs, field):
    with pytest.raises(ConfigError) as exc:
        RadarEquation(**kwargs)
    assert exc.value.field == field


def test_bad_ranges():
    eq = RadarEquation()
    for bad in (0.0, -5.0, float("inf")):
        with pytest.raises(ConfigError) as exc:
            eq.snr(np.array([1e3, bad]))
        assert exc.value.field == "range"
    with pytest.raises(ConfigError) as exc:
        eq.energy_snr(1e3, -1.0)
    assert exc.value.field == "duration"
