# %% [markdown]
# # Mode signatures and Gold codes
#
# A vehicle announces its operating mode $i$ by adding a small, known perturbation to its own
# position reference (§II.A of the mode-signature paper, 47th IEEE CDC, Cancún, 2008). The perturbation is a Gold-code chip sequence multiplying a
# sinusoidal carrier. This page derives the signal model (eqs 1–3), the theory of m-sequences and
# Gold codes that makes the codes easy to tell apart, and audits the paper's Table I. Every claim is
# followed by a numerical check that calls `motionsig_cli`; the checks run when the site is built,
# so a false claim fails the build.
#
# The command-line equivalents are given as we go (`motionsig encode …`).

# %%
import math

import numpy as np
from matplotlib.figure import Figure

from motionsig_cli.signals import gf2, gold, gps, modes
from motionsig_cli.signals.correlation import gold_bound, offpeak_counts, periodic_correlation, to_bipolar
from motionsig_cli.signals.lfsr import m_sequence
from motionsig_cli.signals.signature import SignatureConfig, mode_signature

# %% [markdown]
# ## 1. The signature: eqs (1)–(3)
#
# Samples are taken every $T$ seconds, $t_k = kT$. A chip is a rectangular pulse of $m_\rho$
# samples (chip duration $T_c = m_\rho T$) with value $\rho_0 = -1$ for bit 0 and $\rho_1 = +1$
# for bit 1 (BPSK). The $i$-th mode's code is
#
# $$ p^i = [\,b_{i,1}, b_{i,2}, \dots, b_{i,n_\rho}\,], \qquad b_{i,j} \in \{\rho_0, \rho_1\} \tag{1}$$
#
# (the paper prints the interval $[\rho_0, \rho_1]$; it is the two-element set). With a code phase
# $\tau$ (in samples) sample $k$ carries chip
#
# $$ j(k) = \left\lfloor \frac{k-\tau}{m_\rho} \right\rfloor \bmod n_\rho , \qquad p^i_k[\tau] = b_{i, j(k)} .$$
#
# The signature multiplies the chips by a carrier of frequency $f_c$ and phase $\theta$,
#
# $$ z^i_{\mathrm{sig},k} = p^i_k[\tau]\cos(2\pi f_c t_k + \theta), \tag{2}$$
#
# and the received model allows a frequency offset $f_d$ (zero in both of the paper's examples):
#
# $$ a_{\mathrm{sig}}\, z^i_{\mathrm{sig},k} = a_{\mathrm{sig}}\, p^i_k[\tau]\cos(2\pi f_c t_k + 2\pi f_d t_k + \theta). \tag{3}$$
#
# The paper prints $2\pi f_{d,k}$; a frequency offset has to multiply time, so we use
# $2\pi f_d t_k$. The detector does not know $\theta$, so it works with two replicas,
# $z_{\cos,k} = p_k\cos(2\pi f_c t_k)$ and $z_{\sin,k} = p_k\sin(2\pi f_c t_k)$. The angle-sum
# formula gives
#
# $$ z_k = \cos\theta\, z_{\cos,k} - \sin\theta\, z_{\sin,k} \qquad (f_d = 0). $$
#
# The paper does not give $T$ or $m_\rho$. The defaults $T = 0.05$ s and $m_\rho = 20$ (one carrier
# cycle per chip at $f_c = 1$ Hz) are assumptions, and both are options
# (`motionsig encode signature --T … --mrho …`).

# %%
chips = to_bipolar(modes.table1_codes("corrected")[0])  # mode 1 (A)
cfg = SignatureConfig(T=0.05, m_rho=20, f_c=1.0, theta=0.5, tau=30)
sig = mode_signature(chips, cfg, n_samples=2 * 31 * 20)

# check 1: the chip index follows floor((k - tau)/m_rho) mod n_rho, for every sample
expected_chip = [math.floor((k - cfg.tau) / cfg.m_rho) % 31 for k in sig.k]
assert sig.chip.tolist() == expected_chip
# check 2: the quadrature identity z = cos(theta) z_cos - sin(theta) z_sin
identity_error = np.max(np.abs(sig.z - (math.cos(cfg.theta) * sig.z_cos - math.sin(cfg.theta) * sig.z_sin)))
assert identity_error < 1e-12
# check 3: the code repeats every n_rho * m_rho samples
assert np.array_equal(sig.p[: 31 * 20], sig.p[31 * 20 :])
print(f"max |z - (cos θ z_cos - sin θ z_sin)| = {identity_error:.1e}")

# %%
# alt: Three stacked traces over two code periods: the mode-1 chip sequence p_k as a square wave, the carrier cosine, and their product, the signature z_k.
fig = Figure(figsize=(8, 4.8), layout="constrained")
ax = fig.subplots(3, 1, sharex=True)
ax[0].step(sig.t, sig.p, where="post")
ax[0].set_ylabel("chip $p_k[\\tau]$")
ax[1].plot(sig.t, np.cos(2 * np.pi * cfg.f_c * sig.t + cfg.theta), color="C1")
ax[1].set_ylabel("carrier")
ax[2].plot(sig.t, sig.z, color="C2")
ax[2].set_ylabel("$z_k$")
ax[2].set_xlabel("t [s]")
fig.suptitle("Mode-1 signature, τ = 30 samples, θ = 0.5 rad (two code periods)")
fig

# %% [markdown]
# The closed loop of the later examples also needs the time derivative $\dot z$ (eq 54). The
# paper does not say how $\dot z$ is taken. Inside a chip $p$ is constant, so we differentiate
# the carrier analytically, $\dot z_k = -2\pi f_c\, p_k \sin(2\pi f_c t_k + \theta)$, and ignore the
# chip edges. A backward difference, `--zdot finite-difference`, would add spikes of up to $2/T$
# at every chip flip.

# %%
fd = mode_signature(chips, cfg, n_samples=620, zdot="finite-difference")
flips = np.flatnonzero(np.diff(fd.p) != 0) + 1
print(
    f"finite-difference spike at chip flips: {np.max(np.abs(fd.zdot[flips])):.1f} (2/T = {2 / cfg.T:.0f});"
    f" analytic |ż| <= 2π f_c = {2 * np.pi:.2f}"
)
assert np.max(np.abs(sig.zdot)) <= 2 * np.pi * cfg.f_c + 1e-12

# %% [markdown]
# ## 2. m-sequences
#
# A linear feedback shift register with characteristic polynomial
# $p(x) = x^n + c_{n-1}x^{n-1} + \dots + c_1 x + 1$ over GF(2) produces the recurrence
#
# $$ s_{t+n} = \bigoplus_{i=0}^{n-1} c_i\, s_{t+i} .$$
#
# The nonzero register states are the nonzero elements of $\mathrm{GF}(2)[x]/(p)$. When $p$ is
# **primitive**, $x$ generates the multiplicative group of the field $\mathrm{GF}(2^n)$. The register
# then steps through all $2^n-1$ nonzero states before it repeats, and the output is a
# maximal-length sequence (an *m-sequence*). We test primitivity by checking that the order of $x$
# modulo $p$ is exactly $N = 2^n-1$: $x^N \equiv 1$, and $x^{N/r} \not\equiv 1$ for every prime
# $r \mid N$. The number of primitive polynomials of degree $n$ is $\varphi(2^n-1)/n$.
#
# Three facts about m-sequences follow from this field structure:
#
# * **Balance.** Over one period the register visits every nonzero state once. The output is the
#   lowest stage, which is 1 in $2^{n-1}$ of the $2^n - 1$ states, so there are $2^{n-1}$ ones.
# * **Shift-and-add.** $s \oplus T^\ell s$ with $\ell \not\equiv 0$ satisfies the same linear
#   recurrence and is not identically zero, so it is another cyclic shift of $s$.
# * **Two-valued autocorrelation.** In bipolar form ($\pm1$),
#   $R(\ell) = N - 2\,\mathrm{wt}(s \oplus T^\ell s)$. By shift-and-add the word
#   $s \oplus T^\ell s$ is a shift of $s$ and has weight $2^{n-1}$, so $R(\ell) = -1$ for every
#   $\ell \ne 0$ and $R(0) = N$.
#
# Initial states follow MATLAB's `comm.PNSequence` convention, so the vectors MATLAB prints can be
# reproduced: the first $n$ output chips are the state vector reversed.


# %%
# check: phi(2^n - 1)/n primitive polynomials
def phi(m: int) -> int:
    return sum(1 for a in range(1, m + 1) if math.gcd(a, m) == 1)


for n in range(2, 11):
    assert len(gf2.primitive_polynomials(n)) == phi(2**n - 1) // n
print("degree-5 primitive polynomials (octal):", [gf2.to_octal(p) for p in gf2.primitive_polynomials(5)])

u = m_sequence(0o45, "00001")  # x^5 + x^2 + 1
print("u =", modes.bit_string(u), "(MATLAB comm.PNSequence: 1000010010110011111000110111010)")
assert modes.bit_string(u) == "1000010010110011111000110111010"
assert u.sum() == 16  # balance
r_auto = periodic_correlation(to_bipolar(u)[None, :])[0, 0]
assert r_auto[0] == 31 and set(r_auto[1:]) == {-1}  # two-valued autocorrelation
shifted_sum = u ^ np.roll(u, -7)
assert any(np.array_equal(shifted_sum, np.roll(u, -s)) for s in range(31))  # shift-and-add
print("autocorrelation values:", sorted(set(r_auto.tolist())))

# %% [markdown]
# ## 3. Preferred pairs and Gold codes: why three values
#
# For two different m-sequences $u, v$ of the same degree,
#
# $$ R_{uv}(\ell) = \sum_t (-1)^{u_t} (-1)^{v_{t+\ell}} = N - 2\,\mathrm{wt}(u \oplus T^\ell v). $$
#
# Write $v$ as a decimation of $u$, $v_t = u_{qt}$ (every m-sequence of degree $n$ is a decimation of
# any other, with $\gcd(q, N) = 1$). Then $R_{uv}(\ell) + 1$ is, up to sign, a value of the Walsh
# transform of the Boolean function $\mathrm{Tr}(x^q)$. Gold (1968) showed that for
# $q = 2^k + 1$ this transform takes only the values $0$ and $\pm 2^{(n+e)/2}$, where
# $e = \gcd(n,k)$: $e = 1$ for odd $n$, and $e = 2$ for $n \equiv 2 \pmod 4$. Such a pair is called
# **preferred**. Its cross-correlation takes only three values,
#
# $$ R_{uv}(\ell) \in \{-t(n),\; -1,\; t(n)-2\}, \qquad t(n) = 1 + 2^{\lfloor (n+2)/2 \rfloor} .$$
#
# For $n = 5$, $t = 9$ and the values are $\{-9, -1, 7\}$. For $n \equiv 0 \pmod 4$ no preferred pair
# exists. The **Gold family** of a preferred pair has $N+2 = 2^n+1$ members: $u$, $v$ and
# $u \oplus T^k v$ for $k = 0, \dots, N-1$. Any two members, and any member against a nonzero shift
# of itself, again correlate only in those three values. The reason is the same: each of those
# sums is again of the form $u' \oplus T^{m} v'$ for shifts $u'$ of $u$ and $v'$ of $v$, or is an
# m-sequence. So every member has off-peak correlations bounded by $t(n)$. That is about
# $\sqrt{2}$ times the Welch lower bound ($\approx \sqrt{N}$) for odd $n$.
#
# `motionsig encode pairs --degree 5` finds every preferred pair by testing all pairs of primitive
# polynomials with FFT cross-correlations. `motionsig encode check-pair` tests a given pair.

# %%
rows = []
for n in (3, 5, 6, 7, 9, 10):
    pairs = gold.preferred_pairs(n)
    a, b = pairs[0]
    idx, fam = gold.gold_family(a, b)
    fam = fam[:80]  # u, v and 78 members (the whole family for n <= 6); keeps the page build fast
    m = fam.shape[0]
    auto, cross = offpeak_counts(to_bipolar(fam))
    values = sorted(set(auto) | set(cross))
    t = gold_bound(n)
    assert values == [-t, -1, t - 2]  # the theorem, over the whole family
    rows.append(
        (n, len(pairs), f"{gf2.to_octal(a)}/{gf2.to_octal(b)}", m, values, round(math.sqrt(2**n - 1), 1))
    )
print(f"{'n':>2} {'pairs':>5} {'first pair':>11} {'checked':>7}  off-peak values        √N")
for n, npairs, pair, m, values, welch in rows:
    print(f"{n:>2} {npairs:>5} {pair:>11} {m:>7}  {values!s:<20} {welch}")

# %% [markdown]
# The three reciprocal pairs of degree 5 (45/51, 57/75, 67/73) decimate by $q = -1$. This $q$ is not of
# Gold's form, and these pairs are six-valued:

# %%
for a, b in [(0o45, 0o51), (0o57, 0o75), (0o67, 0o73)]:
    chk = gold.check_pair(a, b)
    print(f"{gf2.to_octal(a)}/{gf2.to_octal(b)}: {chk.values}  preferred={chk.preferred}")
    assert not chk.preferred and len(chk.values) == 6
assert gold.check_pair(0o45, 0o75).values == (-9, -1, 7)

# %% [markdown]
# ### The degree-10 reference: GPS C/A codes
#
# The GPS L1 C/A codes are the best-known Gold family. They are built from
# $G_1 = 1 + x^3 + x^{10}$ and $G_2 = 1 + x^2 + x^3 + x^6 + x^8 + x^9 + x^{10}$, with both
# registers starting all ones and a per-satellite G2 phase selector (IS-GPS-200). Their
# correlations take the values $\{-65, -1, 63\}$, since $t(10) = 65$. The first ten chips of each
# code, in octal, match the interface specification's table.

# %%
ca = gps.ca_codes(range(1, 33))
r = periodic_correlation(to_bipolar(ca))
off = np.concatenate([r[i, i, 1:] for i in range(32)] + [r[np.triu_indices(32, 1)].ravel()])
print("PRN 1-32 off-peak values:", sorted(set(off.tolist())))
print("first 10 chips (octal), PRN 1-10:", [gps.first_chips_octal(c) for c in ca[:10]])
assert sorted(set(off.tolist())) == [-65, -1, 63]
assert [gps.first_chips_octal(c) for c in ca[:10]] == [
    "1440",
    "1620",
    "1710",
    "1744",
    "1133",
    "1455",
    "1131",
    "1454",
    "1626",
    "1504",
]  # IS-GPS-200 Table 3-Ia

# %% [markdown]
# ## 4. Table I: three signatures, two of them misprinted
#
# The paper's Table I lists three 31-chip signatures ($n_\rho = 31 = 2^5 - 1$, so degree 5) for
# behaviours A, B and C, and calls them Gold codes. Mode 1 is exactly a member of the Gold family
# of MATLAB's default preferred pair, octal 45/75 ($x^5+x^2+1$, $x^5+x^4+x^3+x^2+1$). Modes 2 and 3
# are not members of any degree-5 Gold family: their correlations are not three-valued.
#
# We search all $33 \times 31$ members (every index, every cyclic start offset) of the 45/75 family
# for the member nearest each printed string, by edit distance with Hamming distance as the
# tie-break. The result:
#
# * mode 2 is one flipped chip (chip 15) away from a member;
# * mode 3 is two edits away: one '1' of a run of three is missing, and a spurious '0' is inserted
#   at chip 24. That is a slip, so the Hamming distance is 9 although only two characters are wrong.
#
# Each nearest member is unique. `motionsig encode table1` uses these corrected codes by default.
# `--codes printed` reproduces the strings as printed, and `--view errata` prints the comparison
# below.

# %%
printed = modes.printed_codes()
corrected = modes.corrected_codes()
for (mode, behaviour), p, near in zip(modes.modes(), printed, modes.nearest_members(printed), strict=True):
    print(f"mode {mode} ({behaviour})  printed   {modes.bit_string(p)}")
    print(
        f"              Gold k={near.index:>2},a={near.shift:>2} {modes.bit_string(near.code)}"
        f"  edit {near.edit_distance}, Hamming {near.hamming}, ties {near.ties}"
    )
    for op in modes.alignment(p, near.code):
        print("              ", op)
found = modes.nearest_members(printed)
assert [(f.index, f.shift) for f in found] == [(9, 8), (13, 13), (25, 12)]
assert [f.edit_distance for f in found] == [0, 1, 2] and all(f.ties == 1 for f in found)
assert np.array_equal(corrected[0], printed[0])

# %% [markdown]
# The correlations decide it. The corrected codes keep every off-peak value in $\{-9,-1,7\}$, as the
# theory of §3 says they must. The printed codes reach $|R| = 17$: nearly twice the Gold bound, and
# more than half the peak of 31.


# %%
# alt: Two histograms of the off-peak periodic correlations of the Table I codes: the corrected codes take only the values -9, -1 and 7 (within the dotted Gold bounds), the printed codes spread to ±17.
def offpeak(codes: np.ndarray) -> np.ndarray:
    rr = periodic_correlation(to_bipolar(codes))
    return np.concatenate([rr[i, i, 1:] for i in range(3)] + [rr[np.triu_indices(3, 1)].ravel()])


off_c, off_p = offpeak(corrected), offpeak(printed)
print("corrected: values", sorted(set(off_c.tolist())), " max |R| =", np.abs(off_c).max())
print("printed:   values", sorted(set(off_p.tolist())), " max |R| =", np.abs(off_p).max())
assert sorted(set(off_c.tolist())) == [-9, -1, 7]
assert np.abs(off_p).max() == 17 > gold_bound(5)

fig = Figure(figsize=(8, 3.2), layout="constrained")
ax = fig.subplots(1, 2, sharey=True)
bins = np.arange(-18.5, 19.5, 1)
ax[0].hist(off_c, bins=bins, color="C0")
ax[0].set_title("corrected Table I codes")
ax[1].hist(off_p, bins=bins, color="C3")
ax[1].set_title("printed Table I codes")
for a in ax:
    a.axvline(-9, color="k", ls=":", lw=0.8)
    a.axvline(7, color="k", ls=":", lw=0.8)
    a.set_xlabel("off-peak periodic correlation")
ax[0].set_ylabel("count (auto + cross, all lags)")
fig

# %% [markdown]
# ## 5. Summary
#
# | claim | check on this page |
# |---|---|
# | chip index $\lfloor (k-\tau)/m_\rho \rfloor \bmod n_\rho$, quadrature identity, code period | §1 |
# | $\varphi(2^n-1)/n$ primitive polynomials; balance, shift-and-add, two-valued autocorrelation | §2 |
# | Gold families three-valued $\{-t(n), -1, t(n)-2\}$ for $n = 3, 5, 6, 7, 9, 10$; reciprocal pairs are not | §3 |
# | GPS C/A: IS-GPS-200 octal prefixes and $\{-65, -1, 63\}$ | §3 |
# | Table I mode 1 is Gold member $(k, a) = (9, 8)$; modes 2, 3 corrected to $(13, 13)$ and $(25, 12)$ | §4 |
#
# The test suite checks the same facts against independent oracles: MATLAB vectors,
# IS-GPS-200's G2 delay table, Berlekamp–Massey linear complexity, and Gold's decimation theorem.
