"""The jam-bound configurations and core functions check every parameter: a bad value is a ConfigError
naming the field (or argument) that holds it, whatever the entry point."""

import math

import pytest

from motionsig_cli.atc10 import jamming as exp
from motionsig_cli.config import ConfigError
from motionsig_cli.surveillance.antenna import DishAntenna, jammer_antenna
from motionsig_cli.surveillance.jamming import (
    JammingDesign,
    JammingSystem,
    check_level,
    log_bound_pf,
    p_d_for,
    required_jamming,
    t_for,
)


def field_of(fn, *args, **kwargs) -> str:
    with pytest.raises(ConfigError) as info:
        fn(*args, **kwargs)
    return info.value.field


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("bandwidth_hz", {"bandwidth_hz": 0.0}),
        ("bandwidth_hz", {"bandwidth_hz": math.inf}),
        ("alpha_s", {"alpha_s": -1.0}),
        ("beta_s", {"beta_s": math.nan}),
        ("vmax_mph", {"vmax_mph": 0.0}),
        ("vmax_mph", {"vmax_mph": 1e10}),  # faster than light
        ("c_mph", {"c_mph": 0.0}),
        ("energy_j", {"energy_j": 0.0}),
        ("airborne_frac", {"airborne_frac": 0.0}),
        ("airborne_frac", {"airborne_frac": 1.0}),
        ("flight_factor", {"flight_factor": 0.0}),
        ("flight_factor", {"flight_factor": 1.5}),
        ("pick_factor", {"pick_factor": 0.0}),
        ("pick_factor", {"pick_factor": 1.01}),
        ("satellites", {"satellites": 0}),
        ("satellites", {"satellites": 2.5}),
        ("pf_form", {"pf_form": "corrected"}),  # the CLI's name, not the field's value
        ("n_alpha", {"bandwidth_hz": 1e308}),  # 2Bα overflows
        ("n_beta", {"beta_s": 1e305}),  # 4Bβ overflows
        ("n_v", {"vmax_mph": 5e-324}),  # (8B/3)vα/c underflows to 0
    ],
)
def test_system_rejects_each_field(field, kwargs):
    assert field_of(JammingSystem, **kwargs) == field


@pytest.mark.parametrize(
    ("field", "args"),
    [
        ("K", (0, 0.9, 0.0)),
        ("K", (2.5, 0.9, 0.0)),
        ("t", (10, 0.9, 1.0)),
        ("t", (10, 0.9, -0.1)),
        ("t", (1, 0.9, 0.1)),  # K = 1 allows only t = 0
        ("p_d", (10, 0.0, 0.0)),
        ("p_d", (10, 1.0, 0.0)),
        ("p_d", (10, 1e-300, 0.0)),  # q = p_d^4 underflows
        ("satellites", (10, 0.9, 0.0, 0)),
    ],
)
def test_design_rejects_each_field(field, args):
    assert field_of(JammingDesign, *args) == field


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("freq_hz", {"freq_hz": 0.0}),
        ("freq_hz", {"freq_hz": 1e-300}),  # infinite wavelength
        ("efficiency", {"efficiency": 0.0}),
        ("efficiency", {"efficiency": 1.5}),
        ("beamwidth_const_deg", {"beamwidth_const_deg": 0.0}),
        ("beamwidth_const_deg", {"beamwidth_const_deg": math.nan}),
    ],
)
def test_dish_rejects_each_field(field, kwargs):
    assert field_of(DishAntenna, **kwargs) == field


@pytest.mark.parametrize(
    ("field", "call"),
    [
        ("pdl", lambda: p_d_for(10, 0.0)),
        ("pdl", lambda: p_d_for(10, 1.0)),
        ("pdl", lambda: p_d_for(10**29, 0.9, 0.3)),  # not representable in double precision
        ("K", lambda: p_d_for(0, 0.9)),
        ("pdl", lambda: t_for(1, 0.99, 0.5)),
        ("p_d", lambda: t_for(10, 0.0, 0.5)),
        ("pdl", lambda: t_for(10, 0.3, 0.999)),  # infeasible even at t = 0
        ("level", lambda: check_level("nadl", 0.0, JammingSystem())),
        ("level", lambda: check_level("nadl", 1.5, JammingSystem())),
        ("level", lambda: check_level("nfl", 0.9, JammingSystem())),  # the N̄_FL supremum itself
        ("level", lambda: required_jamming("nadl", math.nan, JammingDesign(10, 0.9), JammingSystem())),
        ("quantity", lambda: log_bound_pf("both", -1.0, JammingDesign(10, 0.9), JammingSystem())),
        ("erp_dbw", lambda: jammer_antenna(math.inf, rf_dbw=10.0)),
        ("rf_dbw", lambda: jammer_antenna(33.0, rf_dbw=math.nan)),
        ("rf_dbw", lambda: jammer_antenna(33.0)),
        ("rf_dbw", lambda: jammer_antenna(33.0, rf_dbw=40.0)),  # no dish: rf power above the ERP
        ("diameter_m", lambda: jammer_antenna(33.0, diameter_m=0.0)),
        ("diameter_m", lambda: jammer_antenna(33.0, rf_dbw=10.0, diameter_m=1.0)),
        ("x_min", lambda: exp.x_grid(-2000.0, 0.0, 1.0)),
        ("x_max", lambda: exp.x_grid(0.0, math.inf, 1.0)),
        ("x_max", lambda: exp.x_grid(5.0, 0.0, 1.0)),
        ("step", lambda: exp.x_grid(0.0, 1.0, 0.0)),
        ("step", lambda: exp.x_grid(0.0, 1.0, 1e-3, max_points=10)),
        ("figure", lambda: exp.parse_figure("2.17")),
    ],
)
def test_core_functions_name_the_argument(field, call):
    assert field_of(call) == field


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("figure", {"figure": "3.1"}),
        ("quantity", {"quantity": "nfl,nadl"}),
        ("K", {"figure": "2.4", "K": 100}),
        ("quantity", {"figure": "2.4", "quantity": "nfl"}),
        ("K", {"K": 0}),
        ("pdl", {"pdl": (1.5,)}),
        ("p_d", {"pd": (0.0,)}),
        ("t", {"t": (1.0,)}),
        ("t", {"K": 1, "t": (0.1,)}),
        ("pd", {"pd": (0.9,), "pdl": (0.9,)}),
        ("t", {"pd": (0.3,), "t": (0.5,)}),  # t ≥ q = 0.0081: P_DL = 0
        ("x_min", {"x_min": -2000.0}),
        ("x_max", {"x_min": 5.0, "x_max": 0.0}),
        ("step", {"step": 0.0}),
        ("step", {"K": 1000, "x_min": -20.0, "x_max": 80.0, "step": 2e-4}),  # too many rows
    ],
)
def test_curves_config_rejects_each_field(field, kwargs):
    assert field_of(exp.CurvesConfig, **kwargs) == field


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("quantity", {"quantity": "both"}),
        ("level", {"level": 0.0}),
        ("level", {"quantity": "nfl", "level": 0.9}),
        ("K", {"K": 0}),
        ("pdl", {"pdl": (0.0,)}),
        ("p_d", {"pd": (1.0,)}),
        ("t", {"t": (1.0,)}),
        ("pd", {"pd": (0.9,), "pdl": (0.9,)}),
    ],
)
def test_threshold_config_rejects_each_field(field, kwargs):
    assert field_of(exp.ThresholdConfig, **kwargs) == field


@pytest.mark.parametrize(("field", "kwargs"), [("which", {"which": "3.1"}), ("level", {"level": 2.0})])
def test_table_config_rejects_each_field(field, kwargs):
    assert field_of(exp.TableConfig, **kwargs) == field


def test_table_1_1_names_the_dish_that_cannot_build_a_row():
    config = exp.TableConfig("1.1", antenna=DishAntenna(freq_hz=1e3))  # a 2 ft dish at 1 kHz: no dish
    with pytest.raises(ConfigError, match="fails on the K = 1 row") as info:
        exp.report_table(config)
    assert info.value.field == "antenna"


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("pdl", {}),
        ("t", {"pdl": 0.9, "pd": 0.9, "t": 0.1}),
        ("K", {"K": 0, "pdl": 0.9}),
        ("pdl", {"K": 1, "pdl": 0.5, "pd": 0.99}),
        ("p_d", {"pd": 0.0}),
        ("pdl", {"pdl": 1.5}),
        ("t", {"pdl": 0.9, "t": 1.0}),
    ],
)
def test_design_table_rejects_each_argument(field, kwargs):
    assert field_of(exp.design_table, **({"K": 10} | kwargs)) == field


@pytest.mark.parametrize(
    ("field", "kwargs"),
    [
        ("rf_dbw", {}),
        ("diameter_ft", {"rf_w": 30.0, "diameter_ft": 2.0}),
        ("rf_w", {"rf_w": 0.0}),
        ("diameter_ft", {"diameter_ft": -2.0}),
        ("rf_w", {"rf_w": 1e5}),  # 50 dBW above a 33 dBW ERP: the chain's error names the option given
        ("diameter_ft", {"diameter_ft": 1e-3}),  # smaller than a wavelength
        ("rf_dbw", {"rf_dbw": math.inf}),
        ("erp_dbw", {"erp_dbw": math.inf, "rf_w": 30.0}),
    ],
)
def test_antenna_table_rejects_each_argument(field, kwargs):
    assert field_of(exp.antenna_table, **({"erp_dbw": 33.0} | kwargs)) == field


@pytest.mark.parametrize("name", list(exp.FIGURES))
def test_every_figure_preset_gives_its_curves(name):
    preset = exp.FIGURES[name]
    result = exp.curves_table(exp.CurvesConfig(figure=f"Fig. {name}", step=1.0))
    t = result.table
    col = {c: [r[i] for r in t.rows] for i, c in enumerate(t.columns)}
    assert set(col["figure"]) == {name} and set(col["quantity"]) == {preset.quantity}
    assert (
        set(col["K"]) == {preset.K} and set(col["P_DL"]) == set(preset.pdl) and set(col["t"]) == set(preset.t)
    )
    assert (min(col["x_db"]), max(col["x_db"])) == preset.x_range
    assert len(t.rows) == len(preset.pdl) * len(preset.t) * (round(preset.x_range[1] - preset.x_range[0]) + 1)
    assert t.meta["figure"] == name and result.title == f"Fig. {name} K = {preset.K}"
    assert len(result.panels) == 1 and len(result.panels[0][1]) == len(preset.pdl) * len(preset.t)
