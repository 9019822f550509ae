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
* the scale's reading and the masslines disagree on the mass beyond chance;
* a band given by hand (``--band``) holds or nears a resonance that the recording shows;
* the record is too short for its lowest resonance: a resonance k lines up the axis (f = kΔf) is not
  resolved, and the exponential window an impact test needs (to 1 % at the record's end, σ_w = ln(100)·Δf)
  adds ln(100)/(2πk) ≈ 0.73/k of critical damping to it, so its tail reaches into the band with an imaginary
  part the band fit does not model; with k < RESOLVED the window alone adds over 15 %;
* the force spectrum rolls off (a soft hammer tip): a UFF holds the FRFs and their coherence, not the force's
  autospectrum, but an H1 estimate's incoherence 1 − γ² = G_nn/(|H|² G_ff) rises as G_ff falls. Where the
  FRFs leave their massline above the band with the incoherence tens of times the band's, or where it rises
  that much across the band, the edge is the pulse's spectrum, not a resonance.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import chi2 as chi2_distribution

from massline.identify.warning_codes import CodedWarning
from massline.identify.zones import RESONANT, imaginary_fraction, stretch
from massline.core.band import Band

NEAR = 1.5  # band edges closer than this factor to where the FRFs leave their massline are flagged
CHANCE = 1e-3  # χ² beyond this tail probability of its distribution is flagged
MISFIT = 2.0  # and a reduced χ² above this
POOR_COHERENCE = 0.9  # median γ² of an FRF's band lines below which it is flagged
FEW_LINES = 40
DISAGREE = 3.0  # |studentised residual| of the scale's reading beyond which it is flagged
RESOLVED = 5  # lines up the axis below which the lowest resonance is not resolved
WINDOW_DECAY = np.log(100.0)  # σ_w T of an exponential window to 1 % at the record's end
WINDOW_DAMPING = 0.05  # critical damping the window may add to the lowest resonance (virtual.analyser's rule)
ROLL_OFF = 10.0  # incoherence this many times the band's marks a falling force spectrum
INCOHERENT = 0.01  # ... when it also exceeds this (1 − γ²)


def beyond_chance(chi2: float, dof: float) -> bool:
    """Whether a reduced χ² over ``dof`` degrees of freedom is more than chance and the noise's own uncertainty
    allow: beyond its distribution's ``CHANCE`` tail, and above ``MISFIT`` (the 1-σ of a fit estimated from its
    own scatter is itself known to a few tens of percent). One test for identify, diagnose and the reports."""
    return bool(np.isfinite(chi2) and chi2 * dof > chi2_distribution.isf(CHANCE, max(dof, 1)) and chi2 > MISFIT)


def fit_warnings(chi2: float, dof: float) -> list[CodedWarning]:
    """The fit statistic: reduced χ² (over ``dof`` degrees of freedom) beyond chance, or no redundancy."""
    if not np.isfinite(chi2):
        return [
            CodedWarning(
                "no_redundancy",
                "no redundancy: the layout has no more masslines than the fit has unknowns, so no error in the "
                "data can show; add sensors or hits to check the result",
            )
        ]
    if beyond_chance(chi2, dof):
        return [
            CodedWarning(
                "model_misfit",
                f"the rigid model leaves {np.sqrt(chi2):.1f}× the noise in the masslines (reduced χ² {chi2:.3g}): a "
                "faulty channel or physics the model leaves out; the ± is scaled up by it, but run massline diagnose",
            )
        ]
    return []


def weighing_warnings(z: float, weighed, housings: float) -> list[CodedWarning]:
    """The scale's reading (``weighed``, bare body) against the masslines: its studentised residual ``z``
    beyond DISAGREE (``housings``: the accelerometers' mass added to the reading, kg)."""
    if weighed is None or not abs(z) > DISAGREE:
        return []
    added = f" plus {housings:.4g} kg of accelerometers" if housings else ""
    return [
        CodedWarning(
            "weighed_mass_disagrees",
            f"the weighed mass ({weighed.mass:.6g} ± {weighed.sd:.2g} kg{added}) and the masslines disagree by "
            f"{abs(z):.1f}σ: check the scale, --sensor-mass, and that the body was weighed without its accelerometers",
        )
    ]


def band_warnings(band: Band, lines: int) -> list[CodedWarning]:
    """Band edges close to the resonances found in the recording, and a band with few lines."""
    found = []
    if band.rule != "given" and np.isfinite(band.suspension_top) and band.low < NEAR * band.suspension_top:
        found.append(
            CodedWarning(
                "band_near_support",
                f"the band starts {band.low / band.suspension_top:.1f}× above {band.suspension_top:.3g} Hz, where "
                "the support's resonances move the FRFs off their massline: its tail is a large part of the masslines "
                "there and can bias the mass beyond its ±; a softer support (top mode below a tenth of the band) "
                "removes the doubt",
            )
        )
    if band.rule != "given" and np.isfinite(band.first_elastic) and band.high > band.first_elastic / NEAR:
        found.append(
            CodedWarning(
                "band_near_elastic",
                f"the band ends {band.first_elastic / band.high:.1f}× below {band.first_elastic:.3g} Hz, where the "
                "elastic modes move the FRFs off their massline: their tail is a large part of the masslines there and "
                "can bias the inertia beyond its ±",
            )
        )
    if lines < FEW_LINES:
        found.append(
            CodedWarning(
                "few_lines", f"the band holds only {lines} spectral lines: record a finer resolution (more lines)"
            )
        )
    return found


def coherence_warnings(coherence: np.ndarray | None, in_band: np.ndarray, channels: list[str]) -> list[CodedWarning]:
    """FRFs whose band lines have a median coherence below POOR_COHERENCE (``channels``: 'sensor / hit')."""
    if coherence is None:
        return []
    median = np.median(coherence[:, :, in_band], axis=2).ravel()
    poor = np.flatnonzero(median < POOR_COHERENCE)
    if not len(poor):
        return []
    named = ", ".join(channels[k] for k in poor[:4]) + (" …" if len(poor) > 4 else "")
    return [
        CodedWarning(
            "poor_coherence",
            f"{len(poor)} FRF(s) have a median coherence below {POOR_COHERENCE} in the band ({named}): check the "
            "hits (double hits, overloads) and the sensors' cables",
        )
    ]


TRUNCATION = 2.0  # a truncation shift beyond this many statistical 1-σ is flagged


def truncation_warnings(shift: np.ndarray, statistical: dict, body) -> list[CodedWarning]:
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
        CodedWarning(
            "tail_truncation",
            f"the band is too close to the resonances for its tails: fitting their next term moves the {worst[1]} by "
            f"{worst[2]:.1%}, {worst[0]:.0f}× its statistical ± (the ± shown includes it); a softer support or a "
            "stiffer fixture opens a band clear of both",
        )
    ]


def given_band_warnings(band: Band, free: Band) -> list[CodedWarning]:
    """A band given by hand (``band``, Hz) reaching within NEAR of the resonances bounding the recording's
    resonance-free stretch (``free``, :func:`.band.stretch`), or across them."""
    found = []
    if np.isfinite(free.suspension_top) and band.low < NEAR * free.suspension_top:
        found.append(
            CodedWarning(
                "given_band_near_support",
                f"the given band starts at {band.low:.3g} Hz, {band.low / free.suspension_top:.2g}× the "
                f"{free.suspension_top:.3g} Hz where the support's resonances stop moving the FRFs off their massline: "
                f"their peaks or tails are fitted as massline; start it at {3 * free.suspension_top:.3g} Hz or more, "
                "or leave --band out",
            )
        )
    if np.isfinite(free.first_elastic) and band.high > free.first_elastic / NEAR:
        found.append(
            CodedWarning(
                "given_band_near_elastic",
                f"the given band ends at {band.high:.3g} Hz, {band.high / free.first_elastic:.2g}× the "
                f"{free.first_elastic:.3g} Hz where the elastic modes start moving the FRFs off their massline: their "
                f"peaks or tails are fitted as massline; end it at {free.first_elastic / 3:.3g} Hz or less, or leave "
                "--band out",
            )
        )
    return found


def lowest_resonance(frequencies: np.ndarray, frf: np.ndarray, below: float) -> float:
    """The lowest frequency (Hz) below ``below`` whose FRFs are imaginary-dominated (a resonance); nan if none."""
    inside = np.flatnonzero((imaginary_fraction(frf) > RESONANT) & (frequencies < below))
    return float(frequencies[inside[0]]) if len(inside) else np.nan


def short_record_warnings(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> list[CodedWarning]:
    """The lowest resonance below the band fewer than RESOLVED lines up the axis (``frequencies`` Hz from Δf)."""
    step = frequencies[1] - frequencies[0]
    lowest = lowest_resonance(frequencies, frf, band.low)
    lines = int(round(lowest / step)) if np.isfinite(lowest) else RESOLVED
    if lines >= RESOLVED:
        return []
    needed = WINDOW_DECAY / (WINDOW_DAMPING * 2 * np.pi * lowest)
    return [
        CodedWarning(
            "short_record",
            f"the lowest resonance, at {lowest:.3g} Hz, is {lines} line(s) up the axis (Δf {step:.3g} Hz, a "
            f"{1 / step:.3g} s record): too short a record to resolve it, and an impact test's exponential window "
            f"adds about {WINDOW_DECAY / (2 * np.pi * lines):.0%} of critical damping to it, so its tail reaches into the band; "
            f"record at least {needed:.3g} s (more lines, or a lower fmax)",
        )
    ]


def incoherence(coherence: np.ndarray, where: np.ndarray) -> float:
    """Median over the FRFs and the lines ``where`` of 1 − γ²."""
    return float(np.median(1 - coherence[:, :, where])) if where.any() else np.nan


def rolloff_warnings(frequencies: np.ndarray, coherence: np.ndarray | None, band: Band) -> list[CodedWarning]:
    """The incoherence where the FRFs leave their massline above the band (±10 % of ``band.first_elastic``), or
    over the band's top quarter (in log f), ROLL_OFF times the band's and above INCOHERENT."""
    if coherence is None:
        return []
    f = frequencies
    in_band = (f >= band.low) & (f <= band.high)
    reference = incoherence(coherence, in_band)
    places = [(f"at the band's top ({band.high:.3g} Hz)", in_band & (f >= band.high * (band.low / band.high) ** 0.25))]
    if np.isfinite(band.first_elastic):
        edge = np.abs(np.log(f / band.first_elastic)) < np.log(1.1)
        places.insert(0, (f"at {band.first_elastic:.3g} Hz, where the FRFs leave their massline above the band", edge))
    for place, where in places:
        seen = incoherence(coherence, where)
        if seen > INCOHERENT and seen > ROLL_OFF * reference:
            return [
                CodedWarning(
                    "force_roll_off",
                    f"the coherence falls {place}: 1 − γ² is {seen:.2g}, {seen / max(reference, 1e-12):.3g}× the "
                    "band's: the force spectrum rolls off there (a soft hammer tip), and what looks like a resonance "
                    "may be its notch; hit with a harder tip (force spectrum within 10 dB up to fmax) and record again",
                )
            ]
    return []


def recording_warnings(frequencies: np.ndarray, frf: np.ndarray, coherence, band: Band) -> list[CodedWarning]:
    """What the recording itself says against its ``band``: a given band near resonances, a record too short for
    its lowest resonance, a force spectrum rolling off (``frequencies`` Hz above 0, ``frf`` (n_s, n_e, n_f))."""
    free = stretch(frequencies, frf) if band.rule == "given" else band
    found = given_band_warnings(band, free) if band.rule == "given" else []
    bounds = Band(band.low, band.high, free.suspension_top, free.first_elastic, band.rule)
    return found + short_record_warnings(frequencies, frf, band) + rolloff_warnings(frequencies, coherence, bounds)
