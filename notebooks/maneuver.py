# %% [markdown]
# # Maneuvering targets: GLR, MLR and the IMM
#
# The paper of Yao, Teng & Wu, *Maneuvering Target Tracking Based on EBPSK Modulated JRC System* (an
# EBPSK joint radar–communication system), tracks a target that turns twice, from position measurements. It describes two maneuver detectors that estimate the unknown
# acceleration, the generalised likelihood ratio (GLR) and the marginalised likelihood ratio (MLR), but
# evaluates only an interacting multiple model (IMM) filter of three Kalman filters (Figs 2–4). This page
# derives the GLR and MLR statistics from the innovations of one Kalman filter, then the IMM cycle with the
# printed formulas corrected. Each step is checked numerically with `motionsig_cli`. The page
# then regenerates Figs 2–4 with the model probabilities, and finally does what the paper does not: it runs the
# IMM, GLR, MLR and a plain constant-velocity Kalman filter on the same Monte Carlo runs.
#
# The radar parameters (10 GHz carrier, EBPSK modulation) do not enter the trackers. The measurements are
# positions with i.i.d. Gaussian errors of standard deviation σ per axis. The paper leaves the scan period blank;
# T = 1 s is assumed. The Monte Carlo figures use 100 runs per σ (the paper: 500) while the site
# builds; the commands at the end run any number.

# %%
# fold: Setup: imports and helper functions
import math

import numpy as np
from IPython.display import Markdown
from matplotlib.figure import Figure
from scipy import integrate, stats

from motionsig_cli.detection.glr import CHI2_2_999, GLRConfig, InputModel, input_tracker
from motionsig_cli.filters.imm import imm_filter
from motionsig_cli.maneuver import study as mv
from motionsig_cli.models.motion import H_POS4, H_POS6, ModelSet, cv_input_model, imm_models, two_point_init
from motionsig_cli.plotting import maneuver_comparison_figure, maneuver_figure
from motionsig_cli.rng import trial_rng


def md_table(header, rows):
    """A Markdown table from a header and rows of formatted cells."""
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return Markdown("\n".join(lines))


def kf_run(z, F, Q, H, R, x0, P0, G=None, u=None, onset=0):
    """A plain Kalman filter for the checks, started from the *updated* (x0, P0) of the scan before z[0]:
    predict, then update with z[j]. A known input u enters every prediction into a scan j > onset (the input
    u_{j−1} acts from onset on). Returns the per-scan updated x, innovation ν, S, gain K and log N(ν; 0, S)."""
    x, P = np.array(x0, float), np.array(P0, float)
    out = {"x": [], "nu": [], "S": [], "K": [], "ll": []}
    for j, zj in enumerate(z):
        x = F @ x + (G @ u if u is not None and j > onset else 0.0)
        P = F @ P @ F.T + Q
        S = H @ P @ H.T + R
        K = P @ H.T @ np.linalg.inv(S)
        nu = zj - H @ x
        ll = -0.5 * (nu @ np.linalg.solve(S, nu) + np.linalg.slogdet(2 * np.pi * S)[1])
        x = x + K @ nu
        A = np.eye(len(x)) - K @ H
        P = A @ P @ A.T + K @ R @ K.T
        for key, v in zip(("x", "nu", "S", "K", "ll"), (x, nu, S, K, ll), strict=True):
            out[key].append(v)
    return {key: np.array(v) for key, v in out.items()}


def sl(a, b):
    """Index range of scans a..b (inclusive) in the per-scan arrays (first entry: scan 3)."""
    return slice(a - 3, b - 2)


SEED, RUNS = 2016, 100
CFG = mv.TrackerConfig()
SC = {p: mv.ManeuverScenario(preset=p) for p in mv.PRESETS}

# %% [markdown]
# ## 1. The problem, the two hypotheses and the scenario
#
# The target state is $x = [x, \dot x, y, \dot y]^\top$. It moves at nearly constant velocity, driven by a
# piecewise-constant acceleration input $u = [u_x, u_y]^\top$, and a radar measures its position every $T$
# seconds:
#
# $$ x_{k+1} = F x_k + G u_k + w_k,\qquad z_k = H x_k + v_k,\qquad
#    F = \begin{bmatrix}1 & T\\ 0 & 1\end{bmatrix}^{\oplus 2},\quad
#    G = \begin{bmatrix}T^2/2 & T\end{bmatrix}^{\top\,\oplus 2},\quad v_k \sim \mathcal N(0, \sigma^2 I_2). $$
#
# Here $w_k$ is continuous white-noise acceleration of spectral density $\tilde q_0$ (default 1 m²/s³, an
# assumption; the paper's non-maneuvering model has none). A maneuver is a jump of the input. Over the
# window of the last $s$ scans the paper tests
#
# $$ H_0:\ u_j = 0 \ \text{ for all } j \in [k-s, k], \qquad
#    H_1(u, n):\ u_n = u_{n+1} = \dots = u_{k-1} = u \neq 0 \ \text{ for some onset } n \in [k-s, k-1], \tag{1}$$
#
# with the level $u$ and the onset $n$ unknown. An input $u_n$ first moves the position of scan $n+1$.
#
# **The scenario cannot be reproduced as printed.** The target starts at 450 m/s along $y$. It then makes
# "a 90° sharp turn" over scans 200–300 with $u_x = u_y = 20$ m/s², and "a gradual 90° turn" over scans
# 305–330 with $u_x = u_y = 3$ m/s². A 90° turn from $(0, 450)$ m/s ends at $(\pm 450, 0)$ m/s: each axis
# changes its velocity by 450 m/s. A constant acceleration $a$ held for $m$ scans changes it by $a\,mT$.
# Each turn therefore fixes its own $T$. The same holds if the accelerations are read as centripetal
# (a coordinated turn at constant speed $V$ and rate $\omega$, with $a = V\omega$ and $\omega\,mT = \pi/2$):

# %%
V0 = 450.0
rows, T_needed = [], {}
for label, a, m in (("sharp turn", 20.0, 100), ("gradual turn", 3.0, 25)):
    T_lin = V0 / (a * m)  # a · m T = 450 m/s per axis
    T_ct = V0 * math.pi / 2 / (a * m)  # coordinated turn: V (π/2) / (m T) = a
    T_needed[label] = (T_lin, T_ct)
    rows.append((label, f"{a:g} m/s² over {m} scans", f"{T_lin:.3g} s", f"{T_ct:.3g} s"))
md_table(["turn", "stated", "T for Δv = 450 m/s per axis", "T for a coordinated 90° turn"], rows)

# %% [markdown]
# No single $T$ satisfies both turns under either reading: the two readings need 0.225 s against 6 s,
# and 0.353 s against 9.4 s. We therefore offer two presets, both with $T = 1$ s and exact
# constant-acceleration kinematics over each interval:
#
# * **`literal`** (default) keeps the printed accelerations and windows: $v(1) = (0, 450)$ m/s,
#   $u = (20, 20)$ m/s² on scans [200, 300) and $(3, 3)$ on [305, 330). These are not turns. The target
#   accelerates to about 3.3 km/s, but the first maneuver stays the sharper one, which is how the paper
#   explains Fig 4.
# * **`turn90`** makes both turns exactly 90° in the same windows: $v(1) = (0, -450)$ m/s,
#   $u_1 = 4.5\,(1, 1)$ m/s² and $u_2 = -18\,(1, 1)$ m/s². Here the second turn is the sharper one.
#
# Check: the `turn90` velocity turns by exactly 90° in each window and keeps 450 m/s at the ends of both
# turns. The `literal` speed grows to 3.3 km/s.

# %%
# alt: Two panels, presets literal and turn90: the true target track in the x-y plane in km, the constant-velocity legs in grey and each manoeuvre (its scans and acceleration) in colour, the start marked.
assert not any(math.isclose(T_needed["sharp turn"][i], T_needed["gradual turn"][i]) for i in range(2))
v = {p: sc.truth()[:, [1, 3]] for p, sc in SC.items()}  # velocity at scans 1..N
for p in mv.PRESETS:
    ends = [v[p][k - 1] for k in (200, 300, 305, 330)]
    angle = [
        math.degrees(math.acos(np.dot(a, b) / np.hypot(*a) / np.hypot(*b))) for a, b in (ends[:2], ends[2:])
    ]
    print(f"{p:8s}: v(200) = {ends[0]}, v(300) = {ends[1]}, v(305) = {ends[2]}, v(330) = {ends[3]} m/s; "
          f"heading change {angle[0]:.1f}° and {angle[1]:.1f}°; final speed {np.hypot(*v[p][-1]):.0f} m/s")  # fmt: skip
t90 = [v["turn90"][k - 1] for k in (200, 300, 305, 330)]
assert np.allclose([np.dot(t90[0], t90[1]), np.dot(t90[2], t90[3])], 0.0, atol=1e-9)
assert np.allclose(np.hypot(*np.array(t90).T), V0)
assert 3200 < np.hypot(*v["literal"][-1]) < 3400

fig = Figure(figsize=(11, 4.6), layout="constrained")
for ax, (p, sc) in zip(fig.subplots(1, 2), SC.items(), strict=True):
    tr = sc.truth()
    moving = np.any(sc.inputs() != 0, axis=1)
    ax.plot(tr[:, 0] / 1e3, tr[:, 2] / 1e3, color="0.5", lw=1.0, label="constant velocity")
    for i, (a, b, ux, uy) in enumerate(sc.segments):
        seg = slice(a - 1, b)
        ax.plot(tr[seg, 0] / 1e3, tr[seg, 2] / 1e3, color=f"C{i + 3}", lw=2.5,
                label=f"scans {a}–{b}: u = ({ux:g}, {uy:g}) m/s²")  # fmt: skip
    ax.plot(tr[0, 0] / 1e3, tr[0, 2] / 1e3, "ko", ms=4, label="scan 1")
    ax.set_title(f"preset {p}: true track ({moving.sum()} maneuvering scans)", fontsize="medium")
    ax.set_xlabel("x [km]")
    ax.set_ylabel("y [km]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small")
fig

# %% [markdown]
# ## 2. The GLR statistic from the innovations of one Kalman filter
#
# **The reference filter.** A Kalman filter runs on the model with $u = 0$ (the "$H_0$ filter"). Its gains
# $K_j$, innovations $\nu^*_j = z_j - H\hat x^*_{j|j-1}$ and innovation covariances $S_j$ do not depend on the
# hypothesis.
#
# **Bias propagation.** Suppose $H_1(u, n)$ holds. The prediction error of the $H_0$ filter obeys
# $x_{j+1} - \hat x^*_{j+1|j} = F(I - K_jH)(x_j - \hat x^*_{j|j-1}) - FK_jv_j + w_j + G u$ for $j \ge n$. It is
# linear in $u$, so it splits into the error the filter would have without the input and a deterministic part
# $M_j(n)\,u$ with
#
# $$ M_j(n) = 0 \ (j \le n), \qquad M_{j+1}(n) = F(I - K_jH)\,M_j(n) + G \ (j \ge n). $$
#
# The innovations inherit it. Under $H_1(u, n)$ they are still independent, $\mathcal N(\Psi_j u, S_j)$ with
# $\Psi_j(n) = HM_j(n)$, which is nonzero from $j = n+1$ on. Under $H_0$ they are $\mathcal N(0, S_j)$.
#
# **The log likelihood ratio.** The terms with $j \le n$ cancel, and the normalising constants of the
# Gaussians cancel as well:
#
# $$ J(u, n) = \log\frac{f(z\mid H_1(u,n))}{f(z\mid H_0)}
#    = \sum_{j=n+1}^{k}\Big[-\tfrac12(\nu^*_j - \Psi_ju)^\top S_j^{-1}(\nu^*_j - \Psi_ju) + \tfrac12\nu^{*\top}_j S_j^{-1}\nu^*_j\Big]
#    = e(n)^\top u - \tfrac12 u^\top\Sigma(n)^{-1}u, $$
#
# $$ \Sigma(n)^{-1} = \sum_{j=n+1}^{k}\Psi_j^\top S_j^{-1}\Psi_j, \qquad e(n) = \sum_{j=n+1}^{k}\Psi_j^\top S_j^{-1}\nu^*_j . $$
#
# This quadratic has its maximum at the least-squares input $\hat u(n) = \Sigma(n)e(n)$, which is what the
# paper states. $\Sigma(n)$ is its error covariance. The maximum is
#
# $$ J(\hat u(n), n) = \tfrac12\Delta J(n), \qquad \Delta J(n) = e(n)^\top\Sigma(n)e(n) = \hat u(n)^\top\Sigma(n)^{-1}\hat u(n). $$
#
# The onset estimate is $\hat n = \arg\max_n \Delta J(n)$ (eq 3). A maneuver is declared when
# $\hat u^\top\Sigma^{-1}\hat u = \Delta J(\hat n) > \lambda$ (§III step 3). **The printed eq (5),**
# $J = -\tfrac12\sum\nu^{*\top}S^{-1}\nu^* + \tfrac12\Delta J$, equals
# $-\tfrac12\sum(\nu^* - \Psi\hat u)^\top S^{-1}(\nu^* - \Psi\hat u)$. That is the $H_1$ log-likelihood up to
# the constant $-\tfrac12\sum\log\det 2\pi S$, not the ratio. Subtracting the $H_0$ log-likelihood leaves
# $\tfrac12\Delta J$. Under $H_0$, at a fixed onset, $e \sim \mathcal N(0, \Sigma^{-1})$, so
# $\Delta J \sim \chi^2_2$. The default threshold $\lambda = 13.8$ is its 0.999 quantile.
#
# **Correction and continuation** (§III step 4, made concrete here). On a declaration the $H_0$ estimate
# carries the bias $M_k(\hat n)\hat u$. The package's `exact` correction adds $(I - K_kH)M_k\hat u$ to the
# *updated* estimate and $(I - K_kH)M_k\Sigma M_k^\top(\cdot)^\top$ to its covariance. The paper's form
# (`correction="paper"`) corrects the prediction and redoes the update with $z_k$. That form uses $z_k$
# twice, so its covariance comes out slightly optimistic. The filter then carries the current input in its
# state, $\xi = [x; u]$, and later onsets are restricted to scans after the declaration. The end of a maneuver
# is then detected as another jump, of about $-\hat u$.
#
# **Check (a): a noise-free record.** A constant-velocity truth gets the step input $u = (20, -10)$ m/s² from
# onset $n = 30$. The measurements carry no noise, but the filter still assumes σ = 100 m and
# $\tilde q_0 = 1$. The $H_0$ innovations are then exactly $\Psi_j u$. The first declaration must name
# $n = 30$ and estimate $u$ exactly, and the corrected estimate must equal the truth.

# %%
T, SIG, Q0 = 1.0, 100.0, 1.0
F, G, Q = cv_input_model(T, Q0)
R = SIG**2 * np.eye(2)
MODEL = InputModel(F, G, Q, H_POS4, R)
_, P_INIT = two_point_init(np.zeros(2), np.zeros(2), T, SIG, n=4)  # the two-point covariance as the prior

N_A, ONSET, U_TRUE = 60, 30, np.array([20.0, -10.0])
X_START = np.array([0.0, 300.0, 0.0, 200.0])  # state at the scan before z[0]
truth_a, x = np.empty((N_A, 4)), X_START.copy()
for j in range(N_A):
    x = F @ x + (G @ U_TRUE if j > ONSET else 0.0)  # u_{j−1} acts from j − 1 = n on
    truth_a[j] = x
z_a = truth_a @ H_POS4.T
it_a = input_tracker(z_a[None], MODEL, X_START, P_INIT, GLRConfig())
k_det = int(np.argmax(it_a.detected[0]))
after = slice(k_det, N_A)
err_u = np.abs(it_a.u_jump[0, k_det] - U_TRUE).max()
err_x = np.abs(it_a.x[0, after] - truth_a[after]).max()
print(f"declarations at scans {np.flatnonzero(it_a.detected[0]).tolist()} (onset {ONSET}); declared onset "
      f"{it_a.onset[0, k_det]}, ΔJ(n̂) = {it_a.stat[0, k_det]:.1f}, û = {it_a.u_jump[0, k_det].round(9)} m/s²")  # fmt: skip
print(f"|û − u| = {err_u:.1e} m/s²; max |x̂ − x| from the declaration on = {err_x:.1e}; "
      f"input carried on: {it_a.u_cur[0, -1].round(9)} m/s²")  # fmt: skip
assert it_a.detected[0].sum() == 1 and it_a.onset[0, k_det] == ONSET
assert err_u < 1e-6 and err_x < 1e-6 and np.abs(it_a.u_cur[0, -1] - U_TRUE).max() < 1e-6

# %% [markdown]
# **Check (b): brute force.** Add noise to the same record. A plain Kalman filter is re-run with the input
# $u$ *known* from onset $n = 30$, for a few values of $u$. The difference of its innovation log-likelihood
# from that of the run with $u = 0$ is $J(u, n)$ by definition. It must equal $e^\top u - \tfrac12 u^\top\Sigma^{-1}u$.
# The same check cell computes $e$ and $\Sigma^{-1}$ with the bias recursion above, from the zero-input run's
# gains, and $\Delta J = e^\top\Sigma e$ must equal the tracker's $\Delta J(30)$ at scan $k = 36$. The tracker
# runs with $\lambda = \infty$, so it never corrects and stays the $H_0$ filter. The last line evaluates the
# printed eq (5) against the brute-force $H_1$ log-likelihood over the window.

# %%
K_B = 36
rng = trial_rng(SEED, 0)
z_b = z_a + SIG * rng.standard_normal(z_a.shape)
it_b = input_tracker(z_b[None], MODEL, X_START, P_INIT, GLRConfig(threshold=math.inf))
ref = kf_run(z_b[: K_B + 1], F, Q, H_POS4, R, X_START, P_INIT)
M, e, info = np.zeros((4, 2)), np.zeros(2), np.zeros((2, 2))
for j in range(ONSET + 1, K_B + 1):
    M = F @ (np.eye(4) - ref["K"][j - 1] @ H_POS4) @ M + G  # M_j(n) from M_{j−1}(n)
    Psi_t_Sinv = (H_POS4 @ M).T @ np.linalg.inv(ref["S"][j])
    e += Psi_t_Sinv @ ref["nu"][j]
    info += Psi_t_Sinv @ H_POS4 @ M
rows, worst = [], 0.0
for u in ([10.0, 0.0], [0.0, 10.0], [20.0, -10.0], [-35.0, 5.0], [50.0, 50.0]):
    u = np.array(u)
    brute = (
        kf_run(z_b[: K_B + 1], F, Q, H_POS4, R, X_START, P_INIT, G, u, ONSET)["ll"].sum() - ref["ll"].sum()
    )
    quad_form = e @ u - 0.5 * u @ info @ u
    worst = max(worst, abs(brute - quad_form))
    rows.append((f"({u[0]:g}, {u[1]:g})", f"{brute:.9f}", f"{quad_form:.9f}"))
dJ_check = e @ np.linalg.solve(info, e)
dJ_tracker = it_b.dJ[0, K_B, K_B - 1 - ONSET]  # column d holds the onset k − 1 − d
u_hat = np.linalg.solve(info, e)
h1 = kf_run(z_b[: K_B + 1], F, Q, H_POS4, R, X_START, P_INIT, G, u_hat, ONSET)
win = slice(ONSET + 1, K_B + 1)
quad_sum = sum(n_ @ np.linalg.solve(S_, n_) for n_, S_ in zip(ref["nu"][win], ref["S"][win], strict=True))
eq5 = -0.5 * quad_sum + 0.5 * dJ_check
logdet_const = -0.5 * sum(np.linalg.slogdet(2 * np.pi * S_)[1] for S_ in ref["S"][win])
print(f"max |brute force − (eᵀu − ½uᵀΣ⁻¹u)| = {worst:.1e};  ΔJ(30) at scan 36: eᵀΣe = {dJ_check:.10f}, "
      f"tracker {dJ_tracker:.10f};  û = {u_hat.round(2)} m/s²")  # fmt: skip
print(f"eq (5) as printed: {eq5:.4f};  brute-force H1 log-likelihood over the window at û, minus "
      f"−½Σ log det 2πS: {h1['ll'][win].sum() - logdet_const:.4f};  the log ratio ½ΔJ = {0.5 * dJ_check:.4f}")  # fmt: skip
assert worst < 1e-7 and abs(dJ_check - dJ_tracker) < 1e-8 * dJ_check
assert abs(h1["ll"].sum() - ref["ll"].sum() - 0.5 * dJ_check) < 1e-8
assert abs(eq5 - (h1["ll"][win].sum() - logdet_const)) < 1e-8
md_table(["u [m/s²]", "log-likelihood difference, KF re-run", "eᵀu − ½uᵀΣ⁻¹u"], rows)

# %% [markdown]
# **Check (c): ΔJ under $H_0$ is χ²₂.** Now the truth has process noise of exactly the filter's $\tilde q_0$,
# and its initial state is drawn from the filter's prior, so the $H_0$ model is exact. Over 4000 runs,
# $\Delta J(n)$ at the fixed onset $n = 20$, read at scan $k = 30$ (10 innovations), must be χ²₂: mean 2 and
# a Kolmogorov–Smirnov test against `scipy.stats.chi2(2)`. So must the one-innovation onset $n = 29$. The
# detector, however, thresholds the *maximum* over the $s = 10$ onsets. Its per-scan false-alarm rate is
# larger than the single-onset 0.001, and the union bound caps it at 0.01.

# %%
B_H0, N_H0, K_H0 = 4000, 40, 30
rng = trial_rng(SEED, 1)
x = X_START + rng.standard_normal((B_H0, 4)) @ np.linalg.cholesky(P_INIT).T
L_Q = np.linalg.cholesky(Q)
z_h0 = np.empty((B_H0, N_H0, 2))
for j in range(N_H0):
    x = x @ F.T + rng.standard_normal((B_H0, 4)) @ L_Q.T
    z_h0[:, j] = x @ H_POS4.T + SIG * rng.standard_normal((B_H0, 2))
it_h0 = input_tracker(z_h0, MODEL, X_START, P_INIT, GLRConfig(threshold=math.inf))
rows = []
for n in (20, 29):
    dj = it_h0.dJ[:, K_H0, K_H0 - 1 - n]
    ks = stats.kstest(dj, stats.chi2(2).cdf)
    rows.append((f"n = {n} ({K_H0 - n} innovation{'s' * (K_H0 - n > 1)})", f"{dj.mean():.3f} ± {dj.std() / math.sqrt(B_H0):.3f}",
                 f"{dj.var():.2f}", f"{ks.pvalue:.2f}", f"{(dj > CHI2_2_999).mean():.4f}"))  # fmt: skip
    assert abs(dj.mean() - 2) < 0.15 and ks.pvalue > 0.01
fa_max = (it_h0.stat[:, K_H0] > CHI2_2_999).mean()
rows.append((f"max over the {GLRConfig().window} onsets", f"{it_h0.stat[:, K_H0].mean():.3f}", "", "",
             f"{fa_max:.4f}"))  # fmt: skip
assert fa_max < 0.01 + 3 * math.sqrt(0.01 / B_H0)
md_table(["ΔJ at scan 30", "mean (χ²₂: 2)", "variance (χ²₂: 4)", "KS p-value vs χ²₂", "P(ΔJ > 13.8)"], rows)

# %% [markdown]
# ## 3. The MLR: the input marginalised under a Gaussian prior
#
# The MLR (eq 6) treats $u$ as random with a prior $f(u)$ and averages the likelihood over it,
# $J(n) = \log\int f(z\mid H_1(u,n))f(u)\,du - \log f(z\mid H_0) = \log\int e^{J(u,n)}f(u)\,du$. With
# $J(u, n) = e^\top u - \tfrac12u^\top\Sigma^{-1}u$ from §2 and the prior $u \sim \mathcal N(0, \Sigma_u)$
# (default $\Sigma_u = \sigma_u^2I$, σ_u = 20 m/s², an assumption), completing the square gives the closed form
#
# $$ J_{\mathrm{MLR}}(n) = \tfrac12 e^\top(\Sigma^{-1} + \Sigma_u^{-1})^{-1}e - \tfrac12\log\det(I + \Sigma_u\Sigma^{-1}). $$
#
# The posterior of the input is $\mathcal N\big((\Sigma^{-1}+\Sigma_u^{-1})^{-1}e,\ (\Sigma^{-1}+\Sigma_u^{-1})^{-1}\big)$.
# The tracker's MLR uses it for the correction. The paper's test is $\max_n J_{\mathrm{MLR}}(n) > 0$.
#
# **Relation to the GLR.** As $\Sigma_u \to \infty$,
# $J_{\mathrm{MLR}}(n) + \tfrac12\log\det\Sigma_u \to \tfrac12\Delta J(n) + \tfrac12\log\det\Sigma(n)$. A
# threshold $h$ on the MLR is therefore a GLR with the onset-dependent threshold
# $\Delta J(n) > 2h + \log\det(\Sigma_u\Sigma(n)^{-1})$. Recent onsets carry little information ($\Sigma(n)$
# large), so they get a low threshold. This is the paper's "with a special choice of the GLR threshold both
# tests coincide". It also shows that the MLR does not remove the threshold problem, as the paper claims. It
# moves the problem into $\Sigma_u$ and $h$.
#
# **Check: the closed form against quadrature.** Take the noisy record of §2 at scan 36 and every onset of
# the window. Six Kalman re-runs with known inputs ($u = 0, \pm10e_x, \pm10e_y, 10(e_x + e_y)$) give the exact
# quadratic $J(u, n)$, i.e. $e(n)$ and $\Sigma(n)^{-1}$ (finite differences are exact for a quadratic). The two
# axes of this model are decoupled: $\Sigma^{-1}$ is diagonal, and the re-runs must confirm it. The prior is
# isotropic, so the 2-D integral factorises into one scalar problem per axis,
# $\int e^{e_iu - \frac12 a_iu^2}\mathcal N(u; 0, \sigma_u^2)\,du$ with $a_i = (\Sigma^{-1})_{ii}$. Each is
# evaluated by 1-D quadrature. The tracker's statistic, $\max_n J_{\mathrm{MLR}}(n)$, must equal the largest
# sum of the two log-integrals, and its $\Delta J(n)$ must equal $e^\top\Sigma e$ from the re-runs. At
# σ_u = 10⁴ the limit above must hold.

# %%
S_WIN = GLRConfig().window
z_w = z_b[: K_B + 1]


def tracker_at(cfg):
    return input_tracker(z_w[None], MODEL, X_START, P_INIT, cfg)


def brute_quadratic(n, h=10.0):
    """e(n) and Σ(n)⁻¹ from Kalman re-runs with known inputs from onset n (exact for a quadratic)."""
    base = kf_run(z_w, F, Q, H_POS4, R, X_START, P_INIT)["ll"].sum()

    def llr(u):
        return kf_run(z_w, F, Q, H_POS4, R, X_START, P_INIT, G, np.array(u), n)["ll"].sum() - base

    lx, ly, lmx, lmy, lxy = llr([h, 0]), llr([0, h]), llr([-h, 0]), llr([0, -h]), llr([h, h])
    e_ = np.array([lx - lmx, ly - lmy]) / (2 * h)
    axx, ayy = -(lx + lmx) / h**2, -(ly + lmy) / h**2  # l(0) = 0
    axy = -(lxy - lx - ly) / h**2
    return e_, np.array([[axx, axy], [axy, ayy]])


def log_marginal(e_, a_, sigma_u):
    """log ∫ exp(e u − ½ a u²) N(u; 0, σ_u²) du by 1-D quadrature, scaled at the peak of the integrand."""
    prec = a_ + 1 / sigma_u**2
    centre, width, peak = e_ / prec, 1 / math.sqrt(prec), 0.5 * e_**2 / prec
    f = lambda u: math.exp(e_ * u - 0.5 * a_ * u * u - peak) * stats.norm.pdf(u, 0, sigma_u)  # noqa: E731
    val, _ = integrate.quad(f, centre - 40 * width, centre + 40 * width, epsabs=0, epsrel=1e-12, limit=200)
    return peak + math.log(val)


onsets = [K_B - 1 - d for d in range(S_WIN)]  # column d of the tracker's per-onset arrays
quad_ = {n: brute_quadratic(n) for n in onsets}
coupling = max(abs(A_[0, 1]) / A_[0, 0] for _, A_ in quad_.values())
dJ_w = tracker_at(GLRConfig(threshold=math.inf)).dJ[0, K_B]
dJ_bf = np.array([e_ @ np.linalg.solve(A_, e_) for e_, A_ in (quad_[n] for n in onsets)])
stat20 = tracker_at(GLRConfig("mlr", threshold=math.inf, sigma_u=20.0)).stat[0, K_B]
quad20 = max(sum(log_marginal(e_[i], A_[i, i], 20.0) for i in range(2)) for e_, A_ in quad_.values())
lhs = tracker_at(GLRConfig("mlr", threshold=math.inf, sigma_u=1e4)).stat[0, K_B] + 0.5 * math.log(1e4**4)
rhs = max(0.5 * dJ_w[d] - 0.5 * np.linalg.slogdet(quad_[n][1])[1] for d, n in enumerate(onsets))
print(f"re-runs: max |Σ⁻¹_xy| / Σ⁻¹_xx = {coupling:.1e};  ΔJ(n) for the 10 onsets: max |re-runs − tracker| / "
      f"max ΔJ = {np.abs(dJ_bf - dJ_w).max() / dJ_w.max():.1e}")  # fmt: skip
print(
    f"σ_u = 20: tracker max_n J_MLR = {stat20:.9f}; quadrature {quad20:.9f} (difference {abs(stat20 - quad20):.1e})"
)
print(f"σ_u = 10⁴: max_n J_MLR + ½ log det Σ_u = {lhs:.5f};  max_n ½ΔJ(n) + ½ log det Σ(n) = {rhs:.5f} "
      f"(rel {abs(lhs / rhs - 1):.1e})")  # fmt: skip
assert coupling < 1e-6 and np.abs(dJ_bf - dJ_w).max() < 1e-6 * dJ_w.max()
assert abs(stat20 - quad20) < 1e-6 and abs(lhs / rhs - 1) < 1e-3

# %% [markdown]
# **What $h = 0$ means.** Take the 2-D model at the most recent onset, $n = k-1$. There $\Psi_k = HG = (T^2/2)I$
# and $S_k$ is isotropic, so $\Sigma^{-1} = aI$ with $a = (T^2/2)^2/S_{xx}$. Write $\rho = \sigma_u^2a$ for the
# information relative to the prior and $x = \Delta J \sim \chi^2_2$. Then
# $J_{\mathrm{MLR}} = \tfrac12 x\,\rho/(1+\rho) - \log(1+\rho)$, and
#
# $$ P(J_{\mathrm{MLR}} > 0 \mid H_0) = (1+\rho)^{-(1+\rho)/\rho} \ \longrightarrow\ e^{-1} \approx 0.37 \quad (\rho \to 0). $$
#
# One scan of 100 m noise says almost nothing about a 20 m/s² input, so ρ is small and the test $h = 0$
# becomes $\Delta J > 2$: it fires in about a third of the scans without any maneuver. Check: the MLR with a
# one-onset window ($s = 1$) on the $H_0$ runs of §2(c). With the full window of 10 onsets the per-scan rate
# is higher still.

# %%
S_k = kf_run(z_h0[0, : K_H0 + 1], F, Q, H_POS4, R, X_START, P_INIT)["S"][K_H0]
assert abs(S_k[0, 1]) < 1e-9 * S_k[0, 0] and math.isclose(S_k[0, 0], S_k[1, 1])
rho = 20.0**2 * (T * T / 2) ** 2 / S_k[0, 0]
p_theory = (1 + rho) ** (-(1 + rho) / rho)
p_one = (input_tracker(z_h0, MODEL, X_START, P_INIT, GLRConfig("mlr", window=1, threshold=math.inf)).stat[:, K_H0] > 0).mean()  # fmt: skip
p_full = (input_tracker(z_h0, MODEL, X_START, P_INIT, GLRConfig("mlr", threshold=math.inf)).stat[:, K_H0] > 0).mean()  # fmt: skip
print(f"ρ = {rho:.4f}: P(J_MLR(k−1) > 0 | H0) theory {p_theory:.4f}, measured {p_one:.4f} "
      f"(± {math.sqrt(p_theory * (1 - p_theory) / B_H0):.4f});  max over 10 onsets > 0: {p_full:.4f}")  # fmt: skip
assert abs(p_one - p_theory) < 4 * math.sqrt(p_theory * (1 - p_theory) / B_H0)

# %% [markdown]
# On the paper's scenario (`literal`, σ = 100 m, 100 runs) the trackers count *false alarms*: declarations
# in scans whose last 10 input intervals were all zero, per 1000 such scans (`detection_summary`, response
# window 10 scans). The table compares the GLR at $\lambda = 13.8$ with the MLR at the paper's $h = 0$ and at
# larger thresholds. It also shows how each detects the first maneuver (onset 200).

# %%
z100 = mv.measurements(SC["literal"], 100.0, range(RUNS), SEED)
RESPONSE = 10


def summarize(sc, tr):
    """detection_summary of a GLR/MLR tracker's declarations, response window RESPONSE scans."""
    return mv.detection_summary(sc, tr.detected, tr.onset, RESPONSE)


SCANS = np.arange(mv.FIRST_SCAN, SC["literal"].scans + 1)
CRUISE = (SCANS >= 50) & (SCANS <= 199)


def row(name, thr, tr):
    ds = summarize(SC["literal"], tr)
    cruise = 1000 * tr.detected[:, CRUISE].mean()
    return cruise, (name, thr, f"{cruise:.1f}", f"{ds.false_alarms_per_1000:.1f} ± {ds.false_alarms_se:.1f}",
                    f"{ds.events[0][2]:.0%}", f"{ds.events[0][3]:.1f}")  # fmt: skip


glr_cruise, glr_row = row("GLR", f"λ = {CFG.glr_threshold:.1f}", mv.track("glr", z100, T, 100.0, CFG))
rows, cruise_mlr = [glr_row], {}
for h in (0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0):
    cruise_mlr[h], r_ = row(
        "MLR", f"h = {h:g}", mv.track("mlr", z100, T, 100.0, mv.TrackerConfig(mlr_threshold=h))
    )
    rows.append(r_)
H_MATCH = min(cruise_mlr, key=lambda h: abs(math.log((cruise_mlr[h] + 0.1) / (glr_cruise + 0.1))))
print(
    f"MLR threshold whose rate in scans 50–199 is closest to the GLR's ({glr_cruise:.1f} per 1000): h = {H_MATCH:g}"
)
assert cruise_mlr[0.0] > 250 and glr_cruise < 10 and cruise_mlr[6.0] < 1
md_table(["detector", "threshold", "declarations per 1000 scans, scans 50–199", "false alarms per 1000 quiet scans",
          "onset 200 detected", "mean delay [scans]"], rows)  # fmt: skip

# %% [markdown]
# With the paper's $h = 0$ the MLR declares a maneuver in about a third of all non-maneuvering scans, close to
# the one-onset value above. Raising $h$ cuts the rate in straight flight (scans 50–199) by an order of
# magnitude per unit at first. At $h = 3$ it matches the GLR's 2 per 1000, which in turn matches the per-scan
# rate 0.0022 of the $H_0$ Monte Carlo of §2(c). At $h \ge 4$ almost nothing is left. The summary's count over
# all quiet scans levels off at 3–4 per 1000 instead. Those declarations all fall in the scans after the
# maneuvers (scans 341–450). There they correct an input error that the maneuvers left in the tracker, so no
# threshold removes them. At the matched threshold the MLR detects the first maneuver as fast
# as the GLR. §6 uses it next to the paper's $h = 0$.
#
# ## 4. The IMM cycle, with the printed formulas corrected
#
# The IMM runs $r = 3$ Kalman filters on $X = [x, \dot x, y, \dot y, \ddot x, \ddot y]^\top$ and mixes them
# through a Markov chain on the model index, $p_{ij} = P(\text{model } j \text{ at } k \mid \text{model } i \text{ at } k-1)$.
#
# * Model 1 is constant velocity: $\Phi_1$ has zero acceleration rows and $Q_1 = 0$.
# * Models 2 and 3 are constant acceleration with an acceleration increment through $G_2 = G_3$, with
#   $Q_2 = 0.001I$ and $Q_3 = 0.0144I$.
#
# One cycle, with our corrections of the paper:
#
# 1. $\bar c_j = \sum_i p_{ij}\mu_i(k-1)$, the predicted model probabilities.
# 2. **Mixing probabilities**, from Bayes' rule: $\mu_{i|j} = P(i \text{ at } k-1 \mid j \text{ at } k) = p_{ij}\mu_i(k-1)/\bar c_j$.
#    The paper prints a spurious $\sum_i$ in the numerator. That makes the numerator $\bar c_j$ and every
#    weight 1, so eq (9) would *add* the three estimates.
# 3. Mixing, eqs (9)–(10): $\hat X_{0j} = \sum_i\mu_{i|j}\hat X_i$ and
#    $P_{0j} = \sum_i\mu_{i|j}[P_i + (\hat X_i - \hat X_{0j})(\cdot)^\top]$.
# 4. Model-matched Kalman filters from $(\hat X_{0j}, P_{0j})$.
# 5. Likelihoods, eq (11): $\Lambda_j = \mathcal N(v_j; 0, S_j)$. The package computes them, and steps 1, 2
#    and 6, in the log domain.
# 6. $\mu_j(k) = \Lambda_j\bar c_j / \sum_l\Lambda_l\bar c_l$.
# 7. Output, eqs (12)–(13): $\hat X = \sum_j\mu_j\hat X_j$ and
#    **$P = \sum_j\mu_j(k)[P_j + (\hat X_j - \hat X)(\cdot)^\top]$**, the covariance of the Gaussian mixture.
#    The paper's eq (13) copies $\mu_{ij}$ and $P_{0j}$ from the mixing step and calls the result "measurement
#    error variances".
#
# The paper's "transition probabilities" $\mu = (0.8, 0.1, 0.1)$ are the *initial model probabilities*
# $\mu(2)$. The transition matrix is $\Pi$, with 0.95 on the diagonal.
#
# **Check: the mixing weights.** For $\mu(k-1) = (0.8, 0.1, 0.1)$ and the paper's Π, the corrected weights
# form a distribution over $i$ for every $j$. Summed back they give $\sum_j\mu_{i|j}\bar c_j = \mu_i$. The
# printed formula gives a matrix of ones.

# %%
MS = imm_models(T)
mu_prev = MS.mu0
cbar = MS.Pi.T @ mu_prev
mix = MS.Pi * mu_prev[:, None] / cbar[None, :]  # μ_{i|j}, rows i, columns j
printed = np.broadcast_to((MS.Pi * mu_prev[:, None]).sum(axis=0) / cbar, (3, 3))
print(
    f"c̄ = {cbar.round(4)}\nμ_(i|j) =\n{mix.round(4)}\ncolumn sums {mix.sum(0)}; printed formula gives\n{printed}"
)
assert np.allclose(mix.sum(axis=0), 1) and np.allclose(mix @ cbar, mu_prev) and np.allclose(printed, 1)

# %% [markdown]
# **$G_2$: $T/2$ or $T$ in the $\dot y$ row.** Models 2 and 3 integrate the acceleration by the trapezoidal
# rule. With $a_{k+1} = a_k + w_k$,
#
# $$ x_{k+1} = x_k + T\dot x_k + \tfrac{T^2}{2}\,\tfrac{a_k + a_{k+1}}{2} = x_k + T\dot x_k + \tfrac{T^2}{2}a_k + \tfrac{T^2}{4}w_k,
#    \qquad \dot x_{k+1} = \dot x_k + T\,\tfrac{a_k + a_{k+1}}{2} = \dot x_k + Ta_k + \tfrac T2 w_k . $$
#
# This gives $\Phi_2$ as printed and the noise gain $(T^2/4, T/2, 1)$ per axis. The paper's $x$ column has it.
# Its $y$ column has $(T^2/4, T, 1)$, which would give the two axes different process noise. Our fix,
# `g2="paper-fixed"` (the default), uses $(T^2/4, T/2, 1)$ on both axes. `g2="standard"` is the common
# discrete white-noise-jerk form, $(T^2/2, T, 1)$. In that form the new acceleration $a_{k+1}$ acts over the
# whole interval.
#
# Check: one explicit trapezoidal step (and one "whole interval" step) at $T = 3$ s gives $\Phi$ and $G$.
# Then $\Phi_2$ and $Q_2 = 0.001\,GG^\top$ of `imm_models` must match.


# %%
def step(X, w, T_, rule):
    """One explicit step of the CA model: the acceleration a → a + w acts over the interval as the mean of the
    old and new values (trapezoid) or as the new value (whole interval)."""
    out = np.empty(6)
    for p_, v_, a_ in ((0, 1, 4), (2, 3, 5)):
        a_new = X[a_] + w[a_ - 4]
        a_eff = 0.5 * (X[a_] + a_new) if rule == "trapezoid" else a_new
        out[p_] = X[p_] + T_ * X[v_] + 0.5 * T_**2 * a_eff
        out[v_] = X[v_] + T_ * a_eff
        out[a_] = a_new
    return out


T2 = 3.0
for g2, rule in (("paper-fixed", "trapezoid"), ("standard", "whole interval")):
    ms_ = imm_models(T2, g2=g2)
    Phi_ex = np.stack([step(c, np.zeros(2), T2, rule) for c in np.eye(6)], axis=1)
    G_ex = np.stack([step(np.zeros(6), c, T2, rule) for c in np.eye(2)], axis=1)
    print(
        f"{g2:11s} ({rule}): G (x, ẋ, ẍ) = {G_ex[[0, 1, 4], 0].tolist()}, (y, ẏ, ÿ) = {G_ex[[2, 3, 5], 1].tolist()}"
    )
    assert np.allclose(Phi_ex, ms_.Phi[1]) and np.allclose(0.001 * G_ex @ G_ex.T, ms_.Qd[1])
    assert np.allclose(0.0144 * G_ex @ G_ex.T, ms_.Qd[2])
G_printed = np.array([[T2**2 / 4, 0], [T2 / 2, 0], [0, T2**2 / 4], [0, T2], [1, 0], [0, 1]])
Qp = 0.001 * G_printed @ G_printed.T
print(
    f"printed G₂ at T = {T2:g}: velocity noise variance x {Qp[1, 1]:.5f}, y {Qp[3, 3]:.5f} (different axes)"
)

# %% [markdown]
# **$P(2|2)$.** The filters start at scan 2 from two-point differencing:
# $\hat X(2|2) = [z_x(2),\ (z_x(2)-z_x(1))/T,\ z_y(2),\ (z_y(2)-z_y(1))/T,\ 0,\ 0]$. Its error covariance per
# axis is $\begin{bmatrix}\delta^2 & \delta^2/T\\ \delta^2/T & 2\delta^2/T^2\end{bmatrix}$. The paper prints
# $\delta_x$ in the $\dot y$ entry; it must be $\delta_y$. The two are equal here (σ is the same on both axes),
# so the fix changes nothing numerically. Check: the estimator is linear, so its error covariance is
# $\delta^2AA^\top$, where the columns of $A$ are the estimates from unit measurement errors. `two_point_init`
# must return that covariance and reproduce a constant-velocity truth exactly.

# %%
T_c, s_c = 0.5, 50.0
A = np.stack([two_point_init(c[:2], c[2:], T_c, s_c)[0] for c in np.eye(4)], axis=1)  # (6, 4)
P22 = two_point_init(np.zeros(2), np.zeros(2), T_c, s_c)[1]
p1, vel = np.array([1e3, -2e3]), np.array([120.0, 80.0])
x22 = two_point_init(p1, p1 + vel * T_c, T_c, s_c)[0]
print(f"max |δ² A Aᵀ − P(2|2)| = {np.abs(s_c**2 * A @ A.T - P22).max():.1e} (max entry {P22.max():.0f}); "
      f"noise-free CV estimate {x22.round(9).tolist()}")  # fmt: skip
assert np.allclose(s_c**2 * A @ A.T, P22, rtol=1e-12, atol=0)
p2 = p1 + vel * T_c
assert np.allclose(x22, [p2[0], vel[0], p2[1], vel[1], 0.0, 0.0], rtol=1e-12)

# %% [markdown]
# **Checks of the cycle** on the paper's scenario (`literal`, σ = 100 m, 100 runs, the paper's three models):
#
# * μ(k) is a probability vector at every scan, and the combined $P(k|k)$ of eq (13) is symmetric positive
#   semi-definite.
# * With a single model ($r = 1$, Π = [1]) the IMM is a plain Kalman filter: the same estimates and the same
#   log-likelihood as the `kf_run` of §2.
# * With three identical models the likelihoods are equal, so $\mu(k) = \Pi^\top\mu(k-1)$ exactly (it tends
#   to (1/3, 1/3, 1/3)), and the output is the single filter's.
# * Two explicit IMM cycles with the corrected formulas (steps 1–7 written out below) reproduce
#   `imm_filter`'s μ, $\hat X$ and $P$ at scans 3 and 4. This is the only check in which the mixing weights
#   act on estimates that differ.

# %%
x0_6, P0_6 = two_point_init(z100[:, 0], z100[:, 1], T, 100.0)
imm = imm_filter(z100[:, 2:], H_POS6, R, MS, x0_6, P0_6, keep_P=True)
mu_err = np.abs(imm.mu.sum(axis=-1) - 1).max()
asym = np.abs(imm.P - np.swapaxes(imm.P, -1, -2)).max() / np.abs(imm.P).max()
min_eig = (np.linalg.eigvalsh(imm.P)[..., 0] / np.linalg.eigvalsh(imm.P)[..., -1]).min()
print(f"max |Σ_j μ_j − 1| = {mu_err:.1e}, min μ = {imm.mu.min():.1e};  P: max asymmetry {asym:.1e}, "
      f"min eigenvalue / max eigenvalue {min_eig:.1e}")  # fmt: skip
assert mu_err < 1e-12 and imm.mu.min() >= 0 and asym < 1e-12 and min_eig > -1e-12

# r = 1: the IMM of one CV model against the plain Kalman filter, on the noisy record of §2
ms1 = ModelSet(F[None], Q[None], np.ones((1, 1)), np.ones(1))
one = imm_filter(z_b[None], H_POS4, R, ms1, X_START, P_INIT)
kf = kf_run(z_b, F, Q, H_POS4, R, X_START, P_INIT)
d1 = np.abs(one.x[0] - kf["x"]).max()
print(
    f"r = 1: max |x̂_IMM − x̂_KF| = {d1:.1e} m, max |log Λ − log N(ν; 0, S)| = {np.abs(one.loglik[0, :, 0] - kf['ll']).max():.1e}"
)
assert d1 < 1e-8 and np.allclose(one.loglik[0, :, 0], kf["ll"], atol=1e-9) and np.all(one.log_mu == 0)

# three identical models (model 2 three times) against the single model-2 filter
ms3 = ModelSet(np.repeat(MS.Phi[1:2], 3, 0), np.repeat(MS.Qd[1:2], 3, 0), MS.Pi, MS.mu0)
N3 = 200
three = imm_filter(z100[:1, 2 : 2 + N3], H_POS6, R, ms3, x0_6[0], P0_6)
kf6 = kf_run(z100[0, 2 : 2 + N3], MS.Phi[1], MS.Qd[1], H_POS6, R, x0_6[0], P0_6)
mu_chain = np.empty((N3, 3))
m_ = MS.mu0.copy()
for k in range(N3):
    m_ = MS.Pi.T @ m_
    mu_chain[k] = m_
d3, dmu = np.abs(three.x[0] - kf6["x"]).max(), np.abs(three.mu[0] - mu_chain).max()
print(f"3 identical models: max |x̂ − x̂_KF| = {d3:.1e} m; max |μ(k) − Πᵀμ(k−1)| = {dmu:.1e}; "
      f"μ after 1, 10, {N3} scans: {three.mu[0, 0].round(4)}, {three.mu[0, 9].round(4)}, {three.mu[0, -1].round(6)}")  # fmt: skip
assert d3 < 1e-7 and dmu < 1e-12 and np.allclose(three.mu[0, -1], 1 / 3, atol=1e-6)

# two explicit IMM cycles with the corrected formulas, run 0
Xs, Ps, mu_ = [x0_6[0]] * 3, [P0_6] * 3, MS.mu0.copy()
for k in range(2):
    cb = MS.Pi.T @ mu_  # 1
    w = MS.Pi * mu_[:, None] / cb[None, :]  # 2: μ_{i|j}
    X0 = [sum(w[i, j] * Xs[i] for i in range(3)) for j in range(3)]  # 3: eq (9)
    P0 = [sum(w[i, j] * (Ps[i] + np.outer(Xs[i] - X0[j], Xs[i] - X0[j])) for i in range(3)) for j in range(3)]
    ll = np.empty(3)
    for j in range(3):  # 4–5: one Kalman step per model from the mixed estimate
        Xp = MS.Phi[j] @ X0[j]
        Pp = MS.Phi[j] @ P0[j] @ MS.Phi[j].T + MS.Qd[j]
        S_ = H_POS6 @ Pp @ H_POS6.T + R
        Kg = Pp @ H_POS6.T @ np.linalg.inv(S_)
        nu = z100[0, 2 + k] - H_POS6 @ Xp
        ll[j] = -0.5 * (nu @ np.linalg.solve(S_, nu) + np.linalg.slogdet(2 * np.pi * S_)[1])
        Xs[j], Ps[j] = Xp + Kg @ nu, (np.eye(6) - Kg @ H_POS6) @ Pp
    mu_ = np.exp(ll) * cb / (np.exp(ll) * cb).sum()  # 6
    Xc = sum(mu_[j] * Xs[j] for j in range(3))  # 7: eq (12)
    Pc = sum(mu_[j] * (Ps[j] + np.outer(Xs[j] - Xc, Xs[j] - Xc)) for j in range(3))  # eq (13), corrected
    dX, dP = np.abs(Xc - imm.x[0, k]).max(), np.abs(Pc - imm.P[0, k]).max() / np.abs(Pc).max()
    print(
        f"scan {k + 3}: μ = {mu_.round(6)} (imm_filter {imm.mu[0, k].round(6)}); |ΔX̂| = {dX:.1e}, |ΔP|/|P| = {dP:.1e}"
    )
    assert np.allclose(mu_, imm.mu[0, k], atol=1e-12) and dX < 1e-8 and dP < 1e-9

# %% [markdown]
# **Log-domain likelihoods.** A double underflows below $e^{-745}$. On the paper's scenario at σ = 100 m the
# smallest $\log\Lambda_j$ is only about −125, so a linear-domain IMM would survive. At σ = 10 m, however, the
# 20 m/s² onset drives *all three* log-likelihoods below −745 in some scans. A linear-domain step 6 then
# computes 0/0, and the filter is lost. The package keeps $\log\mu$ finite.

# %%
for s_ in (100.0, 10.0):
    z_ = mv.measurements(SC["literal"], s_, range(20), SEED)
    xi, Pi_ = two_point_init(z_[:, 0], z_[:, 1], T, s_)
    tr_ = imm_filter(z_[:, 2:], H_POS6, s_**2 * np.eye(2), MS, xi, Pi_)
    dead = (np.exp(tr_.loglik) == 0).all(axis=-1)
    print(f"σ = {s_:g} m, 20 runs: min log Λ_j = {tr_.loglik.min():.0f}; scans with every Λ_j = 0 in double "
          f"precision: {dead.sum()}; μ finite and normalised: {bool(np.allclose(tr_.mu.sum(-1), 1))}")  # fmt: skip
assert dead.sum() > 0 and np.all(np.isfinite(tr_.log_mu)) and np.allclose(tr_.mu.sum(-1), 1)

# %% [markdown]
# **Initial probabilities and the $G_2$ form in practice.** The initial μ is forgotten at roughly the rate of
# the Markov chain, whose second eigenvalue is $1 - 3 \cdot 0.025 = 0.925$ per scan. Starting from
# (1/3, 1/3, 1/3) instead of (0.8, 0.1, 0.1) changes μ by about 2 % after 50 scans, and the positions by less
# than 10 m. The $G_2$ form barely matters on this scenario. The maneuvering models' increments are tiny either
# way: $\sqrt{Q_3}$ = 0.12 m/s² per scan, against a 20 m/s² jump. The RMS position error of the 100 runs, with
# both forms:

# %%
ms_flat = imm_models(T, mu0=np.full(3, 1 / 3))
flat = imm_filter(z100[:, 2:], H_POS6, R, ms_flat, x0_6, P0_6)
dmu = np.abs(flat.mu - imm.mu).max(axis=(0, 2))
dpos = np.abs(flat.x[..., [0, 2]] - imm.x[..., [0, 2]]).max()
lam2 = np.sort(np.linalg.eigvals(MS.Pi).real)[-2]
print("μ(2) = (1/3, 1/3, 1/3) instead of (0.8, 0.1, 0.1): max |Δμ| over the runs at scans 3, 23, 53, 103: "
      + ", ".join(f"{dmu[k - 3]:.1e}" for k in (3, 23, 53, 103))
      + f" (0.43 × {lam2:.3f}^(k−3): " + ", ".join(f"{0.43 * lam2 ** (k - 3):.1e}" for k in (3, 23, 53, 103))
      + f"); max position difference {dpos:.1f} m")  # fmt: skip
assert dmu[50] < 0.05 and dmu[100] < 5e-3 and dpos < 10
rows = []
for g2 in ("paper-fixed", "standard"):
    es = mv.error_stats(SC["literal"], mv.track("imm", z100, T, 100.0, mv.TrackerConfig(g2=g2)).pos)
    rows.append(
        (
            g2,
            f"{es.rms[sl(50, 199)].mean():.1f}",
            f"{es.rms[sl(200, 299)].max():.0f}",
            f"{es.rms[sl(305, 339)].max():.0f}",
        )
    )
md_table(
    ["G₂", "mean RMS, scans 50–199 [m]", "peak RMS, scans 200–299 [m]", "peak RMS, scans 305–339 [m]"], rows
)

# %% [markdown]
# ## 5. Figs 2–4 and the model probabilities
#
# 100 runs per σ, for both presets. Every tracker sees the same measurement errors: run $r$ draws its
# standard-normal errors $w_r$ from `trial_rng(seed, r)`, and $z = \text{truth} + \sigma w_r$ for both σ. Fig 2
# shows the estimated track of run 1. Figs 3 and 4 show the mean error $\bar e$ (eq 14, truth − estimate) and
# the standard deviation $\sigma_{\hat x}$ (eq 15, normalised by $1/M$) against the scan. The last panel shows
# the mean model probabilities. The dotted lines mark the input changes.

# %%
# alt: Four panels for the literal preset: Fig 2, the true track and the IMM's filtered tracks in km; Fig 3, the mean filtering error against the scan; Fig 4, its standard deviation; and the mean IMM model probabilities; for σ = 100 and 200 m, the manoeuvre times as dotted lines.
SIGMAS = (100.0, 200.0)
res = {
    p: {s_: mv.run_trackers(SC[p], s_, range(RUNS), SEED, mv.METHODS, CFG) for s_ in SIGMAS}
    for p in mv.PRESETS
}
est = {p: {s_: {m: mv.error_stats(SC[p], tr_.pos) for m, tr_ in res[p][s_].items()} for s_ in SIGMAS} for p in mv.PRESETS}  # fmt: skip
SCAN = est["literal"][100.0]["imm"].scan


def imm_fig(p):
    per = [(s_, res[p][s_]["imm"].pos[0], est[p][s_]["imm"].mean, est[p][s_]["imm"].sd, res[p][s_]["imm"].mu.mean(0))
           for s_ in SIGMAS]  # fmt: skip
    fig = maneuver_figure(SC[p].truth(), SCAN, per, method="IMM", model_names=MS.names,
                          events=tuple(n for n, _ in SC[p].events()))  # fmt: skip
    fig.suptitle(f"preset {p}, {RUNS} runs")
    return fig


imm_fig("literal")

# %%
# alt: The same four panels for the turn90 preset: true and filtered tracks, the mean filtering error and its standard deviation against the scan, and the mean IMM model probabilities.
imm_fig("turn90")

# %% [markdown]
# Our reproduction targets R11–R14 (a pilot used 60 runs). R13 is the paper's Fig 4 claim that
# the first maneuver is the sharper one. It is evaluated for `literal` only, because in `turn90` the second
# turn is the sharper one.

# %%
rows, ok = [], {}
for p in mv.PRESETS:
    for s_ in SIGMAS:
        e_ = est[p][s_]["imm"]
        mu1 = res[p][s_]["imm"].mu.mean(0)[:, 0]
        r11 = e_.sd[sl(50, 199), 0].mean()
        r12 = (np.abs(e_.mean[sl(200, 249), 0]).max(), np.abs(e_.mean[sl(150, 199), 0]).max())
        r13 = (e_.sd[sl(200, 299), 0].max(), e_.sd[sl(300, 339), 0].max())
        r14 = (mu1[sl(200, 299)].mean(), mu1[sl(50, 199)].mean())
        ok[(p, s_)] = {
            "R11": 0.2 * s_ <= r11 <= 0.5 * s_,
            "R12": r12[0] >= 5 * r12[1],
            "R14": r14[0] < r14[1],
        }
        if p == "literal":
            ok[(p, s_)]["R13"] = r13[0] > r13[1]
        rows.append((p, f"{s_:g}", f"{r11:.1f} ({r11 / s_:.2f}σ)", f"{r12[0]:.0f} vs {r12[1]:.1f}",
                     f"{r13[0]:.0f} vs {r13[1]:.0f}" + ("" if p == "literal" else " (not a target)"),
                     f"{r14[0]:.2f} vs {r14[1]:.2f}"))  # fmt: skip
    ratio = est[p][200.0]["imm"].sd[sl(50, 199), 0].mean() / est[p][100.0]["imm"].sd[sl(50, 199), 0].mean()
    ok[(p, "ratio")] = {"R11 ratio": 1.5 <= ratio <= 2.3}
    print(f"{p}: R11 ratio σ_x̂(σ = 200) / σ_x̂(σ = 100) over scans 50–199 = {ratio:.2f} (target [1.5, 2.3])")
print("targets met: " + ", ".join(f"{k[0]} {k[1]}: " + " ".join(f"{n} {'✓' if v else '✗'}" for n, v in d.items()) for k, d in ok.items()))  # fmt: skip
assert all(all(d.values()) for d in ok.values())
md_table(["preset", "σ [m]", "R11: mean σ_x̂, scans 50–199 [m] (target 0.2σ–0.5σ)",
          "R12: max abs(ē_x), 200–249 vs 150–199 [m] (≥ 5×)", "R13: peak σ_x̂, 200–299 vs 300–339 [m]",
          "R14: mean μ₁, 200–299 vs 50–199"], rows)  # fmt: skip

# %% [markdown]
# All four targets hold at 100 runs.
#
# * **R11:** in straight flight the IMM brings the error down to about 0.3σ per axis, and the error scales
#   with σ.
# * **R12:** the mean error jumps by one to two orders of magnitude at the first maneuver. This is the "major
#   fluctuation" of Fig 3.
# * **R13:** in `literal`, the first (20 m/s²) maneuver raises $\sigma_{\hat x}$ more than the second (3 m/s²),
#   as the paper says of Fig 4.
# * **R14:** the CV model loses probability during the maneuver.
#
# μ₁ is not dominant even in straight flight: it stays around 0.4. The CA models fit just as well there,
# because their acceleration estimate is ≈ 0. The figures also show what the paper's curves hide. In
# `literal` the mean error during the first maneuver is several hundred metres, several times σ. With
# $\sqrt{Q_3}$ = 0.12 m/s² per scan, the CA models need many scans to build up a 20 m/s² acceleration, so
# the IMM lags the maneuver. The paper's "less affected by the maneuvering" is therefore relative at best.
# §6 puts a number on it.
#
# ## 6. Beyond the paper: IMM, GLR, MLR and the CV Kalman filter on the same runs
#
# The same 100 runs per σ and preset. The trackers:
#
# * the IMM of §4;
# * the GLR tracker (λ = 13.8, window 10, exact correction, input carried in the state);
# * the MLR tracker, at the paper's $h = 0$ and at the threshold matched in §3;
# * the plain CV Kalman filter they start from ($\tilde q_0$ = 1 m²/s³, never corrected).
#
# Top: the RMS position error against the scan. Bottom: the fraction of runs that declare a maneuver in
# each scan.


# %%
# alt: Literal preset, σ = 100 m (left) and 200 m (right): above, the RMS position error of the IMM, GLR, MLR and the CV Kalman filter against the scan on a log scale; below, the fraction of runs in which GLR and MLR declare at each scan; the manoeuvre times as dotted lines.
def comparison(p):
    rms = {(s_, m): est[p][s_][m].rms for s_ in SIGMAS for m in mv.METHODS}
    rate = {(s_, m): res[p][s_][m].detected.mean(0) for s_ in SIGMAS for m in ("glr", "mlr")}
    fig = maneuver_comparison_figure(SCAN, rms, rate, events=tuple(n for n, _ in SC[p].events()))
    fig.suptitle(f"preset {p}, {RUNS} runs (MLR at the paper's h = 0)")
    return fig


comparison("literal")

# %%
# alt: Turn90 preset, σ = 100 m and 200 m: the RMS position error of the IMM, GLR, MLR and the CV Kalman filter against the scan, and the fraction of runs in which GLR and MLR declare at each scan.
comparison("turn90")

# %% [markdown]
# The table gives the RMS position error per phase (mean over the phase's scans; "peak" is the largest value
# in the phase) and, for the detectors, the false alarms. `detection_summary` attributes a declaration at scan
# $k$ to the latest input change $n$ with $n < k \le n + 10$. Declarations at scans whose last 10 input
# intervals were all zero are false alarms, counted per 1000 such scans.

# %%
res_h = {p: {s_: mv.track("mlr", mv.measurements(SC[p], s_, range(RUNS), SEED), T, s_,
                          mv.TrackerConfig(mlr_threshold=H_MATCH)) for s_ in SIGMAS} for p in mv.PRESETS}  # fmt: skip
LABELS = {"imm": "IMM", "glr": "GLR", "mlr": "MLR h = 0", "mlr_h": f"MLR h = {H_MATCH:g}", "cv": "CV KF"}


def tracks_of(p, s_, m):
    return res_h[p][s_] if m == "mlr_h" else res[p][s_][m]


rows, summary = [], {}
for p in mv.PRESETS:
    phases = SC[p].phases()
    for s_ in SIGMAS:
        for m in ("imm", "glr", "mlr", "mlr_h", "cv"):
            tr_ = tracks_of(p, s_, m)
            rms = mv.error_stats(SC[p], tr_.pos).rms
            cells = [f"{rms[sl(a, b - 1)].mean():.0f} / {rms[sl(a, b - 1)].max():.0f}" for _, a, b in phases]
            ds = summarize(SC[p], tr_) if tr_.detected is not None else None
            summary[(p, s_, m)] = (rms, ds)
            fa = f"{ds.false_alarms_per_1000:.1f}" if ds else ""
            rows.append((p, f"{s_:g}", LABELS[m], *cells, fa))
header = ["preset", "σ", "tracker"] + [
    f"RMS {name} (scans {a}–{b - 1}) mean / peak [m]" for name, a, b in SC["literal"].phases()
]
md_table([*header, "false alarms / 1000"], rows)

# %% [markdown]
# The detection of each input change: the fraction of runs with a declaration within 10 scans of the onset,
# the mean delay (scan of the first declaration − onset), and the mean error of the declared onset, in scans.

# %%
rows = []
for p in mv.PRESETS:
    ev = SC[p].events()
    for s_ in SIGMAS:
        for m in ("glr", "mlr", "mlr_h"):
            ds = summary[(p, s_, m)][1]
            cells = [f"{e_[2]:.0%} / {e_[3]:.1f} / {e_[5]:+.1f}" if e_[2] > 0 else "0 %" for e_ in ds.events]
            rows.append((p, f"{s_:g}", LABELS[m], *cells))
md_table(["preset", "σ", "detector"]
         + [f"onset {n}, Δu = ({du[0]:g}, {du[1]:g}): detected / delay / onset error" for n, du in SC["literal"].events()],
         rows)  # fmt: skip

# %% [markdown]
# Our provisional GLR target R15 has two parts. The false-alarm rate in scans 50–199 must be ≤ 2 % of
# scans, and the first maneuver of `literal` must be detected within 5 scans of scan 200 in ≥ 95 % of runs.

# %%
for s_ in SIGMAS:
    g = res["literal"][s_]["glr"]
    fa_rate = g.detected[:, sl(50, 199)].mean()
    within5 = g.detected[:, sl(201, 205)].any(axis=1).mean()
    within10 = g.detected[:, sl(201, 210)].any(axis=1).mean()
    print(f"σ = {s_:g}: GLR declarations in scans 50–199: {fa_rate:.2%} of scans (target ≤ 2 %: "
          f"{'✓' if fa_rate <= 0.02 else '✗'}); onset 200 declared within 5 scans in {within5:.0%} of runs "
          f"(target ≥ 95 %: {'✓' if within5 >= 0.95 else '✗'}), within 10 scans in {within10:.0%}")  # fmt: skip

imm_peak = summary[("literal", 100.0, "imm")][0][sl(200, 299)].max()
glr_peak = summary[("literal", 100.0, "glr")][0][sl(200, 299)].max()
cv_peak = summary[("literal", 100.0, "cv")][0][sl(200, 299)].max()
mlr0_fa = summary[("literal", 100.0, "mlr")][1].false_alarms_per_1000
print(f"literal, σ = 100: peak RMS in scans 200–299: IMM {imm_peak:.0f} m, GLR {glr_peak:.0f} m, CV {cv_peak:.0f} m; "
      f"MLR (h = 0) false alarms {mlr0_fa:.0f} per 1000 quiet scans")  # fmt: skip
imm_rms, glr_rms = summary[("literal", 100.0, "imm")][0], summary[("literal", 100.0, "glr")][0]
mlr0_cruise = summary[("literal", 100.0, "mlr")][0][sl(50, 199)].mean()
print(f"IMM peak at scan {SCAN[sl(200, 299)][np.argmax(imm_rms[sl(200, 299)])]}; MLR (h = 0) mean RMS in scans "
      f"50–199 {mlr0_cruise:.0f} m (σ = 100 m); scans 380–450: IMM {imm_rms[sl(380, 450)].mean():.0f} m, "
      f"GLR {glr_rms[sl(380, 450)].mean():.0f} m")  # fmt: skip
assert imm_peak > 500 and glr_peak < imm_peak / 3 and cv_peak > imm_peak and mlr0_fa > 200
assert 90 < mlr0_cruise < 120 and glr_rms[sl(380, 450)].mean() > imm_rms[sl(380, 450)].mean()

# %% [markdown]
# What the comparison shows, on these runs:
#
# * **The IMM with the paper's models lags a 20 m/s² onset.** In `literal` at σ = 100 m its RMS error peaks at
#   about 1 km, ten times σ, 16 scans into the maneuver. Averaged over the maneuver it is about 200 m. It
#   recovers once models 2 and 3 have built up the acceleration. The tiny $Q_2$, $Q_3$ are the cause; §4
#   showed that the $G_2$ form is not. The CV Kalman filter never adapts and drifts off by kilometres.
# * **The GLR tracks it.** It declares the 20 m/s² onset in 99 % of the runs, 5–7 scans after the onset (at
#   σ = 100 and 200 m), and estimates the onset to within about a scan. The correction removes the
#   accumulated bias at once, so the RMS error peaks at about 200 m (σ = 100 m), just before the declaration.
#   Gentle changes take longer. The 4.5 m/s² turn of `turn90` is declared within 10 scans in only half the
#   runs at σ = 100 m, yet the error stays below 170 m. The end of the first `literal` maneuver (onset 300),
#   followed 5 scans later by the 3 m/s² segment, is often declared only once, as one combined change (hence
#   the negative onset error at 305). Over scans 305–339 the GLR is therefore worse than the IMM.
# * **R15, the provisional GLR target.** In straight flight the GLR raises 2–3 false alarms per 1000 scans,
#   far inside the 2 % target. The rate matches the $H_0$ Monte Carlo of §2(c). The second part fails: at
#   σ = 100 m the first maneuver is declared within 5 scans in only about half the runs (9 % at σ = 200 m),
#   though within 10 scans in almost all: "within 10 scans" is what this threshold achieves.
# * **The MLR with the paper's h = 0 declares in about a third of the non-maneuvering scans** (§3 explains why).
#   It catches every change within about 3 scans, as any detector that fires every third scan would. Each
#   declaration, however, injects a poorly known input, and the RMS error stays at about σ everywhere: the
#   tracker has lost the filtering gain. At the matched threshold $h = 3$ its errors and detections are close
#   to the GLR's.
# * **Where the IMM does better.** Before the maneuvers the CV filter, whose model is then exact, is best, and
#   the IMM and the GLR are 5–15 % worse. After the maneuvers the IMM is back at its straight-flight error.
#   The GLR still carries a residual input error, which it corrects with late declarations (the "false
#   alarms" after scan 340 in the summary), and stays 20–40 % worse for a hundred scans. The GLR has the
#   smaller error in turn 1 of `literal` and in both turns of `turn90`; the IMM in the 3 m/s² segment of
#   `literal`.
#
# ## Reproduce
#
# ```
# motionsig maneuver --runs 500 --plot figs.png                          # Figs 2-4 and the model probabilities
# motionsig maneuver --preset turn90 --runs 500 --plot figs90.png
# motionsig maneuver --method all --view summary --response 10 --plot-compare cmp.png   # §6
# motionsig maneuver --method glr,mlr --view events --mlr-threshold 0   # detection delays, onset errors
# ```
