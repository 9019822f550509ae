"""``channel_delay``: a channel read late by τ, e^{−iωτ} on every FRF of its row (front ends out of sync, anti-alias
filters that differ).

Simulated: the channel's row times e^{−2πifτ}. Its masslines barely show it (the real part falls by (ωτ)²/2, which
each FRF's Cω² tail takes up), but a massline is real: the phase −2πfτ on every FRF of one row is the chain's. The
diagnosis fits τ on the band's lines of the row jointly with the rigid motion at every line
(:mod:`massline.identify.diagnose.row_factors`); undone by multiplying the row by e^{2πifτ}.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import RowEffect, need, pm
from massline.core.numbers import formatted

LONGEST = 1e-2  # s: a lag beyond 10 ms is no front end's (a 5 s "delay" is a typing error)


class ChannelDelay(RowEffect):
    name = "channel_delay"
    unit = "s"
    summary = "reading delayed by τ: every FRF of the channel times e^(−iωτ)"
    parameter = "delay_s"
    signature = "phase_linear"
    blind_range = (60e-6, 200e-6)  # two front ends' sample clocks, or anti-alias filters of different order

    @classmethod
    def check_size(cls, size):
        need(0 < abs(size) <= LONGEST, f"effect {cls.name}: a delay must be non-zero and within ±{LONGEST:g} s "
             f"(a front end's lag), not {size:g} s")  # fmt: skip

    @classmethod
    def factor(cls, frequencies, value):
        return np.exp(-2j * np.pi * np.asarray(frequencies) * value)

    @classmethod
    def search_range(cls, top):
        return -0.25 / top, 0.25 / top, False  # up to a quarter period at the band's top: phase within ±90°

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        top = p.get("top_hz", np.nan)
        phase = f" ({formatted(-360 * top * p['delay_s'], '+.1f')}° at {top:.0f} Hz)" if np.isfinite(top) else ""
        return (
            f"{who} lags the others by {pm(1e6 * p['delay_s'], 1e6 * p['delay_s_std'])} µs{phase}: a front end out "
            f"of sync or an anti-alias filter that differs; undone as e^(iωτ) on its FRFs{cls.lines_fit(finding)}"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"sensor {scene.sensor} is read {1e6 * size:.0f} µs late (its front end lags the others')"
