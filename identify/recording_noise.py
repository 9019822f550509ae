"""The noise of a recording's FRFs, measured from what the recording shows apart from any model of them.

Every fit of identify and of the diagnosis is judged against one noise: the scatter of one real component of
one spectral line, σ_ij, for each FRF over the band. It must not be the residual of a fit of those FRFs: a
smooth systematic departure (a channel's delay, a mounting resonance) is partly absorbed by the fit's tails and
the rest counted as noise, and the fit is then "within the noise" of itself. Two yardsticks that owe nothing
to the rigid body or its tails:

1. **Coherence** (where the file has it): an H1 estimate from n_d averages errs, on each of its real and
   imaginary parts, by var = |H|² (1 − γ²)/(2 n_d γ²) (Bendat & Piersol, *Random Data*, §9.2.4: the normalised
   random error of |Ĥ| is √(1 − γ²)/(|γ|√(2 n_d))). n_d is what the file's header (dataset 151) states
   (:func:`stated_averages`; the virtual impact test writes 'H1 of 5 averages'); where it says nothing the stored
   coherence is read as one average's (n_d = 1), the convention the virtual test's direct route writes it by
   (:func:`massline.virtual.measurement.noisy_frfs`: γ² = |H|²/(|H|² + σ²), E|Ĥ − H|² = σ²). A coherence of 1
   at every line of an FRF (one average, or a noiseless simulation) measures nothing, and that FRF falls to 2.
2. **Line differences**: at three neighbouring lines the combination c₀H₀ + c₁H₁ + c₂H₂ whose weights annul
   any straight line in frequency (the second divided difference, scaled to ‖c‖ = 1) cancels the massline, the
   tails and any smooth departure to the order (Δf/f)², and leaves the noise with its own variance σ². Its
   scale is read robustly, median |v|/Φ⁻¹(3/4) over the real and imaginary parts of every triple: the few lines
   near a resonance or a hum do not lead it. It assumes each line's noise its own: an impact test's windows make
   neighbouring lines' noise alike, and the differences see less of it (the bracket's virtual impact test: 0.08 %
   where its coherence of 5 averages says 0.15 %), which is why the coherence comes first.

The per-line variance is read as its median over the band (the level of a typical line), per FRF. The line
differences are computed always: where the coherence is used, they check it (a recording noisier than its
coherence says is a finding, :func:`above_coherence`;
so is a fit that leaves less than the noise, :func:`below_noise`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace

import numpy as np

from massline.identify.warning_codes import CodedWarning

MAD_SCALE = 0.6744897501960817  # Φ⁻¹(3/4): median |v| of a unit normal
FEWEST = 12  # lines an FRF needs in the band for a noise of its own
BELOW = 0.8  # a fit's residual below this share of the noise absorbed more than the model can explain
ABOVE_COHERENCE = 2.0  # line differences this many times the coherence's noise: noise the coherence does not see
MEASURABLE = 1e-4  # a relative noise below this (80 dB under the FRFs) is a simulation's or a model's, not noise
COHERENCE, DIFFERENCES = "coherence", "line differences"
AVERAGES = re.compile(r"(\d+)\s*(?:averages|avgs?)\b|\baverages\s*[:=]?\s*(\d+)", re.I)


@dataclass(frozen=True, eq=False, kw_only=True)
class RecordingNoise:
    """Each FRF's noise over the band, from the recording alone.

    Attributes
    ----------
    sigma : (n_s, n_e) array
        σ_ij, 1-σ of one real component (Re or Im) of one line, (m/s²)/N, for the accelerance in the recording's
        frame; NaN for an FRF with fewer than ``FEWEST`` lines in the band.
    differences : (n_s, n_e) array
        The same from line differences alone (the check on the coherence), (m/s²)/N.
    from_coherence : (n_s, n_e) bool array
        The FRFs whose σ is their coherence's.
    lines : (n_s, n_e) int array
        Each FRF's lines in the band.
    mean_square : (n_s, n_e) array
        Each FRF's mean |H|² over its band lines, ((m/s²)/N)²: the scale of the relative noise.
    """

    sigma: np.ndarray
    differences: np.ndarray
    from_coherence: np.ndarray
    lines: np.ndarray
    mean_square: np.ndarray

    @property
    def method(self) -> str:
        """How the noise was found: 'coherence', 'line differences', or the first with the second where an FRF
        has no usable coherence."""
        used = self.from_coherence[np.isfinite(self.sigma)]
        if used.all() and used.size:
            return COHERENCE
        return f"{COHERENCE}, {DIFFERENCES} where it has none" if used.any() else DIFFERENCES

    def relative(self, sigma: np.ndarray | None = None) -> float:
        """The noise as a relative RMS over the band, √(Σ 2 n_ij σ_ij² / Σ n_ij ⟨|H_ij|²⟩) over the FRFs that have
        one (``sigma``: another per-FRF 1-σ on the same FRFs, e.g. ``differences``)."""
        sigma = self.sigma if sigma is None else sigma
        ok = np.isfinite(sigma)
        power = np.sum((self.lines * self.mean_square)[ok])
        return float(np.sqrt(np.sum((2 * self.lines * sigma**2)[ok]) / power)) if power > 0 else float("nan")

    def on(self, frequencies: np.ndarray, frf: np.ndarray, low: float, high: float) -> RecordingNoise:
        """The same noise relative to other FRFs (n_s, n_e, n_f) over the band [low, high] Hz: those a fit sees
        when the recording was moved first (a force gauge's riding mass taken off each column)."""
        lines, mean_square = band_power(frequencies, frf, low, high)
        return replace(self, lines=lines, mean_square=mean_square)

    @property
    def coherence_relative(self) -> float | None:
        """The relative noise the coherence gives, over the FRFs that use it (None: none does)."""
        if not self.from_coherence.any():
            return None
        return self.relative(np.where(self.from_coherence, self.sigma, np.nan))

    @property
    def payload(self) -> dict:
        """The JSON of the noise: relative RMS, how it was found, and the line differences' check."""
        return {
            "relative": self.relative(),
            "method": self.method,
            "line_differences": self.relative(self.differences),
        }


def band_power(frequencies: np.ndarray, frf: np.ndarray, low: float, high: float) -> tuple[np.ndarray, np.ndarray]:
    """Each FRF's lines in the band [low, high] Hz and its mean |H|² over them, ((m/s²)/N)² (0 where it has none)."""
    H = frf[:, :, band_lines(frequencies, low, high)]
    has = np.isfinite(H)
    lines = np.count_nonzero(has, axis=2)
    return lines, np.sum(np.abs(np.where(has, H, 0)) ** 2, axis=2) / np.maximum(lines, 1)


def stated_averages(header: str) -> int:
    """n_d, the averages behind each H1 estimate, as a file's header states them ('H1 of 5 averages',
    'Averages: 10', '8 avg'); 1 where it says nothing."""
    found = AVERAGES.search(header or "")
    return max(int(found.group(1) or found.group(2)), 1) if found else 1


def band_lines(frequencies: np.ndarray, low: float, high: float) -> np.ndarray:
    """(n_f,) bool: the lines in [low, high] Hz."""
    return (frequencies >= low) & (frequencies <= high)


def difference_weights(f: np.ndarray) -> np.ndarray:
    """(k, 3): for each triple of neighbouring lines f (k + 2,) Hz, the second divided difference's weights
    scaled to unit norm: c·(a + b f) = 0 for any straight line, and c·e has the variance of one line's e."""
    h0, h1 = f[1:-1] - f[:-2], f[2:] - f[1:-1]
    w = np.column_stack([1 / (h0 * (h0 + h1)), -1 / (h0 * h1), 1 / (h1 * (h0 + h1))])
    return w / np.linalg.norm(w, axis=1, keepdims=True)


def difference_sigma(f: np.ndarray, h: np.ndarray) -> float:
    """σ of one real component of one line of an FRF ``h`` (n,) complex at lines ``f`` (n,) Hz (its NaN lines
    dropped), from the scatter of its second differences: median |v|/Φ⁻¹(3/4) over their real and imaginary
    parts; NaN with fewer than ``FEWEST`` lines."""
    has = np.isfinite(h)
    f, h = f[has], h[has]
    if len(h) < FEWEST:
        return float("nan")
    c = difference_weights(f)
    v = c[:, 0] * h[:-2] + c[:, 1] * h[1:-1] + c[:, 2] * h[2:]
    return float(np.median(np.abs(np.concatenate([v.real, v.imag]))) / MAD_SCALE)


def coherence_sigma(h: np.ndarray, gamma2: np.ndarray, averages: int = 1) -> float:
    """σ of one real component of one line of an FRF ``h`` (n,) complex from its coherence ``gamma2`` (n,):
    the median over its lines of |H|² (1 − γ²)/(2 n_d γ²), square-rooted; NaN where it has no coherence or a
    coherence of 1 at every line (it measures nothing)."""
    has = np.isfinite(h) & np.isfinite(gamma2)
    if has.sum() < FEWEST or np.all(gamma2[has] >= 1.0):
        return float("nan")
    g = np.clip(gamma2[has], 1e-12, 1.0)
    return float(np.sqrt(np.median(np.abs(h[has]) ** 2 * (1 - g) / (2 * averages * g))))


def recording_noise(
    frequencies: np.ndarray,
    frf: np.ndarray,
    coherence: np.ndarray | None,
    low: float,
    high: float,
    averages: int = 1,
) -> RecordingNoise:
    """Each FRF's noise over the band [low, high] Hz from the recording: its coherence where it has one, else
    its line differences.

    Parameters
    ----------
    frequencies : (n_f,) array
        Hz.
    frf : (n_s, n_e, n_f) complex array
        Accelerance, (m/s²)/N; NaN at the lines an FRF does not have.
    coherence : (n_s, n_e, n_f) array or None
        Ordinary coherence γ² of each line.
    low, high : float
        The band, Hz.
    averages : int
        n_d, the averages behind each H1 estimate (1: the coherence read as one average's).
    """
    keep = band_lines(frequencies, low, high)
    f, H = frequencies[keep], frf[:, :, keep]
    flat = H.reshape(-1, len(f))
    differences = np.array([difference_sigma(f, h) for h in flat]).reshape(H.shape[:2])
    if coherence is None:
        told = np.full(H.shape[:2], np.nan)
    else:
        gamma2 = coherence[:, :, keep].reshape(flat.shape)
        told = np.array([coherence_sigma(h, g, averages) for h, g in zip(flat, gamma2)]).reshape(H.shape[:2])
    from_coherence = np.isfinite(told) & np.isfinite(differences)
    lines, mean_square = band_power(frequencies, frf, low, high)
    return RecordingNoise(
        sigma=np.where(from_coherence, told, differences),
        differences=differences,
        from_coherence=from_coherence,
        lines=lines,
        mean_square=mean_square,
    )


def below_noise(noise: RecordingNoise, residual: float, fit: str) -> list[CodedWarning]:
    """A warning when a ``fit`` (named in the sentence) leaves a relative RMS residual over the band, ``residual``,
    well below the recording's noise: it absorbed more than noise, or the noise is mis-stated."""
    level = noise.relative()
    if not level > MEASURABLE or residual >= BELOW * level:
        return []
    return [CodedWarning(
        "fit_below_noise",
        f"{fit} leaves an RMS residual of {100 * residual:.3g} % of the FRFs, {residual / level:.2f}× the "
        f"recording's noise of {100 * level:.3g} % ({noise.method}): no fit beats the noise, so its tails "
        "absorbed more than noise, or the noise is mis-stated (a coherence of several averages?)",
    )]  # fmt: skip


def above_coherence(noise: RecordingNoise) -> list[CodedWarning]:
    """A warning when the FRFs that have a coherence scatter from line to line far more than it says: noise the
    coherence does not see."""
    told = noise.coherence_relative
    seen = noise.relative(np.where(noise.from_coherence, noise.differences, np.nan))
    if told is None or not told > MEASURABLE or seen <= ABOVE_COHERENCE * told:
        return []
    return [CodedWarning(
        "noise_above_coherence",
        f"the FRFs scatter from line to line by {100 * seen:.3g} % RMS where their coherence says "
        f"{100 * told:.3g} % ({seen / told:.2f}×): noise the coherence does not see (a coherence from other "
        "records, a rattle, a drifting channel); the coherence's noise is used",
    )]  # fmt: skip
