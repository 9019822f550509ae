"""The diagnosis in pictures: residual maps over sensors × hits, and FRF overlays, before and after."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from massline.identify.diagnose.diagnosis import Diagnosis
from massline.identify.recording_noise import RecordingNoise
from massline.identify.tails import BandData, tail_columns
from massline.reports.figures import png_bytes


def diagnosis_figure(
    result: Diagnosis,
    recorded: BandData,
    noise: RecordingNoise,
    sensors: list[str],
    hits: list[str],
    off_rigid=None,
    grid: bool = False,
) -> bytes:
    """PNG bytes: per-FRF relative RMS residual (in units of its ``noise``, the recording's) before and after, the
    worst FRF as recorded (and as corrected for flips and swaps) with both models, and (``off_rigid``, (n_s, n_f))
    how far each recorded channel sits from the rigid motions over the band. The panels stand in a row, or with
    ``grid`` the maps above the curves, a page wide."""
    band = result.band
    own = np.sqrt(2 * noise.lines * noise.sigma**2 / band.energy)  # each FRF's own noise, relative
    own = np.maximum(own, 1e-12)  # a noiseless recording's: the residuals at the numbers' precision
    maps = [np.sqrt(fit.rss / band.energy) / own for fit in (result.before, result.after)]
    panels = 3 if off_rigid is None else 4
    if grid:
        fig = Figure(figsize=(8.6, 0.2 * len(sensors) + 5.5))
        layout = fig.add_gridspec(2, 2, height_ratios=[0.2 * len(sensors) + 1.5, 3.2], hspace=0.45)
        bottom = [layout[1, :]] if off_rigid is None else [layout[1, 0], layout[1, 1]]
        axes = [fig.add_subplot(cell) for cell in [layout[0, 0], layout[0, 1], *bottom]]
    else:
        fig = Figure(figsize=(4.3 * panels, 0.25 * len(sensors) + 3))
        axes = fig.subplots(1, panels, gridspec_kw={"width_ratios": [1, 1, 2, 2][:panels]})
    top = max(float(maps[0].max()), 2.0)
    for ax, values, title in zip(axes[:2], maps, ("before", "after")):
        image = ax.imshow(values, cmap="magma_r", vmin=0, vmax=top, aspect="auto")
        ax.set_xticks(range(len(hits)), hits, rotation=90, fontsize=7)
        ax.set_yticks(range(len(sensors)), sensors, fontsize=7)
        ax.set_title(f"residual / noise, {title}", fontsize=9)
    fig.colorbar(image, ax=axes[:2], shrink=0.8)
    i, j = np.unravel_index(np.argmax(maps[0]), maps[0].shape)
    f = band.frequencies
    ax = axes[2]
    ax.plot(f, recorded.frf[i, j].real, color="0.3", lw=0.8, label="recorded (real part)")
    if result.fixes:
        ax.plot(f, band.frf[i, j].real, color="0.6", lw=0.8, ls=":", label="with flips and swaps undone")
    for fit, style, name in ((result.before, "--", "model before"), (result.after, "-", "model after")):
        level = fit.masslines[i, j]
        tails = fit.problem.data.tails[i, j]
        ax.plot(f, _with_tails(f, level, tails, fit.problem.data.poles), style, lw=1.4, label=name)
    ax.set_title(f"worst FRF before: {sensors[i]} / {hits[j]}", fontsize=9)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("Re H ((m/s²)/N)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    if off_rigid is not None:
        ax = axes[3]
        for k in np.argsort(np.median(off_rigid, axis=1))[::-1][:5]:
            ax.semilogy(f, off_rigid[k], lw=1.0, label=str(sensors[k]))
        ax.semilogy(f, np.median(off_rigid, axis=0), "k--", lw=1.0, label="median channel")
        ax.set_title("recorded: distance from the rigid motions (model-free)", fontsize=9)
        ax.set_xlabel("frequency (Hz)")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, which="both")
    return png_bytes(fig, bbox_inches="tight")


def _with_tails(frequencies: np.ndarray, level: float, tails: np.ndarray, poles: dict) -> np.ndarray:
    """The model's real part over the band: the massline plus its tail laws (as fitted)."""
    X = tail_columns(2 * np.pi * frequencies, poles)[: len(frequencies)]
    return level + (X @ tails if X.shape[1] else np.zeros(len(frequencies)))
