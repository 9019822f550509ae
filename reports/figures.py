"""Figures written by the commands (matplotlib, no display needed)."""

from __future__ import annotations

import io

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from massline.placement.files import claim_output, write_atomic_bytes  # noqa: E402
from massline.placement.lines import Lines  # noqa: E402
from massline.placement.masslines import synthesise  # noqa: E402
from massline.virtual.band import frequency_axis  # noqa: E402


def driving_point_figure(path, cases: list, exciters: Lines, force: bool = False) -> None:
    """Predicted driving-point accelerances |H_jj(f)| at every hit, with each case's band shaded.

    ``cases`` holds (label, SuspendedBody, Band). The massline of each hit is drawn as a dotted
    level: inside the band the curves sit on it.
    """
    claim_output(path, force)
    fig, axes = plt.subplots(len(cases), 1, figsize=(8, 3.2 * len(cases)), sharex=True, squeeze=False)
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
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=110)
    plt.close(fig)
    write_atomic_bytes(path, buffer.getvalue(), force)
