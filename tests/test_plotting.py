"""Readability of the figures: no text cut off at the figure's edge, no two texts on top of each other, no
legend over the data. Each check is made with matplotlib's own renderer (``get_window_extent`` after a
draw), on the figure builders fed the inputs of the commands whose figures were found unreadable
(``encode gps --prn 1-3 | encode correlations - --plot``, the 2-D ``detect --plot``, ``slrt --plot``,
``encode signature --plot``, ``track-sat psi --plot``, ``slrt --plot-scan``)."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from motionsig_cli import plotting

TOL = 1.0  # px: a text may touch the edge, or another text, by a pixel (antialiasing) and no more


def _draw(fig: Figure):
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def _texts(fig: Figure, renderer) -> list[tuple[str, Bbox]]:
    """Every drawn, non-empty text with its window extent: titles, labels, annotations, legend entries and
    the tick labels of the ticks inside each axis's view."""
    out: list[tuple[str, Bbox]] = []
    ticks: set[int] = set()
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
            lo, hi = sorted(lim)
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                for lab in (tick.label1, tick.label2):
                    ticks.add(id(lab))
                    loc = tick.get_loc()
                    if loc is None or not (lo - 1e-12 * abs(hi - lo) <= loc <= hi + 1e-12 * abs(hi - lo)):
                        continue
                    if lab.get_visible() and tick.get_visible() and lab.get_text():
                        out.append((f"tick {lab.get_text()!r}", lab.get_window_extent(renderer)))
    for t in fig.findobj(Text):
        if id(t) in ticks or not t.get_text().strip() or not t.get_visible():
            continue
        if not all(a.get_visible() for a in _ancestors(t)):
            continue
        out.append((repr(t.get_text()), t.get_window_extent(renderer)))
    return out


def _ancestors(t: Text) -> list:
    axes = t.axes
    return [axes] if axes is not None else []


def clipped_texts(fig: Figure, renderer=None) -> list[str]:
    renderer = renderer or _draw(fig)
    w, h = fig.bbox.width, fig.bbox.height
    return [
        name
        for name, bb in _texts(fig, renderer)
        if bb.x0 < -TOL or bb.y0 < -TOL or bb.x1 > w + TOL or bb.y1 > h + TOL
    ]


def overlapping_texts(fig: Figure, renderer=None) -> list[tuple[str, str]]:
    renderer = renderer or _draw(fig)
    items = _texts(fig, renderer)
    bad = []
    for i, (na, a) in enumerate(items):
        for nb, b in items[i + 1 :]:
            dx = min(a.x1, b.x1) - max(a.x0, b.x0)
            dy = min(a.y1, b.y1) - max(a.y0, b.y0)
            if dx > TOL and dy > TOL:
                bad.append((na, nb))
    return bad


def points_under_legends(fig: Figure, renderer=None) -> int:
    """The data vertices (lines and markers of the axes, not the legend's own handles, not reference lines
    drawn across the whole axes) that fall inside a legend box of their axes."""
    renderer = renderer or _draw(fig)
    n = 0
    for ax in fig.axes:
        legends = [c for c in ax.get_children() if isinstance(c, Legend)]
        if not legends:
            continue
        box = legends[0].get_window_extent(renderer)
        clip = ax.bbox
        for line in ax.get_lines():
            if not isinstance(line, Line2D) or not line.get_visible():
                continue
            xy = line.get_transform().transform(np.column_stack(line.get_data()).astype(float))
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            inside_ax = (
                (xy[:, 0] >= clip.x0) & (xy[:, 0] <= clip.x1) & (xy[:, 1] >= clip.y0) & (xy[:, 1] <= clip.y1)
            )
            under = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
            n += int(np.count_nonzero(inside_ax & under))
    return n


def assert_readable(fig: Figure, *, legend_free: bool = True) -> None:
    renderer = _draw(fig)
    assert clipped_texts(fig, renderer) == []
    assert overlapping_texts(fig, renderer) == []
    if legend_free:
        assert points_under_legends(fig, renderer) == 0


# ------------------------------------------------------------------------------------ the checks themselves
def test_checks_catch_what_they_should() -> None:
    """The three checks fail on a figure built to fail them, so that their passing below means something."""
    fig = Figure(figsize=(3, 2))
    ax = fig.add_subplot()
    ax.plot(np.linspace(0, 1, 50), np.linspace(1, 0, 50), label="a line under its own legend")
    ax.legend(loc="upper left")
    ax.set_title("a title far too long for a figure three inches wide, cut at both ends")
    ax.annotate("one", (0.5, 0.5), xycoords="axes fraction")
    ax.annotate("one", (0.5, 0.5), xycoords="axes fraction")
    assert clipped_texts(fig)
    assert overlapping_texts(fig)
    assert points_under_legends(fig) > 0


# ------------------------------------------------------------------------------- the defects, one by one
def test_correlations_of_three_gps_codes_one_panel_per_pair() -> None:
    """`encode gps --prn 1-3 | encode correlations - --plot`: 1023 lags × 6 pairs, once one unreadable block.
    Now one panel per pair, the side lobes at −65, −1, 63 visible (the limits stay within 1.5 t(n) = 97.5)
    and the cut autocorrelation peak R[0] = 1023 written in its panel."""
    from motionsig_cli.signals.code_sets import CodeSet, correlation_curves
    from motionsig_cli.signals.gps import ca_codes

    codes = CodeSet(["PRN1", "PRN2", "PRN3"], 1 - 2 * ca_codes([1, 2, 3]).astype(np.int64), {})  # bits → ±1
    lags, values, labels, bound = correlation_curves(codes)
    assert values.shape == (6, 1023) and bound == 65
    fig = plotting.correlation_figure(lags, values, labels, bound)
    assert len(fig.axes) == 6
    for ax in fig.axes:
        lo, hi = ax.get_ylim()
        assert -100 < lo < -65 and 63 < hi < 100
    notes = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert notes.count("R[0] = 1023 (off scale)") == 3
    assert_readable(fig)


def test_statistic_title_of_the_2d_example_is_wrapped() -> None:
    """The 2-D `detect --plot` title ("horizon 30 s, R_range = …, R_bearing = …, c_r = 100") was cut."""
    title = "horizon 30 s, R_range = 3.06e-07, R_bearing = 5e-06, c_r = 100"
    rng = np.random.default_rng(0)
    lam = rng.normal(-4.0, 0.3, size=(3, 31))
    lam[2, 7] = -2.1
    fig = plotting.statistic_figure([(title, lam, (2, 7))], 3, np.arange(31.0))
    assert "c_r = 100" in fig.axes[0].get_title()
    assert_readable(fig)


def test_slrt_threshold_labels_apart() -> None:
    """slrt's "log B (confirm)" and "log A (delete)" overprinted wherever the panel's scale is large."""
    from motionsig_cli.existence.slrt import SlrtStudy

    thresholds = SlrtStudy().thresholds  # Wald's (log A, log B) = (−2.30, 6.80) at α = 1e-3, β = 0.1
    k = np.arange(1, 31.0)
    panels = []
    for title, slope in (("target, p_D = 0.9", 31.0), ("target, p_D = 0.5", 16.0), ("no target", -14.0)):
        mean = slope * k
        panels.append(
            (
                title,
                k,
                {"ckf": (mean, mean - 20.0, mean + 20.0), "lkf": (mean / 4, mean / 4 - 5, mean / 4 + 5)},
            )
        )
    fig = plotting.slrt_figure(panels, thresholds)
    assert_readable(fig)


def test_signature_legend_clear_of_the_waveform() -> None:
    """`encode signature --mode 1 --theta random --seed 7 --plot`: the legend covered z_k."""
    from motionsig_cli.signals.code_sets import resolve_theta, signature_table
    from motionsig_cli.signals.signature import SignatureConfig

    _, sig = signature_table(1, "corrected", SignatureConfig(), seed=7, theta_option="random")
    fig = plotting.signature_figure(sig, title="Mode 1 signature", theta=resolve_theta("random", 7))
    assert_readable(fig)


def test_psi_labels_inside_the_axes() -> None:
    """`track-sat psi --plot`: the "II, σ0=5" label at ψ ≈ 0.04 ran below the axes."""
    from motionsig_cli.atc10.satellite_tracking import PsiConfig, psi_report

    fig = plotting.psi_figure(**psi_report(PsiConfig()).figure)
    labels = [t for t in fig.axes[0].texts if t.get_text().startswith("II, σ0=5")]
    assert labels
    renderer = _draw(fig)
    box = fig.axes[0].bbox
    for t in fig.axes[0].texts:
        bb = t.get_window_extent(renderer)
        assert box.y0 - TOL <= bb.y0 and bb.y1 <= box.y1 + TOL, t.get_text()
    assert_readable(fig)


def test_slrt_scan_legend_hides_no_point() -> None:
    """`slrt --plot-scan`: the legend in the upper left hid a clutter point; now it sits below the plane."""
    sensors = np.array([[13e3, 0.0], [0.0, 13e3], [-13e3, 0.0], [0.0, -13e3]])
    rng = np.random.default_rng(3)
    clutter = [rng.uniform(-28e3, 28e3, size=(6, 2)) for _ in range(4)]
    clutter[1][0] = (-10.5e3, 16.3e3)  # where the legend was
    target = [np.array([[4.4e3, 1.0e3]]) for _ in range(4)]
    truth = np.column_stack([np.linspace(0, 4.4e3, 30), np.zeros(30), np.linspace(0, 1e3, 30), np.zeros(30)])
    fig = plotting.slrt_scan_figure(sensors, clutter, target, truth, "target, p_D = 0.9: run 0, scan 30")
    assert_readable(fig)


def _jamming(figure: str) -> Figure:
    from motionsig_cli.atc10.jamming import CurvesConfig, curves_table

    result = curves_table(CurvesConfig(figure=figure))
    return plotting.jamming_figure(result.panels, title=result.title)


def test_jamming_rise_of_a_few_db_gets_a_zoom_clear_of_the_curves() -> None:
    """`jam-bound curves --figure 2.11`: the curves rose within 4 dB of a 105 dB axis, drawn on top of each
    other; an inset now shows that span, placed where it covers none of the panel's rising curves."""
    fig = _jamming("2.11")
    ax = fig.axes[0]
    assert len(ax.child_axes) == 1
    ins = ax.child_axes[0]
    renderer = _draw(fig)
    box = ins.get_tightbbox(renderer)
    lo, hi = ins.get_xlim()
    y_floor = ax.get_ylim()[0]
    for line in ax.get_lines():
        x, y = (np.asarray(v, float) for v in line.get_data())
        if x.size < 3:
            continue  # a reference level
        rising = (y > y_floor) & (y < 0.95 * np.max(y))
        assert np.all((x[rising] >= lo) & (x[rising] <= hi))  # the whole rise is in the zoom
        xy = line.get_transform().transform(np.column_stack([x, y]))
        under = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
        assert not np.any(under & rising)
    assert_readable(fig)


def test_jamming_spread_curves_get_no_zoom() -> None:
    """Fig. 2.12 spreads its curves over 40 dB: no inset."""
    fig = _jamming("2.12")
    assert fig.axes[0].child_axes == []
    assert_readable(fig)


def test_response_legend_outside_the_curves() -> None:
    """`simulate --plot` (Fig 2 of the mode-signature paper): the legend at 'best' sat on the response,
    which fills the plane; now it is above the axes."""
    t = np.arange(0, 60, 0.05)
    r = 10 * np.sin(2 * np.pi * 0.1 * t)
    x = r + 0.5 * np.sin(2 * np.pi * t)
    fig = plotting.response_figure(t, x, r, x, x + 0.1)
    renderer = _draw(fig)
    (leg,) = fig.legends
    assert not leg.get_window_extent(renderer).overlaps(fig.axes[0].get_window_extent(renderer))
    assert_readable(fig)
