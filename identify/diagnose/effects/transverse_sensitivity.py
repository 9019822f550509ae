"""``transverse_sensitivity``: an accelerometer reading s·(a·t) besides a·d, t ⊥ d (mismatch notes §3 B1).

Simulated: every named channel reads ``size`` of the acceleration along a random t ⊥ its axis, as datasheets
allow (a few per cent). Knowingly not diagnosed (``model`` None): every fit estimates each channel's transverse
components under the datasheet's prior (:mod:`..effect_model`), and one beyond it is a ``sensor_direction``.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect, perpendicular


class TransverseSensitivity(Effect):
    name = "transverse_sensitivity"
    unit = "fraction"
    summary = "reads s·(a·t) besides a·d, t ⊥ d at random"
    model = None

    def simulate(self, state, lines, targets, rng):
        drawn = []
        for t in targets:
            t_dir = perpendicular(lines.directions[t], rng)
            state.sensor_vectors[t] += self.size * t_dir
            drawn.append(t_dir.tolist())
        return {"transverse": drawn} if drawn else {}
