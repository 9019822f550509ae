"""``sensor_mass_loading``: a mass at an accelerometer's point (its housing, a cable clamp).

Simulated: ``size`` kg added at the point of each named accelerometer. Diagnosed against the mesh's body
(:mod:`..mass_loading`): one mass at one housing, or every housing alike, weighed on identify's θ̂ − θ_mesh;
undone on the body (its masses taken off), not on the recording.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect, accelerometers, need, pm
from massline.core.numbers import formatted


class SensorMassLoading(Effect):
    name = "sensor_mass_loading"
    unit = "kg"
    summary = "a mass at the sensor's point (per accelerometer)"
    model = "mass"
    undone_on = "body"
    blind_range = (0.02, 0.05)  # fraction of the body's mass
    adds_mass = True

    @classmethod
    def check_size(cls, size):
        super().check_size(size)
        need(size >= 0, f"effect {cls.name}: a housing's mass is ≥ 0 kg, not {size:g}")

    def simulate(self, state, lines, targets, rng):
        for t, _ in accelerometers(lines, targets):
            state.add_mass(self.size, state.sensor_points[t].copy())
        return {}

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        return float(rng.uniform(*cls.blind_range)) * body_mass

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        if p.get("each_housing"):
            grams = ", ".join(pm(1e3 * m, 1e3 * s) for m, s in zip(p["masses_kg"], p["masses_std_kg"]))
            return (
                f"the body is {formatted(1e3 * sum(p['masses_kg']), '.0f')} g heavier than the mesh, as housings of "
                f"their own masses at {who} make it ({grams} g); taken off (identify --sensor-mass KG NODE=KG does "
                "the same)"
            )
        if p.get("every_housing"):
            return (
                f"every accelerometer housing ({p['housings']}) weighs "
                f"{pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g: "
                f"the body as tested is {formatted(1e3 * p['mass_kg'] * p['housings'], '.0f')} g heavier than the "
                "mesh in their pattern; taken off (identify --sensor-mass does the same)"
            )
        return (
            f"the body is {pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g heavier than the mesh, as a mass "
            f"at {who} would make it; taken off"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"an extra {1e3 * size:.0f} g sits at sensor {scene.sensor}"
