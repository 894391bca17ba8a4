# %% [markdown]
# # The EBPSK radar–communication front end
#
# Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System*, put their trackers behind
# an EBPSK joint radar–communication (JRC) front end: EBPSK pulses carry the communication payload, the echoes
# are detected after the EBPSK "impacting filter" by an amplitude threshold with CFAR, and a weighted least
# squares location turns range and bearing into the positions the trackers see (§I, Fig. 1, Table I). The paper
# then simulates the trackers on positions with a fixed σ = 100 or 200 m per axis and never uses the front end.
#
# This page builds the front end step by step — the waveform, the impacting filter, the CA-CFAR detector, the
# Cramér–Rao bound of the range, the location step — each followed by a numerical check, then runs the four
# trackers (IMM, GLR, MLR and the constant-velocity Kalman filter) on the front end's measurements along the
# paper's trajectory: with a covariance R(k) that changes from scan to scan and with missed detections.
# Everything the paper does not state is assumed and said so: the radar's position (150 km, 150 km), its power
# budget (10 kW, 38 dBi, 1 m², 6 dB losses, 3 dB noise figure), the 16-bit payload per pulse, P_FA = 10⁻⁶, a
# monopulse bearing with a 2° beam.

# %%
import math

import numpy as np
from IPython.display import Markdown

from motionsig_cli.detection.cfar import CFARConfig, ca_cfar, ca_cfar_alpha
from motionsig_cli.engine import run_job
from motionsig_cli.maneuver import ebpsk_tracking as et
from motionsig_cli.maneuver import study as mv
from motionsig_cli.maneuver.ebpsk_radar import EbpskRadarConfig, EbpskRadarJob, locate
from motionsig_cli.plotting import ebpsk_front_end_figure
from motionsig_cli.signals.ebpsk import (
    EBPSKConfig,
    filter_response,
    impact_ratio,
    modulate,
    signal_correlation,
)


def md_table(header, rows):
    """A Markdown table from a header and rows of formatted cells."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return Markdown("\n".join(lines))


# %% [markdown]
# ## 1. The waveform
#
# A symbol is N = 7 cycles of the 100 MHz IF, sampled at 1 GHz (70 samples). Bit 0 is sin(2π f t) throughout;
# bit 1 reverses the phase (θ = π) of its first K = 2 cycles. Check: the first 20 samples of a bit-1 symbol are
# those of a bit-0 symbol negated, the other 50 are equal.

# %%
wave = EBPSKConfig()
x = np.asarray(modulate(np.array([0, 1]), wave), float).reshape(-1)
s0, s1 = x[:70], x[70:140]
assert x.size == 140
assert np.allclose(s1[:20], -s0[:20]) and np.allclose(s1[20:], s0[20:])
rho = signal_correlation(wave)
print(f"samples per symbol 70; correlation of the two symbols ρ = {rho:.4f} (1 − 2K/N = {1 - 4 / 7:.4f})")
assert abs(rho - (1 - 2 * 2 / 7)) < 1e-9

# %% [markdown]
# ## 2. The impacting filter
#
# A zero pair on the unit circle at the IF and pole pairs beside it: an unmodulated carrier is notched out,
# the phase jump of a bit-1 symbol rings the poles — the "impact". Check: |H(f_if)| is the minimum of the
# response near the IF, and the impact of a bit 1 dominates the residue of a bit 0.

# %%
f, h = filter_response(wave)
near = (f > 50e6) & (f < 150e6)
i_min = int(np.argmin(np.abs(h[near])))
print(
    f"|H| minimum at {f[near][i_min] / 1e6:.2f} MHz; impact ratio (bit 1 / bit 0 peak) {impact_ratio(wave):.3g}"
)
assert abs(f[near][i_min] - wave.f_if) <= 1e6
assert impact_ratio(wave) > 10

# %% [markdown]
# ## 3. The detector: CA-CFAR
#
# Square-law cell averaging: declare when |u|² > α · mean of N_t training cells, α = N_t (P_FA^(−1/N_t) − 1)
# (the moment-generating function of the gamma-distributed training sum). Check on complex Gaussian noise:
# the measured P_FA is within 4 SE of the nominal one.

# %%
cfar = CFARConfig(n_train=32, n_guard=2, pfa=1e-3)
rng = np.random.default_rng(20150624)
noise = rng.standard_normal((200, 4096)) + 1j * rng.standard_normal((200, 4096))
det, _ = ca_cfar(np.abs(noise) ** 2, cfar)
valid = det[:, cfar.half_width : -cfar.half_width]
pfa_hat, n_cells = valid.mean(), valid.size
se = math.sqrt(1e-3 * (1 - 1e-3) / n_cells)
print(f"α = {ca_cfar_alpha(1e-3, 32):.3f}; P_FA measured {pfa_hat:.2e} ± {se:.1e} (nominal 1e-3)")
assert abs(pfa_hat - 1e-3) < 4 * se

# %% [markdown]
# ## 4. Range accuracy and the Cramér–Rao bound
#
# The range is read from the impact peak of the filter output (parabolic interpolation). The bound for a delay
# with an unknown carrier phase is var(τ̂) ≥ 1/(8π² β² E/N₀), β the RMS bandwidth of the received pulse about
# its mean frequency (processing cannot add information, so the bound is on the received samples). Check, from
# the sample-level chain: P_D rises with E/N₀ and the RMS range error is never below the bound (beyond 4 SE).

# %%
radar_cfg = EbpskRadarConfig()
res = run_job(EbpskRadarJob(radar_cfg, (14.0, 18.0, 22.0, 30.0), 300, 7))
rows = []
for i, e in enumerate(res.enr_db):
    rows.append((f"{e:g}", f"{res.pd[i]:.3f} ± {res.pd_se[i]:.3f}", f"{res.pd_model[i]:.3f}",
                 f"{res.rms_r[i]:.3f}", f"{res.crlb_r[i]:.3f}"))  # fmt: skip
    if res.pd[i] > 0.2:
        assert res.rms_r[i] + 4 * res.rms_r_se[i] >= res.crlb_r[i]
assert np.all(np.diff(res.pd) >= -4 * np.hypot(res.pd_se[1:], res.pd_se[:-1]))
md_table(("E/N₀ [dB]", "P_D (samples)", "P_D (model)", "RMS range error [m]", "√CRLB [m]"), rows)

# %% [markdown]
# ## 5. Location
#
# One radar measures range r and bearing φ; the position is s + r (cos φ, sin φ) with the covariance
# J diag(σ_r², σ_φ²) Jᵀ, plus the conversion's second-order term ¾ r² σ_φ⁴ along the line of sight. Check by
# Monte Carlo at 200 km, σ_r = 0.3 m, σ_φ = 1.5 mrad: the whitened position errors have unit covariance.

# %%
fe0 = et.EbpskFrontEnd()
n = 20000
r_true, phi_true = 200e3, 0.7
g = np.random.default_rng(3)
r_m = r_true + 0.3 * g.standard_normal(n)
phi_m = phi_true + 1.5e-3 * g.standard_normal(n)
xy, cov = locate(r_m[:, None], phi_m[:, None], np.array([0.3, 1.5e-3]), np.zeros((1, 2)))
u = np.stack([np.cos(phi_m), np.sin(phi_m)], -1)
cov = cov + (0.75 * r_m**2 * 1.5e-3**4)[:, None, None] * u[:, :, None] * u[:, None, :]
e = xy - r_true * np.array([math.cos(phi_true), math.sin(phi_true)])
w = np.linalg.solve(np.linalg.cholesky(cov), e[..., None])[..., 0]
C = w.T @ w / n
print(
    "whitened error covariance", np.round(C, 3), "; cross-range σ", round(r_true * 1.5e-3), "m, range σ 0.3 m"
)
assert np.allclose(C, np.eye(2), atol=4 * math.sqrt(2 / n))

# %% [markdown]
# ## 6. The front end along the paper's trajectory
#
# The paper's (literal) trajectory runs 737 km; from a radar at (150 km, 150 km) the range runs from 92 km to
# 530 km, so E/N₀ changes by 30 dB (r⁻⁴) and the position σ — dominated by the cross-range r σ_φ ∝ r/√(E/N₀) ∝
# r³ — by a factor of 200. The table gives, per phase, what the front end delivers at the transmit power that
# makes the median σ along the track 100 m, and the power (and E/N₀) at which the phase's RMS σ would be the
# paper's 100 or 200 m. Check: P_D < 1 at the far end (missed scans), ≈ 1 in the cruise.

# %%
sc = mv.ManeuverScenario("literal")
fe = et.EbpskFrontEnd().prepared(sc.truth())
fe100 = fe.calibrated(sc.truth(), 100.0)
tab = et.front_end_table(sc, fe100)
c = tab.columns
rows = [(r[0], f"{r[3]:.0f}–{r[4]:.0f}", f"{r[5]:.1f}", f"{r[6]:.3f}", f"{r[7]:.2f}", f"{r[8]:.2f}",
         f"{r[10]:.0f}", f"{r[c.index('p_t_W_for_100')]:.2e}", f"{r[c.index('enr_db_for_100')]:.1f}",
         f"{r[c.index('p_t_W_for_200')]:.2e}") for r in tab.rows]  # fmt: skip
assert tab.rows[0][6] > 0.99 and tab.rows[3][6] < 0.9
md_table(("phase", "range [km]", "E/N₀ [dB]", "P_D", "σ_r [m]", "σ_φ [mrad]", "σ_pos [m]", "P_t for 100 m [W]",
          "E/N₀ for 100 m", "P_t for 200 m [W]"), rows)  # fmt: skip

# %%
ebpsk_front_end_figure(**et.front_end_figure_data(sc, fe100, (100.0, 200.0)))

# %% [markdown]
# ## 7. The trackers on the front end
#
# The same four trackers as on the maneuver page, now with the front end's R(k) in every Kalman update and
# predict-only steps at the missed scans (the first two scans initiate the track and are taken as detected).
# 60 runs per σ here (the command runs any number: 500 runs take about half a minute). Check: at every σ and in
# the cruise the IMM's RMS error is below the front end's median σ (the filter averages scans).

# %%
src = et.EbpskPositions(fe, calibrate=True)
job = mv.ManeuverJob(sc, (100.0, 200.0), 60, 2008, mv.METHODS, mv.TrackerConfig(), source=src, quiet_fp=True)
results = run_job(job)
rep = mv.report(mv.ManeuverStudy(job, "summary"), results)
cols = rep.table.columns
rows = [(f"{r[0]:g}", r[1], *(f"{v:.0f}" for v in r[2:6]), "" if r[cols.index("detected_200")] is None
         else f"{r[cols.index('detected_200')]:.2f}") for r in rep.table.rows]  # fmt: skip
for r in rep.table.rows:
    if r[1] == "imm":
        assert r[2] < r[0]
md_table(("σ [m]", "method", "RMS cruise", "RMS turn 1", "RMS turn 2", "RMS after", "turn 1 detected"), rows)

# %% [markdown]
# Where P_D ≈ 1 (the cruise and the turns, 92–212 km) the trackers behave as on the maneuver page: the GLR and
# MLR follow both turns, the IMM lags in the sharp first turn. In the last phase P_D falls towards 0 and every
# tracker coasts on predictions for tens of scans: the IMM and the CV filter drift by hundreds of metres to
# kilometres, and a GLR or MLR declaration there — an input estimate from one or two far, noisy detections — is
# carried forward by the continuation, so their RMS error in that phase grows to kilometres (in a 500-run
# Monte Carlo a few runs end thousands of kilometres away). A constant σ, as in the paper, hides both effects.

# %% [markdown]
# ## Errata and inconsistencies
#
# * **σ = 100 and 200 m "standard deviation of the noise"** cannot come from this waveform's range measurement:
#   at 1 GHz sampling the impact peak gives σ_r ≈ 0.2–0.4 m at any E/N₀ where P_D is useful (section 4). A
#   position σ of 100 m is cross-range (r σ_φ), and the error ellipse is then hundreds of times longer than wide —
#   not the isotropic σ per axis of the paper's simulation.
# * **A constant σ along the track** contradicts the radar equation: σ_pos ∝ r³ at a fixed power, a factor of
#   200 along the literal track from any single radar (section 6).
# * **Table I leaves the scanning period blank**; T = 1 s is assumed (as on the maneuver page).
# * **The power budget**: with the assumed 10 kW and a 1.12 µs pulse the radar sees nothing beyond ~30 km; the
#   100 m of the paper needs E/N₀ of 24–37 dB per scan along this track, i.e. P_t of 10⁸–10¹¹ W for a single
#   pulse — or the equivalent energy by coherent integration of many pulses (`--n-pulses`) or a longer payload.
# * **The literal trajectory** (u = 20 m/s² for 100 scans) reaches 3.2 km/s and 737 km from its start: not the
#   "90-degree sharp turn" of the text (the `turn90` preset is). The unambiguous range c·PRI/2 must cover it
#   (PRI 5 ms assumed: 749 km).
#
# Reproduce:
#
# ```
# motionsig maneuver --front-end ebpsk --view front-end --plot front_end.png
# motionsig maneuver --front-end ebpsk --method all --view summary --runs 500
# motionsig maneuver --front-end ebpsk --level samples --runs 2 --method imm
# ```
