"""From the model's FRFs to what a test system records: noise, or a full impact test.

Two routes:

* ``noisy_frfs``: the exact accelerance with a relative error and a floor, as
  complex Gaussian noise (the planner's noise model, DESIGN.md), with the coherence
  of an H1 estimate erring by that noise; ``with_dc_line`` puts the exporter's 0 Hz
  line before it.
* ``impact_test``: what a lab does. A half-sine force pulse of duration τ hits
  the body at rest; the responses are computed in time, noise is added to the
  force and response channels, both are windowed (force window, exponential
  window), and H1 = Σ X F* / Σ |F|² over the averages is estimated with its
  coherence γ² = |Σ X F*|² / (Σ |X|² Σ |F|²), from the DC line (``dc=True``) or from Δf.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from massline.virtual.hum import impact_tones


@dataclass(frozen=True)
class Noise:
    """Measurement noise of an FRF: σ = relative·|H| + floor/m, complex Gaussian.

    ``floor`` is a fraction of 1/m (m the body's mass), like the planner's noise model.
    """

    relative: float = 0.01
    floor: float = 0.0


def noisy_frfs(H: np.ndarray, noise: Noise, mass: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """H plus complex noise of standard deviation σ = relative·|H| + floor/mass on each value, and its coherence.

    The noisy value stands for an H1 estimate whose response channel carries noise N uncorrelated with the
    force F: X = H F + N. With the auto-spectra G_ff and G_nn, H1 = G_xf/G_ff = H + G_nf/G_ff errs by a
    variance E|H1 − H|² = G_nn/G_ff over one record, which is σ²; and the ordinary coherence is

        γ² = |G_xf|² / (G_xx G_ff) = |H|² G_ff² / ((|H|² G_ff + G_nn) G_ff) = |H|² / (|H|² + σ²).

    So γ²/(1 − γ²) = |H|²/σ², the inverse relative variance that identify weights each line by
    (:func:`massline.uff.runs.coherence_weights`). The stored value is read as one average's
    estimate: with n_d averages of that noise the error variance would be σ²/n_d and γ² unchanged. The
    coherence returned is this expected value (no estimation scatter); 1 where σ = 0.

    Returns
    -------
    frf : complex array like H
        (m/s²)/N.
    coherence : array like H
        γ², dimensionless.
    """
    sigma = noise.relative * np.abs(H) + noise.floor / mass
    power = np.abs(H) ** 2
    coherence = np.divide(power, power + sigma**2, out=np.ones(H.shape), where=sigma > 0)
    return H + sigma * (rng.normal(size=H.shape) + 1j * rng.normal(size=H.shape)) / np.sqrt(2), coherence


def with_dc_line(
    frequencies: np.ndarray, frf: np.ndarray, coherence: np.ndarray, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The recording as exporters store it, lines + DC: a 0 Hz line put before the first.

    An analyser's DC line holds no massline (accelerance vanishes at 0 Hz on a support) but the DC of the
    windowed signals: sensor offset and window residue. Real exports show it real-valued and an outlier
    (−0.77 against ~0.08, 1.7e-4 against ~1e-5: ``notes/lab-realism.md`` §2). Here it is real, of random sign,
    1 to 20 times (log-uniform) the FRF's median magnitude, with a coherence drawn from 0–0.3.

    Parameters
    ----------
    frequencies : (n,) array
        Hz, evenly spaced from Δf.
    frf : (n_s, n_e, n) complex array
        (m/s²)/N.
    coherence : (n_s, n_e, n) array
    """
    shape = frf.shape[:2]
    size = np.median(np.abs(frf), axis=2) * np.exp(rng.uniform(0.0, np.log(20.0), size=shape))
    dc = rng.choice([-1.0, 1.0], size=shape) * size
    return (
        np.concatenate([[0.0], frequencies]),
        np.concatenate([dc[:, :, None].astype(complex), frf], axis=2),
        np.concatenate([rng.uniform(0.0, 0.3, size=shape)[:, :, None], coherence], axis=2),
    )


@dataclass(frozen=True)
class ImpactTest:
    """An impact hammer test.

    Attributes
    ----------
    pulse : float or None
        Half-sine pulse duration τ, s (its spectrum falls to zero at 1.5/τ); None: the virtual test's
        analyser setup chooses it (:func:`massline.virtual.analyser.hammer_pulse`).
    peak : float
        Peak force, N.
    averages : int
        Hits per exciter averaged into H1.
    window_end : float
        Value of the exponential window at the end of the record.
    force_noise, response_noise : float
        Standard deviation of the noise on each channel, fraction of its RMS over the record.
    offset : float
        Standard deviation of a constant offset on each response record, as a fraction of the windowed
        response's mean: what an IEPE channel's bias has not settled to differs from hit to hit, so the DC
        line holds residue that the force does not explain, its coherence near 1/(1 + offset²) whatever the
        record length (0.3 here; 0.37 in a real export, ``fixtures/uff/ufffiles_dataset58_coh.unv``); the
        exponential window spreads a little of it into the lowest lines (∝ 1/f).
    pretrigger : float
        Fraction of the record before the hit.
    force_window : float
        Fraction of the record after the hit kept by the force window (the rest is set to zero);
        it must hold the ringing of the band-limited pulse.
    record : {"support", "band"}
        The record the analyser setup chooses: long enough for the lowest support mode, or the shortest the
        band needs (:func:`massline.virtual.analyser.impact_setup`).
    """

    pulse: float | None = None
    peak: float = 200.0
    averages: int = 5
    window_end: float = 0.01
    force_noise: float = 0.002
    response_noise: float = 0.005
    pretrigger: float = 0.01
    force_window: float = 0.05
    offset: float = 1.5
    record: str = "support"


def half_sine_spectrum(f: np.ndarray, start: float, duration: float, peak: float) -> np.ndarray:
    """Fourier transform (N·s) of f(t) = peak·sin(π (t − start)/τ) for start ≤ t ≤ start + τ.

    F(ω) = peak (π/τ) (1 + e^{−iωτ}) e^{−iω·start} / ((π/τ)² − ω²), whose limit at ω = π/τ is
    −i·peak·τ/2 (times the shift); its first zero is at f = 1.5/τ.
    Sampling the band-limited pulse through this spectrum is what the anti-aliasing filter of
    the acquisition does to a pulse shorter than a sample.
    """
    w = 2 * np.pi * np.asarray(f, dtype=float)
    a = np.pi / duration
    near = np.isclose(w, a, rtol=1e-9)
    safe = np.where(near, 0.0, w)
    F = peak * a * (1 + np.exp(-1j * safe * duration)) / (a**2 - safe**2)
    F = np.where(near, -0.5j * peak * duration, F)
    return F * np.exp(-1j * w * start)


def exponential_window(n: int, end: float) -> np.ndarray:
    """w(t) = exp(−t/τ_w) over n samples, with w = ``end`` at the last one."""
    return end ** (np.arange(n) / (n - 1))


def impact_test(
    accelerance: Callable[[np.ndarray], np.ndarray],
    n_sensors: int,
    n_exciters: int,
    fmax: float,
    lines: int,
    test: ImpactTest,
    rng: np.random.Generator,
    padding: int = 8,
    dc: bool = True,
    hums: tuple = (),
    levels: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """H1 FRFs and coherence from simulated hits.

    Parameters
    ----------
    accelerance : callable
        f (Hz, array) → H (n_s, n_e, n_f), the system's accelerance.
    fmax, lines : float, int
        Analysis bandwidth (Hz) and number of spectral lines: Δf = fmax/lines, fs = 2.56 fmax.
    padding : int
        The response is computed over ``padding`` records and the first kept, so it starts
        from rest rather than wrapping around.
    dc : bool
        Keep the 0 Hz line, as exporters store lines + DC: H1 there is the ratio of the windowed
        signals' DC, real-valued residue.
    hums, levels : tuple of Hum, (n_s,) array
        Mains hum added to every hit's response records (:mod:`massline.virtual.hum`), each channel's at
        ``levels`` × its size ((m/s²)/N, the channels' massline levels); drawn from a generator spawned from
        ``rng``, so the rest of the test draws the same noise with or without it.

    Returns
    -------
    frequencies (m,) Hz, H1 (n_s, n_e, m) (m/s²)/N, coherence (n_s, n_e, m); m = lines + 1 with the DC line.
    """
    df = fmax / lines
    fs = 2.56 * fmax
    n = int(round(fs / df))
    f_long = np.fft.rfftfreq(n * padding, 1 / fs)
    H_long = accelerance(np.maximum(f_long, 1e-6 * df))
    start = test.pretrigger * n / fs
    F_long = fs * half_sine_spectrum(f_long, start, test.pulse, test.peak)
    force = np.fft.irfft(F_long, n=n * padding)[:n]
    w = exponential_window(n, test.window_end)
    keep = (np.arange(n) / fs) <= start + max(4 * test.pulse, test.force_window * n / fs)
    kept = slice(0 if dc else 1, lines + 1)
    f = np.fft.rfftfreq(n, 1 / fs)[kept]
    mains = rng.spawn(1)[0]
    force_lines = np.abs(np.fft.rfft(force * keep * w))
    tones = impact_tones(hums, levels, lambda tone: force_lines[int(round(tone / df))], w.sum(), fmax, mains)
    t = np.arange(n) / fs
    H1 = np.empty((n_sensors, n_exciters, len(f)), dtype=complex)
    coherence = np.empty(H1.shape)
    for j in range(n_exciters):
        response = np.fft.irfft(H_long[:, j] * F_long, n=n * padding, axis=-1)[:, :n]
        rms = np.sqrt(np.mean(response**2, axis=1))[:, None]
        offset = test.offset * np.abs(response @ w)[:, None] / w.sum()
        Sxf, Sxx, Sff = 0.0, 0.0, 0.0
        for _ in range(test.averages):
            f_meas = force + test.force_noise * np.sqrt(np.mean(force**2)) * rng.normal(size=n)
            noise = test.response_noise * rms * rng.normal(size=response.shape)
            x_meas = response + noise + offset * rng.normal(size=offset.shape)
            if hums:
                x_meas = x_meas + tones.record(t, mains.uniform(0, 2 * np.pi))
            F = np.fft.rfft(f_meas * keep * w)[kept]
            X = np.fft.rfft(x_meas * w, axis=-1)[:, kept]
            Sxf, Sxx, Sff = Sxf + X * F.conj(), Sxx + np.abs(X) ** 2, Sff + np.abs(F) ** 2
        H1[:, j] = Sxf / Sff
        coherence[:, j] = np.abs(Sxf) ** 2 / (Sxx * Sff)
    return f, H1, coherence
