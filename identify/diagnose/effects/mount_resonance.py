"""``mount_resonance``: an accelerometer read through its mount's resonance at f_m (wax, a magnet base, a thick
adhesive): every FRF of its row times 1/(1 − (f/f_m)² + 2iζ f/f_m).

Simulated: the channel's row times that factor, ζ = ``DAMPING``. Each FRF's Cω² + Dω⁴ tail takes up the rise in its
massline fit, so the masslines barely show it; the whole row rising together, by one f_m, does. The diagnosis
fits f_m on the band's lines of the row jointly with the rigid motion at every line
(:mod:`massline.identify.diagnose.row_factors`), ζ taken as ``DAMPING``; undone by dividing the row by the factor.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import RowEffect, need, pm
from massline.core.numbers import formatted

DAMPING = 0.05  # ζ of a mount's resonance (wax and adhesives: a few per cent of critical)
HIGHEST = 1e5  # Hz: a stud-mounted accelerometer's resonance is tens of kHz; no mount is stiffer


class MountResonance(RowEffect):
    name = "mount_resonance"
    unit = "Hz"
    summary = (f"read through its mount's resonance at f_m: every FRF of the channel ÷ (1 − (f/f_m)² + 2iζf/f_m), "
               f"ζ {DAMPING}")  # fmt: skip
    parameter = "mount_hz"
    signature = "rising"
    blind_range = (2.0, 4.0)  # f_m / the planned band's upper edge: a rise of 6–33 % there

    @classmethod
    def check_size(cls, size):
        need(0 < size <= HIGHEST, f"effect {cls.name}: the mount's resonance must lie in (0, {HIGHEST:g}] Hz, "
             f"not {size:g} Hz")  # fmt: skip

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        return float(rng.uniform(*cls.blind_range) * band[1])

    @classmethod
    def factor(cls, frequencies, value):
        u = np.asarray(frequencies) / value
        return 1 / (1 - u**2 + 2j * DAMPING * u)

    @classmethod
    def search_range(cls, top):
        return 1.05 * top, 100 * top, True

    @classmethod
    def row_parameters(cls, value, sigma):
        return {**super().row_parameters(value, sigma), "damping": DAMPING}

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        top = p.get("top_hz", np.nan)
        rise = abs(cls.factor(top, p["mount_hz"])) - 1 if np.isfinite(top) else np.nan
        at_top = f", {formatted(100 * rise, '+.1f')} % at {top:.0f} Hz" if np.isfinite(rise) else ""
        return (
            f"{who} is read through a mount resonating at {pm(p['mount_hz'], p['mount_hz_std'])} Hz (ζ "
            f"{p['damping']:g} taken{at_top}): check its wax, magnet base or adhesive; undone on its FRFs"
            f"{cls.lines_fit(finding)}"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"sensor {scene.sensor} sits on a soft mount resonating at {size:.0f} Hz (wax, a magnet, thick glue)"
