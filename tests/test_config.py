"""The core's one error type for bad parameters and its checks."""

import math

import pytest

from motionsig_cli.config import ConfigError, in_range, integer, one_of, positive


def test_config_error_is_a_value_error_naming_field_and_value():
    exc = ConfigError("sigma_r", -1.0, "is not a finite number > 0")
    assert isinstance(exc, ValueError)
    assert str(exc) == "sigma_r = -1 is not a finite number > 0"
    assert exc.detail == "-1 is not a finite number > 0"
    assert (exc.field, exc.value) == ("sigma_r", -1.0)


@pytest.mark.parametrize(
    "kwargs, value, ok",
    [
        ({"lo": 0.0, "hi": 1.0}, 0.0, True),
        ({"lo": 0.0, "hi": 1.0, "lo_open": True}, 0.0, False),
        ({"lo": 0.0, "hi": 1.0, "hi_open": True}, 1.0, False),
        ({"lo": 0.0, "hi": 1.0}, 1.0, True),
        ({"lo": 0.0}, math.inf, False),
        ({"lo": 0.0}, math.nan, False),
        ({}, -1e300, True),
    ],
)
def test_in_range_bounds(kwargs, value, ok):
    if ok:
        assert in_range("x", value, **kwargs) == value
    else:
        with pytest.raises(ConfigError) as exc:
            in_range("x", value, **kwargs)
        assert exc.value.field == "x"


def test_in_range_messages_show_the_interval_and_unit():
    with pytest.raises(ConfigError, match=r"x = 2 is not in \(0, 1\] m"):
        in_range("x", 2.0, 0.0, 1.0, lo_open=True, unit="m")
    with pytest.raises(ConfigError, match=r"is not a finite number > 0"):
        positive("x", 0.0)
    with pytest.raises(ConfigError, match="is not a number"):
        in_range("x", "abc")  # type: ignore[arg-type]


@pytest.mark.parametrize("value", [True, 1.5, "3", -1, 11, math.inf, math.nan])
def test_integer_rejects_non_integers_and_out_of_range(value):
    with pytest.raises(ConfigError):
        integer("n", value, 0, 10)


def test_integer_accepts_integral_floats_and_numpy_integers():
    import numpy as np

    assert integer("n", 3.0, 0, 10) == 3
    assert integer("n", np.int64(7), 0, 10) == 7 and type(integer("n", np.int32(7))) is int
    with pytest.raises(ConfigError):
        integer("n", np.bool_(True))


def test_one_of():
    assert one_of("mode", "lr", ("lr", "log")) == "lr"
    with pytest.raises(ConfigError, match="mode = 'x' is not one of lr, log"):
        one_of("mode", "x", ("lr", "log"))
