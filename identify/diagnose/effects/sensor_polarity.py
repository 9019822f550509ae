"""``sensor_polarity``: a channel wired with its sign flipped.

Simulated: the channel's reading × −1. Diagnosed as a discrete fix (it breaks any linearisation): proposed by the
rigid-subspace screen (:mod:`..screens`), kept when the refit's BIC says so (:mod:`..diagnosis`); undone by
flipping the channel's FRFs back.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect


class SensorPolarity(Effect):
    name = "sensor_polarity"
    summary = "reading sign flipped"
    discrete = True
    model = "discrete"

    def simulate(self, state, lines, targets, rng):
        for t in targets:
            state.sensor_vectors[t] *= -1
        return {}

    @classmethod
    def undo_rows(cls, frf, channels):
        frf[list(channels)] *= -1

    @classmethod
    def proposals(cls, n_channels):
        return [(k,) for k in range(n_channels)]

    @classmethod
    def sentence(cls, finding, who, hit):
        return f"{who} has its polarity flipped: its readings are the rigid body's with the opposite sign; corrected"

    @classmethod
    def concealed(cls, size, scene):
        return f"sensor {scene.sensor} is wired with its polarity flipped"
