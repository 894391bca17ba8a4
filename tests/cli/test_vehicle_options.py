"""The vehicle's model options are declared once (cli/vehicle_options.py) and shared by ``simulate`` (the
true vehicle, the paper's values or our assumptions as defaults) and ``detect`` (the model the filters
assume, from the record unless given)."""

import dataclasses
import inspect
import math
import typing

import pytest

from motionsig_cli.cli import detect, simulate
from motionsig_cli.cli.vehicle_options import VEHICLE_OPTIONS, vehicle_options
from motionsig_cli.models.vehicle import Vehicle1D, pole_placement_gain
from motionsig_cli.modesig.vehicle_record import RecordConfig


def _flags(fn) -> dict[str, object]:
    """The command's options: flag -> default, read from the signature typer reads."""
    out = {}
    for p in inspect.signature(fn).parameters.values():
        for meta in typing.get_args(p.annotation)[1:]:
            # typer keeps Option("--flag", ...)'s first declaration in .default, the others in .param_decls
            decls = (getattr(meta, "default", None), *(getattr(meta, "param_decls", None) or ()))
            for decl in decls:
                if isinstance(decl, str) and decl.startswith("--"):
                    out[decl] = p.default
    return out


@pytest.mark.parametrize("command", [simulate.simulate, detect.detect])
def test_both_commands_declare_every_model_option_from_the_one_table(command):
    flags = _flags(command)
    for opt in VEHICLE_OPTIONS:
        assert opt.flag in flags, opt.flag


def test_simulates_defaults_are_the_cores():
    flags = _flags(simulate.simulate)
    truth = Vehicle1D(K=pole_placement_gain(0.05))
    for name in ("T", "a_sig", "a_r", "f_r", "sigma_a"):
        assert flags["--" + name.replace("_", "-")] == getattr(truth, name), name
    sig = inspect.signature(pole_placement_gain).parameters
    assert flags["--pole-wn"] == sig["wn"].default == 4 * math.pi
    assert flags["--pole-zeta"] == sig["zeta"].default
    rec = {f.name: f.default for f in dataclasses.fields(RecordConfig)}
    assert (flags["--fc"], flags["--mrho"], flags["--codes"]) == (rec["f_c"], rec["m_rho"], rec["codes"])


def test_detect_defaults_to_the_record():
    flags = _flags(detect.detect)
    for opt in VEHICLE_OPTIONS:
        assert flags[opt.flag] == opt.detect, opt.flag
        assert opt.detect is None or opt.flag == "--db-convention"


def test_a_group_has_the_fields_before_then_the_table_in_order():
    group = vehicle_options("detect", "G", before=(("columns", typing.Annotated[str | None, "x"], None),))
    names = [f.name for f in dataclasses.fields(group)]
    assert names == ["columns", *(o.name for o in VEHICLE_OPTIONS)]
    assert dataclasses.fields(group)[0].default is None
    with pytest.raises(dataclasses.FrozenInstanceError):
        group().T = 1.0
