"""Warnings a machine can check: each a stable snake_case ``code`` beside the sentence for the engineer.

identify's and diagnose's JSON carry every warning as ``{"code": CODE, "text": SENTENCE}``; the console and the
reports print the sentence. A code never changes meaning; a new suspicion gets a new code, listed in ``CODES``
with what it says (docs/identifying.md, "Warnings").
"""

from __future__ import annotations

from dataclasses import dataclass

CODES = {
    "no_redundancy": "as many unknowns as masslines: no error in the data can show",
    "model_misfit": "the rigid model leaves more than the noise in the masslines (reduced χ² beyond chance)",
    "weighed_mass_disagrees": "the scale's reading and the masslines disagree on the mass beyond 3σ",
    "band_near_support": "the chosen band starts close above the support's resonances",
    "band_near_elastic": "the chosen band ends close below the elastic modes",
    "few_lines": "the band holds too few spectral lines for the tails",
    "poor_coherence": "FRFs with a poor median coherence in the band",
    "tail_truncation": "the tails' next term moves a property by more than twice its statistical ±",
    "given_band_near_support": "a band given by hand starts at or below the support's resonances",
    "given_band_near_elastic": "a band given by hand ends at or above the elastic modes",
    "short_record": "the record is too short to resolve the lowest resonance",
    "force_roll_off": "the coherence falls where the force spectrum rolls off (a soft hammer tip)",
    "denser_than_any_material": "the mass and inertia need material denser than any element, even read 9.81× "
    "lighter (a length label)",
    "lighter_than_air": "the mass over the hull of the measured points is lighter than air (a length label)",
    "heavy_for_extent": "9.81× heavy: the inertia ellipsoid denser than any element by less than 9.81×, or (--mesh) "
    "the mass near 9.81× the mesh's",
    "light_for_extent": "9.81× light: the inertia ellipsoid below a solid's floor, or (--mesh) the mass near 1/9.81× "
    "the mesh's",
    "nominal_mass_mismatch": "the mass differs from the nominal mesh's (--mesh) by more than 3σ and 2 %: a mass not "
    "given (--sensor-mass, --exciter-mass), or the mesh",
    "dc_line_set_aside": "the file's lines at or below 0 Hz were set aside",
    "mains_set_aside": "the lines of mains interference (a fundamental and its harmonics) were set aside",
    "support_modelled": "the support's departure from the masslines, modelled with the mesh's FE model, was taken off",
    "support_model_reliance": "the band's FRFs depart from their masslines by more than 5 %: the properties rest on "
    "the support model",
    "identify_no_band": "identify found no band: the properties are on the given band",
    "identify_refused": "identify refuses the file as it came",
    "frf_missing": "response-reference pairs without an FRF (or lines in the band), or geometry nodes without any: "
    "estimated from those present",
    "repeat_disagrees": "a pair measured in several runs differs between them beyond their noise",
    "fit_below_noise": "a fit's RMS residual is well below the recording's noise (tails that absorb a departure, or "
    "a mis-stated noise)",
    "noise_above_coherence": "the FRFs scatter from line to line far more than their coherence says",
}


@dataclass(frozen=True)
class CodedWarning:
    """One warning: ``code`` (a key of ``CODES``) and ``text`` (the sentence the console and reports show)."""

    code: str
    text: str

    def __post_init__(self):
        if self.code not in CODES:
            raise ValueError(f"unregistered warning code {self.code!r}: add it to CODES")

    def __str__(self) -> str:
        return self.text

    def as_json(self) -> dict:
        return {"code": self.code, "text": self.text}


def codes_of(warnings) -> set[str]:
    """The codes of a sequence of ``CodedWarning``."""
    return {w.code for w in warnings}
