"""The identification report's plots: representative FRFs with the band and the massline, and the fit."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from massline.identify.diagnose.screens import driving_points
from massline.core.lines import Lines
from massline.reports.figures import png_bytes

WIDTH_IN = 7.3  # inches: the A4 page's printable width at the report's margins
STYLES = ("-", "--", ":")  # of the levels drawn, in order
LEGEND_IN = 0.3  # inches above the panels for the legend


def representative(sensors: Lines, exciters: Lines, values: np.ndarray, count: int = 6, first=()) -> list:
    """(i, j) pairs worth showing: ``first``, then up to three driving points, then the largest masslines
    ``values`` (n_s, n_e), one per sensor as long as there are sensors left."""
    picks = list(dict.fromkeys(first))[:count]
    for pair in driving_points(sensors, exciters)[:3]:
        if len(picks) < count and pair not in picks:
            picks.append(pair)
    order = [tuple(int(v) for v in np.unravel_index(k, values.shape)) for k in np.argsort(-np.abs(values), None)]
    for distinct in (True, False):
        for i, j in order:
            if len(picks) >= count:
                return picks
            if (i, j) not in picks and not (distinct and i in {p[0] for p in picks}):
                picks.append((i, j))
    return picks


def _limits(real: np.ndarray, inside: np.ndarray, levels: list[float]) -> tuple[float, float]:
    """y-limits showing the band's curve and the levels whole; resonances outside the band may leave them. Lines
    an FRF lacks (NaN: not measured there, or left out as the support's) and a pair with no level are passed over."""
    shown = np.concatenate([real[inside], levels])
    shown = shown[np.isfinite(shown)]
    if not len(shown):
        return -1.0, 1.0
    lo, hi = float(shown.min()), float(shown.max())
    pad = max(0.6 * (hi - lo), 0.25 * max((abs(v) for v in levels if np.isfinite(v)), default=0.0), 1e-12)
    return lo - pad, hi + pad


def frf_figure(
    frequencies: np.ndarray,
    frf: np.ndarray,
    band: tuple[float, float],
    picks: list,
    sensors: list[str],
    hits: list[str],
    levels: dict,
    resonances: tuple = (),
    notes: dict | None = None,
) -> bytes:
    """PNG: Re H of each picked FRF (i, j) against frequency (log), the band shaded and each of ``levels``
    (name → (n_s, n_e) masslines, (m/s²)/N) drawn as a level across the band and dotted beyond it;
    ``resonances`` (Hz, nan for none) as vertical lines; ``notes`` ((i, j) → text) under each title."""
    keep = frequencies > 0
    f, H = frequencies[keep], frf[:, :, keep]
    rows = (len(picks) + 1) // 2
    height = 2.2 * rows + LEGEND_IN
    fig = Figure(figsize=(WIDTH_IN, height))
    axes = fig.subplots(rows, 2, squeeze=False)
    inside = (f >= band[0]) & (f <= band[1])
    for ax, (i, j) in zip(axes.flat, picks):
        real = H[i, j].real
        ax.semilogx(f, real, color="0.25", lw=0.9, label="recorded, Re H")
        ax.axvspan(*band, color="tab:green", alpha=0.12, label="band used")
        for (name, values), style in zip(levels.items(), STYLES):
            level = float(values[i, j])
            (line,) = ax.plot(band, [level, level], style, lw=1.6, label=name)
            ax.axhline(level, color=line.get_color(), ls=":", lw=0.7)
        for r in resonances:
            if np.isfinite(r):
                ax.axvline(r, color="0.5", ls="-.", lw=0.7)
        ax.set_ylim(*_limits(real, inside, [float(v[i, j]) for v in levels.values()]))
        ax.set_xlim(f[0], f[-1])
        title = f"{sensors[i]} / {hits[j]}"
        if notes and (i, j) in notes:
            title += f"\n{notes[i, j]}"
        ax.set_title(title, fontsize=7.5)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3, which="both")
    for ax in axes.flat[len(picks) :]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("frequency (Hz)", fontsize=8)
    for ax in axes[:, 0]:
        ax.set_ylabel("Re H ((m/s²)/N)", fontsize=8)
    handles, names = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, names, loc="upper center", ncol=len(names), fontsize=7, frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - LEGEND_IN / height))
    return png_bytes(fig)


def fit_figure(measured: np.ndarray, std: np.ndarray, model: np.ndarray, sensors: list[str], hits: list[str]) -> bytes:
    """PNG: every measured massline against the identified body's (with its 1-σ), and the residual in σ over
    sensors × hits."""
    fig = Figure(figsize=(WIDTH_IN, 0.16 * len(sensors) + 2.4))
    left, right = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.1, 1]})
    left.errorbar(model.ravel(), measured.ravel(), yerr=std.ravel(), fmt="o", ms=3, lw=0.8, color="tab:blue")
    span = [min(model.min(), measured.min()), max(model.max(), measured.max())]
    left.plot(span, span, "k--", lw=0.8, label="equal")
    left.set_xlabel("identified body's massline ((m/s²)/N)", fontsize=8)
    left.set_ylabel("measured massline ((m/s²)/N)", fontsize=8)
    left.set_title("each FRF's massline, measured against the identified body", fontsize=8)
    left.tick_params(labelsize=7)
    left.legend(fontsize=7)
    left.grid(alpha=0.3)
    z = (measured - model) / std
    top = max(3.0, float(np.abs(z).max()))
    image = right.imshow(z, cmap="RdBu_r", vmin=-top, vmax=top, aspect="auto")
    right.set_xticks(range(len(hits)), hits, rotation=90, fontsize=6.5)
    right.set_yticks(range(len(sensors)), sensors, fontsize=6.5)
    right.set_title("(measured − identified) / 1-σ of the band fit", fontsize=8)
    fig.colorbar(image, ax=right, shrink=0.85).ax.tick_params(labelsize=7)
    fig.tight_layout()
    return png_bytes(fig)
