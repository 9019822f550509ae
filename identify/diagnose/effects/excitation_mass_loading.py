"""``excitation_mass_loading``: a force gauge's structure-side mass riding at each drive point.

A shaker test drives the body through a force gauge glued to it; the gauge measures the force into its own
structure-side mass (5–25 g with the stinger's attachment), which moves with the body. The shaker is moved
between runs, so column j of the FRF matrix is the body plus that mass at drive point j: each column its own
body (:mod:`massline.identify.exciter_mass`).

Simulated: ``size`` kg riding at each named exciter's point while it drives (``simulate --gauge-mass KG`` puts
it at every one). Diagnosed (:mod:`..gauge_mass`): one mass, the same at every drive point, profiled through
identify's estimator with each column on its own body; named when it explains the misfit. Undone by identify
itself (``--exciter-mass``): each column fitted on its own body, the bare body reported.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import Effect, need, pm


class ExcitationMassLoading(Effect):
    name = "excitation_mass_loading"
    unit = "kg"
    perturbs = "exciter"
    summary = "a force gauge's structure-side mass at the drive point, while that exciter drives"
    model = "gauge"
    undone_on = "identify"
    identify_option = "exciter_mass"
    blind_range = (0.005, 0.025)  # kg: impedance heads and force gauges with their stinger attachment

    @classmethod
    def check_place(cls, where) -> None:
        need(where is None or where == "all" or len(where) >= 1, f"{cls.name}: name the drive points, or all")

    def simulate(self, state, lines, targets, rng):
        need(self.size >= 0, f"{self.name}={self.size:g}: a gauge's mass is ≥ 0 kg")
        for t in targets:
            state.exciter_masses[t] += self.size
        return {}

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        return float(rng.uniform(*cls.blind_range))

    @classmethod
    def option_value(cls, finding) -> float:
        """What identify is given to undo it: the gauge's mass, kg."""
        return float(finding.parameters["mass_kg"])

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"each column weighs the body plus {pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g at its drive point "
            f"({p['drive_points']} drive points), as a force gauge's structure side makes it: fitted column by "
            "column on its own body (identify --exciter-mass does the same)"
        )

    @classmethod
    def concealed(cls, size, scene):
        return f"a {1e3 * size:.0f} g force gauge rides at every drive point"

    @classmethod
    def located(cls, finding, channels, hit):
        return finding.effect == cls.name
