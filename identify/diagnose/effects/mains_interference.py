"""``mains_interference``: a ground loop's mains hum on the response channels (test physics).

Simulated as an additive disturbance of every response channel (:mod:`massline.virtual.hum`): the fundamental
(50 or 60 Hz) and its harmonics, the odd ones dominant, each a narrow line with the mains' phase, not the FRF's,
the coherence dropping there. Found by identify as lines at multiples of one frequency that stand out of most
FRFs (:mod:`massline.identify.mains`) and set aside from every fit and the noise estimate; the diagnosis names
it with its fundamental, the harmonics found and their size relative to the FRFs' level.
"""

from __future__ import annotations

import numpy as np

from massline.identify.diagnose.effects.base import Effect, need

MAINS_HZ = 50.0  # the fundamental when @HZ is not given


class MainsInterference(Effect):
    name = "mains_interference"
    kind = "test_physics"
    unit = "fraction"  # the fundamental's line, of each channel's massline level
    perturbs = "sensor"
    summary = "mains hum (a ground loop) at a fundamental and its harmonics on every response channel"
    model = "lines"  # set aside from every fit by identify: no block, no correction
    undone_on = None
    place = "frequency"
    blind_range = (0.05, 0.2)

    @classmethod
    def syntax(cls) -> str:
        return f"{cls.name}=AMPLITUDE[@HZ]"

    @classmethod
    def described(cls) -> str:
        return (
            f"{cls.syntax()} (AMPLITUDE: the fundamental's line, a fraction of each channel's massline level, "
            f"e.g. 0.1; HZ: the mains frequency inside the recorded band, default {MAINS_HZ:g}; odd harmonics at "
            "1/k of it, even ones at 0.1/k)"
        )

    @classmethod
    def parse_place(cls, where: str) -> float:
        """The fundamental, Hz (MAINS_HZ when not given)."""
        return float(where) if where else MAINS_HZ

    @classmethod
    def check_size(cls, size: float) -> None:
        need(
            bool(np.isfinite(size)) and size > 0,
            f"effect {cls.name}: its amplitude must be a positive fraction of the massline level (e.g. 0.1), "
            f"not {size:g}",
        )

    @classmethod
    def check_place(cls, where) -> None:
        need(
            bool(np.isfinite(where)) and where > 0,
            f"effect {cls.name}: its frequency must be a positive number of Hz (50 or 60), not {where:g}",
        )

    def simulate(self, state, lines, targets, rng):
        state.add_hum(float(self.where), self.size)
        return {"fundamental_hz": float(self.where)}

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        orders = ", ".join(str(k) for k in p["harmonics"])
        return (
            f"test physics, mains interference: lines at {p['fundamental_hz']:.4g} Hz × ({orders}) stand out of "
            f"every FRF, up to {p['amplitude']:.1%} of its level; {len(p['lines_hz'])} lines set aside from every "
            "fit and from the noise estimate"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"a ground loop puts mains hum on every channel, its fundamental at {size:.0%} of the massline"
