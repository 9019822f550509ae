"""What makes an identification suspect: each check a sentence for the engineer, none a silent pass.

A result that may be off by more than its ± carries a warning (DESIGN.md, identify JSON ``warnings``):

* the rigid model leaves more than the noise in the masslines (reduced χ² ≫ 1): a fault or physics
  the model leaves out — ``massline diagnose`` says which;
* nothing is left over to judge the fit by (as many parameters as masslines): no check is possible;
* the band starts close above where the support's resonances, or ends close below where the elastic
  modes, move the FRFs off their massline:
  the fitted tails carry tens of per cent of the masslines there, and what their truncation leaves
  can exceed the ± (per-FRF tails are the fallback of a structured support model);
* the tails the band fits remove are truncated: their next term would move the properties by more than
  twice their statistical ± (the reported ± includes it, but the result rests on the tail model);
* the record is coarse for the band: fewer lines than the tails need;
* the coherence of the band's lines is poor;
* the scale's reading and the masslines disagree on the mass beyond chance.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import chi2 as chi2_distribution

from massline.placement.band import Band

NEAR = 1.5  # band edges closer than this factor to where the FRFs leave their massline are flagged
CHANCE = 1e-3  # χ² beyond this tail probability of its distribution is flagged
POOR_COHERENCE = 0.9  # median γ² of an FRF's band lines below which it is flagged
FEW_LINES = 40
DISAGREE = 3.0  # |studentised residual| of the scale's reading beyond which it is flagged


def fit_warnings(chi2: float, dof: float) -> list[str]:
    """The fit statistic: reduced χ² (over ``dof`` degrees of freedom) beyond chance, or no redundancy."""
    if not np.isfinite(chi2):
        return [
            "no redundancy: the layout has no more masslines than the fit has unknowns, so no error in the "
            "data can show; add sensors or hits to check the result"
        ]
    if chi2 * dof > chi2_distribution.isf(CHANCE, max(dof, 1)) and chi2 > 2.0:
        return [
            f"the rigid model leaves {np.sqrt(chi2):.1f}× the noise in the masslines (reduced χ² {chi2:.3g}): a "
            "faulty channel or physics the model leaves out; the ± is scaled up by it, but run massline diagnose"
        ]
    return []


def weighing_warnings(z: float, weighed, housings: float) -> list[str]:
    """The scale's reading (``weighed``, bare body) against the masslines: its studentised residual ``z``
    beyond DISAGREE (``housings``: the accelerometers' mass added to the reading, kg)."""
    if weighed is None or not abs(z) > DISAGREE:
        return []
    added = f" plus {housings:.4g} kg of accelerometers" if housings else ""
    return [
        f"the weighed mass ({weighed.mass:.6g} ± {weighed.sd:.2g} kg{added}) and the masslines disagree by "
        f"{abs(z):.1f}σ: check the scale, --sensor-mass, and that the body was weighed without its accelerometers"
    ]


def band_warnings(band: Band, lines: int) -> list[str]:
    """Band edges close to the resonances found in the recording, and a band with few lines."""
    found = []
    if band.rule != "given" and np.isfinite(band.suspension_top) and band.low < NEAR * band.suspension_top:
        found.append(
            f"the band starts {band.low / band.suspension_top:.1f}× above {band.suspension_top:.3g} Hz, where the "
            "support's resonances move the FRFs off their massline: its tail is a large part of the masslines there "
            "and can bias the mass beyond its ±; a softer support (top mode below a tenth of the band) removes the doubt"
        )
    if band.rule != "given" and np.isfinite(band.first_elastic) and band.high > band.first_elastic / NEAR:
        found.append(
            f"the band ends {band.first_elastic / band.high:.1f}× below {band.first_elastic:.3g} Hz, where the elastic "
            "modes move the FRFs off their massline: their tail is a large part of the masslines there and can bias "
            "the inertia beyond its ±"
        )
    if lines < FEW_LINES:
        found.append(f"the band holds only {lines} spectral lines: record a finer resolution (more lines)")
    return found


def coherence_warnings(coherence: np.ndarray | None, in_band: np.ndarray, channels: list[str]) -> list[str]:
    """FRFs whose band lines have a median coherence below POOR_COHERENCE (``channels``: 'sensor / hit')."""
    if coherence is None:
        return []
    median = np.median(coherence[:, :, in_band], axis=2).ravel()
    poor = np.flatnonzero(median < POOR_COHERENCE)
    if not len(poor):
        return []
    named = ", ".join(channels[k] for k in poor[:4]) + (" …" if len(poor) > 4 else "")
    return [
        f"{len(poor)} FRF(s) have a median coherence below {POOR_COHERENCE} in the band ({named}): check the "
        "hits (double hits, overloads) and the sensors' cables"
    ]


TRUNCATION = 2.0  # a truncation shift beyond this many statistical 1-σ is flagged


def truncation_warnings(shift: np.ndarray, statistical: dict, body) -> list[str]:
    """The tails' truncation (``shift``: 25 property entries, uncertainty.truncation_std) against the
    statistical 1-σ: flagged where it exceeds TRUNCATION of them for the mass or a principal moment."""
    mass = (shift[0], statistical["mass"], body.mass)
    moments = [(shift[13 + k], statistical["principal_moments"][k], body.principal_moments[k]) for k in range(3)]
    worst = max(
        [
            (d / s, name, d / v)
            for (d, s, v), name in zip([mass, *moments], ["mass", "J1", "J2", "J3"])
            if s > 0 and np.isfinite(d / s)
        ],
        default=(0.0, "", 0.0),
    )
    if worst[0] <= TRUNCATION:
        return []
    return [
        f"the band is too close to the resonances for its tails: fitting their next term moves the {worst[1]} by "
        f"{worst[2]:.1%}, {worst[0]:.0f}× its statistical ± (the ± shown includes it); a softer support or a "
        "stiffer fixture opens a band clear of both"
    ]
