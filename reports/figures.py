"""Figures as PNG bytes (matplotlib's object API: no display, no global state); the simulator's band check."""

from __future__ import annotations

import io

import numpy as np
from matplotlib.figure import Figure

from massline.core.lines import Lines
from massline.core.masslines import synthesise
from massline.virtual.band_prediction import frequency_axis


def png_bytes(fig: Figure, **options) -> bytes:
    """The figure as PNG bytes (110 dpi), through matplotlib's object API: no pyplot, no global backend."""
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110, **options)
    return buffer.getvalue()


def driving_point_figure(cases: list, exciters: Lines) -> bytes:
    """PNG: predicted driving-point accelerances |H_jj(f)| at every hit, with each case's band shaded.

    ``cases`` holds (label, SuspendedBody, Band). The massline of each hit is drawn as a dotted
    level: inside the band the curves sit on it.
    """
    fig = Figure(figsize=(8, 3.2 * len(cases)))
    axes = fig.subplots(len(cases), 1, sharex=True, squeeze=False)
    f = frequency_axis(cases[0][1], points=800)
    for ax, (label, model, band) in zip(axes[:, 0], cases):
        H = model.accelerance(f, exciters.points, exciters.directions, exciters.points, exciters.directions)
        ideal = synthesise(model.loaded, exciters, exciters).values
        for j in range(len(exciters)):
            (line,) = ax.loglog(f, np.abs(H[j, j]), lw=1.2, label=f"hit {j + 1}")
            ax.axhline(abs(ideal[j, j]), color=line.get_color(), ls=":", lw=0.8)
        if band.exists:
            ax.axvspan(band.low, min(band.high, f[-1]), color="tab:green", alpha=0.12, label="massline band")
        ax.axvline(band.suspension_top, color="0.4", ls="--", lw=0.8)
        if np.isfinite(band.first_elastic):
            ax.axvline(band.first_elastic, color="0.4", ls="-.", lw=0.8)
        ax.set_title(label, fontsize=9)
        ax.set_ylabel("|H_jj| ((m/s²)/N)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=4, loc="lower right")
    axes[-1, 0].set_xlabel("frequency (Hz); dashed: top suspension mode, dash-dot: first elastic mode")
    fig.tight_layout()
    return png_bytes(fig)
