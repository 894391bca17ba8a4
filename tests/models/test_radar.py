"""The sensor and motion models of the track-existence scenario: the checks of their parameters."""

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.models.radar import MEASUREMENT_KINDS, MeasurementModel, cv_model

R_OK = np.diag([50.0**2, 1e-6])


@pytest.mark.parametrize("kind", MEASUREMENT_KINDS)
def test_every_kind_builds(kind):
    m = MeasurementModel(kind, R_OK)
    assert m.angular == (1 if kind == "range_bearing" else None) and m.fov_volume > 0


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"kind": "polar"}, "kind"),
        ({"R": np.eye(3)}, "R"),
        ({"R": np.array([[1.0, 0.5], [0.0, 1.0]])}, "R"),  # not symmetric
        ({"R": np.diag([1.0, 0.0])}, "R"),  # singular
        ({"R": np.diag([1.0, np.nan])}, "R"),
        ({"fov_range": 0.0}, "fov_range"),
        ({"fov_range": float("inf")}, "fov_range"),
    ],
)
def test_measurement_model_checks(kwargs, field):
    args = {"kind": "range_bearing", "R": R_OK, **kwargs}
    with pytest.raises(ConfigError) as exc:
        MeasurementModel(**args)
    assert exc.value.field == field


def test_cv_model_blocks():
    F, Q = cv_model(2.0, 10.0)
    assert np.array_equal(F[:2, :2], [[1.0, 2.0], [0.0, 1.0]]) and np.array_equal(F[2:, 2:], F[:2, :2])
    np.testing.assert_allclose(Q[:2, :2], 10.0 * np.array([[8 / 3, 2.0], [2.0, 2.0]]))
    assert not F[:2, 2:].any() and not Q[:2, 2:].any()


@pytest.mark.parametrize(
    ("args", "field"), [((0.0, 1.0), "T"), ((float("nan"), 1.0), "T"), ((1.0, -1.0), "q")]
)
def test_cv_model_checks(args, field):
    with pytest.raises(ConfigError) as exc:
        cv_model(*args)
    assert exc.value.field == field
