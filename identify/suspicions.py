"""What makes an identification suspect: each check a sentence for the engineer, none a silent pass.

A result that may be off by more than its ± carries a warning (DESIGN.md, identify JSON ``warnings``):

* the rigid model leaves more than the noise in the masslines (reduced χ² ≫ 1): a fault or physics
  the model leaves out — ``massline diagnose`` says which;
* nothing is left over to judge the fit by (as many parameters as masslines): no check is possible;
* the band starts close above the support's top mode, or ends close below the first elastic mode, as the
  record resolves them (:func:`.resonances.bounding_modes`: a peak of the record, never an extrapolation):
  the fitted tails carry tens of per cent of the masslines there, and what their truncation leaves
  can exceed the ± (per-FRF tails are the fallback of a structured support model);
* the tails the band fits remove are truncated: their next term would move the properties by more than
  twice their statistical ± (the reported ± includes it, but the result rests on the tail model);
* the record is coarse for the band: fewer lines than the tails need;
* the coherence of the band's lines is poor, and not only because the FRF is small: a cross-axis FRF far
  below its row's and column's level has a low coherence at its channel's and hit's noise, and nothing wrong;
* the scale's reading and the masslines disagree on the mass beyond chance;
* a band given by hand (``--band``) holds or nears a resonance that the recording shows;
* the record is too short for its lowest resonance: a resonance k lines up the axis (f = kΔf) is not
  resolved, and the exponential window of an impact test (to 1 % at the record's end, σ_w = ln(100)·Δf)
  adds ln(100)/(2πk) ≈ 0.73/k of critical damping to it, so its tail reaches into the band with an imaginary
  part the band fit does not model; with k < RESOLVED the window alone adds over 15 %. Only on a record the
  file says was windowed so (dataset 1858): a shaker's record has no such window, and its unresolved support
  modes leave the band alone;
* the force spectrum rolls off (a soft hammer tip): a UFF holds the FRFs and their coherence, not the force's
  autospectrum, but an H1 estimate's incoherence 1 − γ² = G_nn/(|H|² G_ff) rises as G_ff falls. Where the
  FRFs leave their massline above the band with the incoherence tens of times the band's, or where it rises
  that much across the band, the edge is the force's spectrum, not a resonance.

The recording's checks read each FRF on the lines it has (:mod:`.missing_lines`): a line it lacks (NaN) is
left out of every median, and says nothing either way.
"""

from __future__ import annotations

import numpy as np

from massline.core.chi_square import chi2_isf
from massline.identify.missing_lines import median_present, missing_as_nan, present
from massline.identify.warning_codes import CodedWarning
from massline.identify.resonances import massline_level, peak_curve
from massline.identify.zones import RESONANT, imaginary_fraction, stretch
from massline.core.band import Band

NEAR = 1.5  # band edges closer than this factor to a resonance the record shows are flagged
CHANCE = 1e-3  # χ² beyond this tail probability of its distribution is flagged
MISFIT = 2.0  # and a reduced χ² above this
POOR_COHERENCE = 0.9  # median γ² of an FRF's band lines below which it is flagged
GOOD_RATIO = POOR_COHERENCE / (1 - POOR_COHERENCE)  # γ²/(1 − γ²) = |H|²/N at that coherence
FAULTY = 10.0  # an FRF's noise this many times its row's or column's is not its smallness
FEW_LINES = 40
DISAGREE = 3.0  # |studentised residual| of the scale's reading beyond which it is flagged
RESOLVED = 5  # lines up the axis below which the lowest resonance is not resolved
WINDOW_DECAY = np.log(100.0)  # σ_w T of an exponential window to 1 % at the record's end
WINDOW_DAMPING = 0.05  # critical damping the window may add to the lowest resonance (virtual.analyser's rule)
ROLL_OFF = 10.0  # incoherence this many times the band's marks a falling force spectrum
INCOHERENT = 0.01  # ... when it also exceeds this (1 − γ²)
ROLL_OFF_CAUSES = {  # on a record windowed as an impact test's, or on one that does not say how it was excited
    True: ("a soft hammer tip", "hit with a harder tip"),
    False: ("a hammer tip too soft, or a shaker's force dropping out", "excite the band evenly"),
}
LOUD = 0.5  # ‖Im H‖ over the band's massline level at which an imaginary-dominated line is a resonance


def beyond_chance(chi2: float, dof: float) -> bool:
    """Whether a reduced χ² over ``dof`` degrees of freedom is more than chance and the noise's own uncertainty
    allow: beyond its distribution's ``CHANCE`` tail, and above ``MISFIT`` (the 1-σ of a fit estimated from its
    own scatter is itself known to a few tens of percent). One test for identify, diagnose and the reports."""
    return bool(np.isfinite(chi2) and chi2 * dof > chi2_isf(CHANCE, max(dof, 1)) and chi2 > MISFIT)


def fit_warnings(chi2: float, dof: float, explained: float = 0.0, draws: int = 1) -> list[CodedWarning]:
    """The fit statistic: reduced χ² (over ``dof`` degrees of freedom) beyond chance, or no redundancy. The
    chain's calibration errors at their 1-σ leave ``explained`` of Σ r² in the fit (``draws`` independent errors,
    :mod:`.uncertainty_budget`): beyond chance is then beyond the noise's chance tail plus the calibration's, whose
    Σ r² is taken as a χ² of ``draws`` degrees of freedom."""
    if not np.isfinite(chi2):
        return [
            CodedWarning(
                "no_redundancy",
                "no redundancy: the layout has no more masslines than the fit has unknowns, so no error in the "
                "data can show; add sensors or hits to check the result",
            )
        ]
    bar = chi2_isf(CHANCE, max(dof, 1)) + explained * chi2_isf(CHANCE, max(draws, 1)) / max(draws, 1)
    if beyond_chance(chi2, dof) and chi2 * dof > bar:
        return [
            CodedWarning(
                "model_misfit",
                f"the rigid model leaves {np.sqrt(chi2):.1f}× the noise in the masslines (reduced χ² {chi2:.3g}"
                + (f", beyond the {explained / dof:.3g} the chain's calibration explains" if explained > 0 else "")
                + "): a faulty channel or physics the model leaves out; the ± is scaled up by it, but run massline "
                "diagnose",
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
    """Band edges close to the resonances the recording resolves, and a band with few lines.

    ``band.suspension_top`` is the support's top mode below the band and ``band.first_elastic`` the first
    elastic mode above it, Hz, as :func:`.resonances.bounding_modes` finds them (nan where the record resolves
    none: then nothing is said of that edge); ``lines`` the band's spectral lines."""
    found = []
    top, elastic = band.suspension_top, band.first_elastic
    if band.rule != "given" and top < band.low < NEAR * top:
        found.append(
            CodedWarning(
                "band_near_support",
                f"the band starts {band.low / top:.1f}× above the highest support mode the record resolves, at "
                f"{top:.3g} Hz: its tail is a large part of the masslines there and can bias the mass beyond its ±; "
                "a softer support (top mode below a tenth of the band) removes the doubt",
            )
        )
    if band.rule != "given" and band.high < elastic < NEAR * band.high:
        found.append(
            CodedWarning(
                "band_near_elastic",
                f"the band ends {elastic / band.high:.1f}× below the first elastic mode at {elastic:.3g} Hz: its "
                "tail is a large part of the masslines there and can bias the inertia beyond its ±",
            )
        )
    if lines < FEW_LINES:
        found.append(
            CodedWarning(
                "few_lines", f"the band holds only {lines} spectral lines: record a finer resolution (more lines)"
            )
        )
    return found


def noise_levels(frf: np.ndarray, coherence: np.ndarray) -> np.ndarray:
    """|H|² (1 − γ²)/γ² of every line (n_s, n_e, n_f), ((m/s²)/N)²: an H1 estimate's error variance G_nn/G_ff,
    the response channel's noise over the force's power, whatever the FRF's own size (γ² = 0: inf; NaN at a
    line the FRF does not have)."""
    gamma2 = np.clip(coherence, 0.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        levels = np.where(gamma2 > 0, np.abs(frf) ** 2 * (1 - gamma2) / gamma2, np.inf)
    return missing_as_nan(levels, present(frf, coherence))


def small_not_faulty(frf: np.ndarray, coherence: np.ndarray) -> np.ndarray:
    """(n_s, n_e) bool: FRFs whose poor coherence is their smallness, from their band lines.

    An FRF's noise N_ij (the median over the lines of :func:`noise_levels`) is its sensor channel's over its
    hit's force: a small cross-axis FRF at the same noise has a low coherence and nothing wrong. It is expected
    when N_ij is within FAULTY of the quieter of its row's and its column's median N (its channel's noise with
    the other hits, its hit's with the other channels: a bad cable raises a row, a double hit a column, both
    stand out from the other), and when that noise would leave an FRF of its row's and column's level
    s_ij = √(max_l |H_il| max_k |H_kj|) (medians of |H| over the lines) a good coherence. Every median and
    maximum is over the lines and FRFs present; a pair with none is not expected (False).
    """
    noise = median_present(noise_levels(frf, coherence), axis=2)
    expected = np.minimum(median_present(noise, axis=1)[:, None], median_present(noise, axis=0)[None, :])
    size = median_present(np.abs(frf), axis=2)  # |NaN| is NaN
    scale2 = np.fmax.reduce(size, axis=1)[:, None] * np.fmax.reduce(size, axis=0)[None, :]
    return (noise <= FAULTY * expected) & (scale2 >= GOOD_RATIO * expected)


def coherence_warnings(
    frf: np.ndarray, coherence: np.ndarray | None, in_band: np.ndarray, channels: list[str]
) -> list[CodedWarning]:
    """FRFs whose band lines have a median coherence below POOR_COHERENCE that their smallness does not explain
    (:func:`small_not_faulty`; ``frf`` (n_s, n_e, n_f) accelerance, ``channels``: 'sensor / hit'), over the lines
    each has; a pair with none in the band is not named."""
    if coherence is None:
        return []
    frf, coherence = frf[:, :, in_band], coherence[:, :, in_band]
    median = median_present(missing_as_nan(coherence, present(frf, coherence)), axis=2)
    poor = (median < POOR_COHERENCE) & ~small_not_faulty(frf, coherence)
    poor = np.flatnonzero(poor.ravel())
    if not len(poor):
        return []
    named = ", ".join(channels[k] for k in poor[:4]) + (" …" if len(poor) > 4 else "")
    return [
        CodedWarning(
            "poor_coherence",
            f"{len(poor)} FRF(s) have a median coherence below {POOR_COHERENCE} in the band ({named}), more noise "
            "than their channel shows with the other hits or their hit with the other channels: check the hits "
            "(double hits, overloads) and the sensors' cables",
        )
    ]


TRUNCATION = 2.0  # a truncation shift beyond this many statistical 1-σ is flagged


def truncation_warnings(shift: np.ndarray, statistical: dict, body) -> list[CodedWarning]:
    """The tails' truncation (``shift``: 25 property entries, uncertainty.truncation_std) against the
    statistical 1-σ: flagged where it exceeds TRUNCATION of them for the mass or a principal moment, or where it
    is infinite (the masslines moved by it fit no body: the ± is unbounded)."""
    mass = (shift[0], statistical["mass"], body.mass)
    moments = [(shift[13 + k], statistical["principal_moments"][k], body.principal_moments[k]) for k in range(3)]
    if np.isinf(shift).any():
        return [
            CodedWarning(
                "tail_truncation",
                "the band is too close to the resonances for its tails: moved by their next term, the masslines fit "
                "no body at all, and the ± is unbounded (∞); a softer support or a stiffer fixture opens a band "
                "clear of both (with --mesh, --suspension takes a stiff support's departure off)",
            )
        ]
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


def lowest_resonance(frequencies: np.ndarray, frf: np.ndarray, band: Band) -> float:
    """The lowest line (Hz) below ``band`` where the FRFs are imaginary-dominated (RESONANT) with an imaginary
    part of the masslines' size (‖Im H‖ ≥ LOUD × the band's ‖Re H‖, :func:`.resonances.massline_level`): a
    resonance, not the noise on the spring-like lines below a stiff support; nan if none."""
    loud = peak_curve(frf) >= LOUD * massline_level(frequencies, frf, band)
    inside = np.flatnonzero((imaginary_fraction(frf) > RESONANT) & loud & (frequencies < band.low))
    return float(frequencies[inside[0]]) if len(inside) else np.nan


def short_record_warnings(frequencies: np.ndarray, frf: np.ndarray, band: Band, windowed: bool) -> list[CodedWarning]:
    """The lowest resonance below the band fewer than RESOLVED lines up the axis (``frequencies`` Hz from Δf),
    on a record ``windowed`` exponentially (an impact test's window, which broadens it into the band)."""
    step = frequencies[1] - frequencies[0]
    lowest = lowest_resonance(frequencies, frf, band) if windowed else np.nan
    lines = int(round(lowest / step)) if np.isfinite(lowest) else RESOLVED
    if lines >= RESOLVED:
        return []
    needed = WINDOW_DECAY / (WINDOW_DAMPING * 2 * np.pi * lowest)
    added = WINDOW_DECAY / (2 * np.pi * lines)
    return [
        CodedWarning(
            "short_record",
            f"the lowest resonance, near {lowest:.3g} Hz, is {lines} line(s) up the axis (Δf {step:.3g} Hz, a "
            f"{1 / step:.3g} s record): too short a record to resolve it, and the exponential window the file "
            f"says was applied (to 1 % at the record's end) adds about {added:.0%} of critical damping to it, so "
            f"its tail reaches into the band; record at least {needed:.3g} s (more lines, or a lower fmax)",
        )
    ]


def incoherence(coherence: np.ndarray, where: np.ndarray) -> float:
    """Median over the FRFs and the lines ``where`` of 1 − γ², of those present (not NaN); nan if none."""
    return float(median_present(1 - coherence[:, :, where])) if where.any() else np.nan


def rolloff_warnings(
    frequencies: np.ndarray, coherence: np.ndarray | None, band: Band, windowed: bool
) -> list[CodedWarning]:
    """The incoherence where the FRFs leave their massline above the band (±10 % of ``band.first_elastic``, the
    top of the resonance-free stretch), or over the band's top quarter (in log f), ROLL_OFF times the band's and
    above INCOHERENT; its cause a hammer's tip on a record ``windowed`` as an impact test's, else either exciter's."""
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
            cause = ROLL_OFF_CAUSES[windowed]
            return [
                CodedWarning(
                    "force_roll_off",
                    f"the coherence falls {place}: 1 − γ² is {seen:.2g}, {seen / max(reference, 1e-12):.3g}× the "
                    f"band's: the force spectrum rolls off there ({cause[0]}), and what looks like a resonance may "
                    f"be its notch; {cause[1]} (force spectrum within 10 dB up to fmax) and record again",
                )
            ]
    return []


def recording_warnings(
    frequencies: np.ndarray, frf: np.ndarray, coherence, band: Band, windowed: bool = False
) -> list[CodedWarning]:
    """What the recording itself says against its ``band`` (given, or chosen with the edges of its stretch): a
    given band near resonances, a record too short for its lowest resonance, a force spectrum rolling off
    (``frequencies`` Hz above 0, ``frf`` (n_s, n_e, n_f); ``windowed``: the record's exponential window)."""
    free = stretch(frequencies, frf) if band.rule == "given" else band
    found = given_band_warnings(band, free) if band.rule == "given" else []
    bounds = Band(band.low, band.high, free.suspension_top, free.first_elastic, band.rule)
    return (
        found
        + short_record_warnings(frequencies, frf, band, windowed)
        + rolloff_warnings(frequencies, coherence, bounds, windowed)
    )
