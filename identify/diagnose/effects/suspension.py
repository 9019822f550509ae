"""``suspension``: the support's modes below the band, their tail reaching into it (test physics).

Simulated by the virtual test's support (:mod:`massline.virtual.suspension`): in the blind scenarios a support much
stiffer than planned, its bounce at ``blind_range`` × the planned band's lower edge. Diagnosed as the tail
law "suspension" (:mod:`massline.identify.tails`), per FRF or the rigid body's own, s_iᵀ X e_j with
X = M⁻¹KM⁻¹/ω_mid² shared by every FRF; modelled, never blamed.
"""

from __future__ import annotations

from massline.identify.diagnose.effects.base import TailEffect


class Suspension(TailEffect):
    name = "suspension"
    unit = "Hz"  # the support's bounce
    perturbs = "support"
    summary = "the body on a support whose modes reach into the band"
    blind_range = (0.2, 0.4)  # bounce / planned band's lower edge
    edge_line = 0
    rigid_tail = True

    @classmethod
    def blind_size(cls, rng, body_mass, band):
        return float(rng.uniform(*cls.blind_range)) * band[0]

    @classmethod
    def tail_evidence(cls, reduced):
        """Its tail the rigid body's, s_iᵀ X e_j on every FRF, or each FRF's own."""
        return {"tail": "rigid_body" if reduced.shared else "per_frf"}

    @classmethod
    def sentence(cls, finding, who, hit):
        p = finding.parameters
        return (
            f"test physics, the support: its tail reaches {p['tail_max']:.1%} of the FRF matrix's scale at "
            f"{p['edge_hz']:.1f} Hz (median {p['tail_median']:.1%})"
            + (f"; its top mode is at {p['mode_hz']:.3g} Hz" if p.get("mode_hz") else "")
            + "; modelled in every FRF, as identify does"
        )

    @classmethod
    def concealed(cls, size, scene):
        return (
            f"the body rests on a stiff support bouncing at {size:.1f} Hz, not the planned soft cord "
            f"(planned band from {scene.band[0]:.1f} Hz)"
        )
