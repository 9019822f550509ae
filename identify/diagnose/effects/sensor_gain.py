"""``sensor_gain``: a channel reading (1 + g) times what it should (a wrong sensitivity in the channel table).

Simulated: the channel's reading scaled by (1 + ``size``). Diagnosed: one value g per channel, s_i → (1 + g) s_i
(mismatch notes §3 B); once named, the gain stated is the channel's factor on identify's objective
(:func:`massline.identify.diagnose.undone.by_identify`), and the channel's FRFs are divided by it.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Block, Effect, block_values, need, pm
from massline.core.numbers import formatted, signed, value_with_sigma


class SensorGain(Effect):
    name = "sensor_gain"
    unit = "fraction"
    summary = "reading scaled by (1 + g)"
    moves = "gain"
    rank = 1
    blind_range = (0.05, 0.3)  # either sign

    @classmethod
    def check_size(cls, size):
        super().check_size(size)
        need(-0.9 < size < 10.0, f"effect {cls.name}: a reading (1 + g) of {1 + size:g} times the true one is no "
             "sensitivity a channel table holds: give −0.9 < g < 10 (sensor_polarity flips a sign)")  # fmt: skip

    def simulate(self, state, lines, targets, rng):
        for t in targets:
            state.sensor_vectors[t] *= 1 + self.size
        return {}

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        size = float(rng.uniform(*cls.blind_range))
        return size * rng.choice([-1.0, 1.0])

    @classmethod
    def blocks(cls, layout):
        return [Block(cls.name, i) for i in range(len(layout.sensors))]

    @classmethod
    def values(cls, layout, target):
        return 1

    @classmethod
    def channels(cls, layout, target):
        return [target]

    @classmethod
    def displace(cls, lines, layout, target, v):
        lines.gains[[target]] *= 1 + v[0]

    @classmethod
    def plausible(cls, result, block, v, tau):
        return -0.9 < v[0] < 10.0

    @classmethod
    def parameters(cls, result, block):
        v, sigma, _ = block_values(result, block)
        return {"gain": float(1 + v[0]), "gain_std": float(sigma[0])}

    @classmethod
    def correct(cls, frf, sensors, exciters, finding):
        """The channel's FRFs ÷ its gain."""
        frf[list(finding.channels)] /= finding.parameters["gain"]
        return frf, sensors, exciters

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"{who} reads {signed(value_with_sigma(100 * (p['gain'] - 1), 100 * p['gain_std'])[0])} % of what it "
            f"should (gain {pm(p['gain'], p['gain_std'])}): check its sensitivity in the channel table"
        )

    @classmethod
    def concealed(cls, size, scene):
        percent = formatted(100 * size, "+.1f")
        return f"sensor {scene.sensor} reads {percent} % of what it should (its sensitivity is wrong)"
