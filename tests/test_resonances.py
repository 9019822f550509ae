"""Which peak is which (identify/resonances.py): a support mode moves the body rigidly, an elastic one does not.

A body on a stiff support whose bounce lies above the band: the FRF matrix is a modal sum of the six support
modes (mass-normalised rigid motions, Σ ψ ψᵀ = M⁻¹, so that above them all H is the massline S M⁻¹ Eᵀ) and one
elastic mode whose shape no rigid motion gives.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import sqrtm

from massline.identify.resonances import RIGID, rigid_misfit, support_and_elastic
from massline.core.band import Band
from massline.core.lines import Lines
from massline.core.rigid_body import RigidBody

BODY = RigidBody(12.0, np.array([0.02, -0.01, 0.03]), np.diag([0.3, 0.4, 0.5]))
DAMPING = 0.01


def lines(count: int, seed: int) -> Lines:
    rng = np.random.default_rng(seed)
    return Lines(rng.uniform(-0.3, 0.3, (count, 3)), np.eye(3)[rng.integers(0, 3, count)])


SENSORS, HITS = lines(10, 1), lines(4, 2)
S, E = SENSORS.coordinates, HITS.coordinates


def support_modes() -> np.ndarray:
    """(6, 6) mass-normalised rigid motions, ψᵀ M ψ = I, in random directions."""
    Q = np.linalg.qr(np.random.default_rng(3).normal(size=(6, 6)))[0]
    return np.real(np.linalg.inv(sqrtm(BODY.mass_matrix))) @ Q


def modal_frf(f: np.ndarray, support_hz, elastic_hz: float, elastic_size: float = 1.0) -> np.ndarray:
    """Accelerance (n_s, n_e, n_f): −ω² Σ φ_s φ_eᵀ / (ω_r² − ω² + 2iζω_rω) over support and elastic modes."""
    rng = np.random.default_rng(4)
    psi = support_modes()
    shapes = [(S @ p, E @ p) for p in psi.T]
    size = np.linalg.norm(shapes[0][0]) * elastic_size
    shapes.append((size * rng.normal(size=len(S)) / np.sqrt(len(S)), size * rng.normal(size=len(E)) / np.sqrt(len(E))))
    w, H = 2 * np.pi * f, 0
    for (a, b), hz in zip(shapes, list(support_hz) + [elastic_hz]):
        wr = 2 * np.pi * hz
        H = H + np.einsum("i,j,f->ijf", a, b, -(w**2) / (wr**2 - w**2 + 2j * DAMPING * wr * w))
    return H


def test_a_rigid_motion_fits_both_sides_and_an_elastic_shape_does_not():
    rng = np.random.default_rng(7)
    q = rng.normal(size=6)
    assert rigid_misfit(1j * np.outer(S @ q, E @ q), S, E) < 1e-12
    assert rigid_misfit(1j * np.outer(rng.normal(size=len(S)), rng.normal(size=len(E))), S, E) > 3 * RIGID
    # a shape rigid at the sensors but not at the hits (the structure's first elastic mode) is not rigid
    assert rigid_misfit(1j * np.outer(S @ q, rng.normal(size=len(E))), S, E) > RIGID


@pytest.mark.parametrize("bounce", [30.0, 80.0])
def test_a_bounce_above_the_band_is_the_support_top_not_the_first_elastic_mode(bounce):
    """Band 14–47 Hz: a bounce at 80 Hz lies above it and is the support's top; the elastic mode at 170 Hz is
    the first elastic one. With the bounce at 30 Hz (below a band from 60 Hz) nothing changes."""
    f = np.arange(0.25, 400.0, 0.25)
    H = modal_frf(f, [0.8, 1.0, 2.0, 3.0, 4.0, bounce], 170.0)
    band = Band(14.0, 47.0, np.nan, np.nan, "found") if bounce > 47 else Band(60.0, 90.0, np.nan, np.nan, "found")
    top, first = support_and_elastic(f, H, band, S, E)
    assert top == pytest.approx(bounce, rel=0.01) and first == pytest.approx(170.0, rel=0.01)


def test_nothing_is_printed_for_a_peak_the_record_does_not_resolve():
    f = np.arange(10.0, 400.0, 20.0)  # 20 Hz lines: the 170 Hz mode's peak (ζ = 1 %) falls between them
    H = modal_frf(f, [0.8, 1.0, 2.0, 3.0, 4.0, 5.0], 170.0, elastic_size=3.0)
    top, first = support_and_elastic(f, H, Band(30.0, 90.0, np.nan, np.nan, "found"), S, E)
    assert np.isnan(top) and np.isnan(first)
