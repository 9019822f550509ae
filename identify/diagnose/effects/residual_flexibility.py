"""``residual_flexibility``: the body's elastic modes above the band, their tail reaching into it (test physics).

Simulated by the virtual test's FE modes (:mod:`massline.virtual.elastic`): in the blind scenarios a body softer
than its mesh, its first elastic mode at ``blind_range`` × the planned band's upper edge. Diagnosed as the tail
law "residual_flexibility" (:mod:`massline.identify.tails`); modelled, never blamed.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import TailEffect


class ResidualFlexibility(TailEffect):
    name = "residual_flexibility"
    unit = "Hz"  # the first elastic mode
    perturbs = "modes"
    summary = "the body's elastic modes above the band"
    blind_range = (2.0, 4.0)  # first elastic mode / planned band's upper edge
    edge_line = -1

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        return float(rng.uniform(*cls.blind_range)) * band[1]

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"test physics, the elastic modes above the band: their tail reaches {p['tail_max']:.1%} of the FRF "
            f"matrix's scale at {p['edge_hz']:.0f} Hz (median {p['tail_median']:.1%})"
            + (f"; the first is at {p['mode_hz']:.3g} Hz" if p.get("mode_hz") else "")
            + "; modelled in every FRF, as identify does"
        )

    @classmethod
    def concealed(cls, size, scene):
        return (
            f"the body is softer than its mesh: first elastic mode at {size:.0f} Hz "
            f"(planned band to {scene.band[1]:.0f} Hz)"
        )
