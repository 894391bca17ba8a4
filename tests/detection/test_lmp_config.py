"""Every configuration of the LMP detector and its experiments checks its own fields: a bad value of each
checked field raises ConfigError naming that field (the command line maps it to the option), and the
defaults pass. Also the progress callbacks of the filter banks."""

import math

import numpy as np
import pytest

from motionsig_cli.config import ConfigError
from motionsig_cli.detection.lmp import (
    LMPConfig,
    RadarLMPConfig,
    lmp_detect,
    lmp_detect_radar,
    progress_steps,
)
from motionsig_cli.filters.kalman import step_reporter
from motionsig_cli.filters.unscented import SigmaPointParams
from motionsig_cli.models.vehicle import Vehicle1D
from motionsig_cli.models.vehicle2d import Vehicle2D
from motionsig_cli.modesig.lmp1d import CalibrationJob, LmpJob, RecordDetection, table1_chips
from motionsig_cli.modesig.lmp2d import RadarLmpJob, RadarRecordDetection
from motionsig_cli.modesig.record_reading import VehicleRecord

CHIPS = table1_chips()


def _record_1d(n: int = 40) -> VehicleRecord:
    veh = Vehicle1D(R=1e-3)
    return VehicleRecord(np.arange(n) * veh.T, np.zeros(n), veh, CHIPS, 20, 1.0, None, {}, "test")


def _record_2d(n: int = 40) -> VehicleRecord:
    veh = Vehicle2D()
    y = np.stack([np.full(n, 70.0), np.full(n, -0.28)], axis=-1)
    return VehicleRecord(np.arange(n) * veh.T, y, veh, CHIPS, 20, 1.0, None, {}, "test")


CASES = [
    # (factory, bad keyword arguments, field the error names)
    (LMPConfig, dict(c_r=0.0), "c_r"),
    (LMPConfig, dict(c_r=math.inf), "c_r"),
    (LMPConfig, dict(Q0=(1.0, 1.0, 1.0)), "Q0"),
    (LMPConfig, dict(Q0=(1.0, -1.0, 1.0, 1.0)), "Q0"),
    (LMPConfig, dict(Q0=(1.0, math.nan, 1.0, 1.0)), "Q0"),
    (LMPConfig, dict(Q_a=-1.0), "Q_a"),
    (LMPConfig, dict(P0=0.0), "P0"),
    (LMPConfig, dict(A_r="random"), "A_r"),
    (LMPConfig, dict(tau_grid="half-chips"), "tau_grid"),
    (LMPConfig, dict(fc_grid=()), "fc_grid"),
    (LMPConfig, dict(fc_grid=(1.0, -0.5)), "fc_grid"),
    (LMPConfig, dict(include_logdet="yes"), "include_logdet"),
    (LMPConfig, dict(weights="both"), "weights"),
    (LMPConfig, dict(zdot="numeric"), "zdot"),
    (LMPConfig, dict(center="h1"), "center"),
    (LMPConfig, dict(q_model="density"), "q_model"),
    (RadarLMPConfig, dict(c_r=-1.0), "c_r"),
    (RadarLMPConfig, dict(Q0=(1.0,) * 4), "Q0"),
    (RadarLMPConfig, dict(Q1=(1.0,) * 2), "Q1"),
    (RadarLMPConfig, dict(Q1=(-1.0,) * 10), "Q1"),
    (RadarLMPConfig, dict(P0=math.nan), "P0"),
    (RadarLMPConfig, dict(tau_grid="x"), "tau_grid"),
    (RadarLMPConfig, dict(fc_grid=(math.inf,)), "fc_grid"),
    (RadarLMPConfig, dict(include_logdet=2), "include_logdet"),
    (RadarLMPConfig, dict(zdot="x"), "zdot"),
    (RadarLMPConfig, dict(sigma=(1.0, 2.0, 0.0)), "sigma"),
    (RadarLMPConfig, dict(sigma=SigmaPointParams(kappa=-9.0)), "kappa"),  # α²(8 + κ) <= 0
    (RadarLMPConfig, dict(sigma=SigmaPointParams(alpha=1e-8)), "alpha"),  # centre weight ~1e16
    (SigmaPointParams, dict(alpha=0.0), "alpha"),
    (SigmaPointParams, dict(alpha=math.nan), "alpha"),
    (SigmaPointParams, dict(beta=math.inf), "beta"),
    (SigmaPointParams, dict(kappa=math.nan), "kappa"),
    (LmpJob, dict(fr_list=()), "fr_list"),
    (LmpJob, dict(fr_list=(0.01, -1.0)), "fr_list"),
    (LmpJob, dict(R_list=(0.0,)), "R_list"),
    (LmpJob, dict(horizons_s=(0.02,)), "horizons_s"),
    (LmpJob, dict(horizons_s=(-1.0,)), "horizons_s"),
    (LmpJob, dict(horizons_s=()), "horizons_s"),
    (LmpJob, dict(trials=0), "trials"),
    (LmpJob, dict(trials=2.5), "trials"),
    (LmpJob, dict(trials=60_000_000, R_list=(1.0, 2.0)), "trials"),
    (LmpJob, dict(seed=-1), "seed"),
    (LmpJob, dict(signature="no"), "signature"),
    (LmpJob, dict(method="gpu"), "method"),
    (LmpJob, dict(method="fft"), "method"),  # the default Q_a = 1: the FFT path needs 0
    (LmpJob, dict(codes="bent"), "codes"),
    (LmpJob, dict(m_rho=0), "m_rho"),
    (LmpJob, dict(f_c=-1.0), "f_c"),
    (LmpJob, dict(chunk=0), "chunk"),
    (CalibrationJob, dict(pfa=0.0), "pfa"),
    (CalibrationJob, dict(pfa=1.0), "pfa"),
    (CalibrationJob, dict(pfa=1e-9), "pfa"),  # 20/pfa default null trials: too many
    (CalibrationJob, dict(null_trials=0), "null_trials"),
    (CalibrationJob, dict(null_trials=3_000_000), "null_trials"),
    (CalibrationJob, dict(trials=0), "trials"),
    (CalibrationJob, dict(trials=3_000_000), "trials"),
    (CalibrationJob, dict(R_list=(-1.0,)), "R_list"),
    (CalibrationJob, dict(horizons_s=(0.0,)), "horizons_s"),
    (CalibrationJob, dict(method="fft"), "method"),
    (RadarLmpJob, dict(fr_list=(2e6,)), "fr_list"),
    (RadarLmpJob, dict(fr_list=(-1.0,)), "fr_list"),
    (RadarLmpJob, dict(anr_pairs=(5,)), "anr_pairs"),
    (RadarLmpJob, dict(anr_pairs=()), "anr_pairs"),
    (RadarLmpJob, dict(horizons_s=(2e6,)), "horizons_s"),
    (RadarLmpJob, dict(horizons_s=(0.01,)), "horizons_s"),
    (RadarLmpJob, dict(trials=0), "trials"),
    (RadarLmpJob, dict(trials=1, horizons_s=(500_000.0,)), "trials"),  # ~4.5 GB of replicas
    (RadarLmpJob, dict(seed=-3), "seed"),
    (RadarLmpJob, dict(signature=None), "signature"),
    (RadarLmpJob, dict(codes="x"), "codes"),
    (RadarLmpJob, dict(m_rho=0), "m_rho"),
    (RadarLmpJob, dict(chunk=-1), "chunk"),
]


def _record_detection(**kw):
    return RecordDetection(_record_1d(), kw.pop("cfg", LMPConfig()), **kw)


def _radar_record_detection(**kw):
    return RadarRecordDetection(_record_2d(), kw.pop("cfg", RadarLMPConfig()), **kw)


RECORD_CASES = [
    (_record_detection, dict(filter="ekf"), "filter"),
    (_record_detection, dict(method="gpu"), "method"),
    (_record_detection, dict(method="fft", cfg=LMPConfig(Q_a=0.0), filter="ukf"), "method"),
    (_record_detection, dict(method="fft", cfg=LMPConfig(Q_a=0.0, center="h0-noise")), "method"),
    (_record_detection, dict(filter="ukf", cfg=LMPConfig(weights="exact")), "filter"),
    (_record_detection, dict(filter="ukf", sigma=SigmaPointParams(kappa=-4.5)), "kappa"),  # α²(4 + κ) < 0
    (_record_detection, dict(horizons=(3.0,)), "horizons"),  # the record is 2 s long
    (_record_detection, dict(horizons=(0.0,)), "horizons"),
    (_record_detection, dict(horizons=(0.01,)), "horizons"),
    (_record_detection, dict(threshold=math.nan), "threshold"),
    (
        _record_detection,  # 2 × 1 488 000 + 1 filters over 40 samples: ~6.7 GB of gains (limit 4 GB)
        dict(cfg=LMPConfig(tau_grid="samples", fc_grid=tuple(np.linspace(0.5, 1.5, 800)))),
        "horizons",
    ),
    (_radar_record_detection, dict(horizons=(0.0,)), "horizons"),
    (_radar_record_detection, dict(horizons=(2.5,)), "horizons"),
    (_radar_record_detection, dict(threshold="high"), "threshold"),
    (
        _radar_record_detection,
        dict(cfg=RadarLMPConfig(tau_grid="samples", fc_grid=tuple(np.linspace(0.5, 1.5, 800)))),  # ~5.7 GB
        "horizons",
    ),
]


@pytest.mark.parametrize(
    ("factory", "kwargs", "field"),
    CASES + RECORD_CASES,
    ids=[f"{getattr(f, '__name__', f)}-{field}-{i}" for i, (f, _, field) in enumerate(CASES + RECORD_CASES)],
)
def test_a_bad_value_is_a_config_error_naming_its_field(factory, kwargs, field):
    with pytest.raises(ConfigError) as info:
        factory(**kwargs)
    assert info.value.field == field, info.value


@pytest.mark.parametrize(
    "factory",
    [LMPConfig, RadarLMPConfig, SigmaPointParams, LmpJob, CalibrationJob, RadarLmpJob, _record_detection,
     _radar_record_detection],
)  # fmt: skip
def test_the_defaults_pass(factory):
    factory()


def test_every_checked_field_of_the_detector_configs_has_a_case():
    """The field lists above cover every field of the two detector configurations and the jobs' own."""
    named = {(f, field) for f, _, field in CASES}
    for cls in (LMPConfig, RadarLMPConfig):
        assert {name for name in cls.__dataclass_fields__ if (cls, name) not in named} == set(), cls
    job_fields = {"fr_list", "R_list", "horizons_s", "trials", "seed", "signature", "method", "codes", "m_rho",
                  "f_c", "chunk"}  # fmt: skip
    assert job_fields <= {field for f, _, field in CASES if f is LmpJob}


def test_chunk_size_does_not_change_the_monte_carlo_and_lists_become_tuples():
    job = LmpJob(fr_list=[0.01], R_list=[1e-3], horizons_s=[2.0], trials=3, seed=4, chunk=3)
    assert job.fr_list == (0.01,) and job.horizons_s == (2.0,)
    from motionsig_cli.engine import run_job

    a = run_job(job).cells
    b = run_job(LmpJob(fr_list=(0.01,), R_list=(1e-3,), horizons_s=(2.0,), trials=3, seed=4, chunk=1)).cells
    assert a == b


def test_step_reporter_reports_every_step_once_per_block():
    got = []
    tick = step_reporter(got.append, 150, block=64)
    for k in range(150):
        tick(k)
    assert got == [64, 64, 22]
    step_reporter(None, 10)(3)  # no callback: nothing happens


@pytest.mark.parametrize(
    ("cfg", "filter"), [(LMPConfig(), "kf"), (LMPConfig(center="h0-noise"), "kf"), (LMPConfig(), "ukf")]
)
def test_the_banks_report_progress_steps(cfg, filter):
    rec = _record_1d(70)
    got = []
    lmp_detect(rec.y, CHIPS, rec.vehicle, 20, cfg, [70], filter=filter, progress=got.append)
    assert sum(got) == progress_steps(70, cfg, filter) and max(got) <= 64


def test_the_radar_bank_reports_its_time_steps():
    rec = _record_2d(70)
    got = []
    lmp_detect_radar(rec.y, CHIPS, rec.vehicle, 20, RadarLMPConfig(), [70], progress=got.append)
    assert sum(got) == 70 == progress_steps(70, RadarLMPConfig())
