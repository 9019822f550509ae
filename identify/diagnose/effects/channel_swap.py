"""``channel_swap``: two channels' labels exchanged (``channel_swap@I,J``).

Simulated: recorded channel I holds sensor J's signal and J holds I's. Diagnosed as a discrete fix, as a
flipped polarity is (:mod:`..diagnosis`), unless one of the two accelerometers moved on its face explains
the data as well; undone by exchanging the two channels' FRFs back.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect, need


class ChannelSwap(Effect):
    name = "channel_swap"
    summary = "two channels' labels exchanged (@I,J)"
    discrete = True
    model = "discrete"
    lines_needed = 2

    @classmethod
    def syntax(cls):
        return f"{cls.name}@I,J"

    @classmethod
    def check_place(cls, where):
        need(isinstance(where, tuple) and len(where) == 2, "channel_swap needs the two channels: channel_swap@I,J")

    def simulate(self, state, lines, targets, rng):
        i, j = targets
        state.channel_order[[i, j]] = state.channel_order[[j, i]]
        return {}

    @classmethod
    def undo_rows(cls, frf, channels):
        i, j = channels
        frf[[i, j]] = frf[[j, i]]

    @classmethod
    def proposals(cls, n_channels):
        return [(i, j) for i in range(n_channels) for j in range(i + 1, n_channels)]

    @classmethod
    def sentence(cls, finding, who, hit):
        return f"{who} are swapped: each channel reads what the other should; corrected"

    @classmethod
    def concealed(cls, size, scene):
        return f"channels {scene.sensors[0]} and {scene.sensors[-1]} are swapped"

    @classmethod
    def located(cls, finding, channels, hit):
        return set(finding.channels) == set(channels)
