"""The measuring chain's errors a real test carries, drawn for the virtual test from the budget's 1-σ.

A lab's accelerometers and force transducer are calibrated only so well, and every accelerometer reads a few per
cent across its axis (:mod:`massline.core.calibration`). The virtual test draws, from the same 1-σ that identify's
budget assumes:

* each accelerometer channel's sensitivity error ε_i ~ N(0, sensor²): it reads (1 + ε_i) of the truth;
* the force transducer's ε_F ~ N(0, force²): the force is read (1 + ε_F) too large, every FRF 1/(1 + ε_F);
* each channel's transverse reading τ_i = T_i z_i, z_i ~ N(0, transverse² I₂), T_i two unit vectors ⊥ its axis:
  the identify prior's distribution (datasheets' maxima of 3–5 % are about 1-2 σ of it).

They come from their own stream of the test's seed, so the noise of a seed is the same with or without them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.calibration import Calibration
from massline.core.lines import perpendicular_bases

STREAM = 0xCA1  # the chain's draws' own stream of a seed (np.random.default_rng((seed, STREAM)))


@dataclass(frozen=True)
class ChainErrors:
    """One test's chain errors.

    Attributes
    ----------
    gains : (n_s,) array
        Each accelerometer's reading per unit of the truth, 1 + ε_i.
    force_gain : float
        The force transducer's reading per unit of the truth, 1 + ε_F (every FRF is divided by it).
    transverse : (n_s, 3) array
        Each accelerometer's transverse reading vector (⊥ its axis), per unit of axial sensitivity.
    calibration : Calibration
        The 1-σ they were drawn from.
    """

    gains: np.ndarray
    force_gain: float
    transverse: np.ndarray
    calibration: Calibration

    def reading_vectors(self, vectors: np.ndarray) -> np.ndarray:
        """What each accelerometer reads per m/s² (n_s, 3): its ``vectors`` plus the transverse reading, times
        its gain."""
        return self.gains[:, None] * (vectors + self.transverse)

    @property
    def payload(self) -> dict:
        """The truth file's ``chain``: the 1-σ and every draw."""
        return {
            "calibration": self.calibration.payload,
            "sensor_gain_errors": (self.gains - 1).tolist(),
            "force_gain_error": self.force_gain - 1,
            "transverse": self.transverse.tolist(),
        }


def draw_chain_errors(calibration: Calibration, directions: np.ndarray, seed: int) -> ChainErrors:
    """The chain errors of a test with sensors along ``directions`` (n_s, 3), drawn from ``calibration``'s 1-σ on
    the seed's own stream."""
    rng = np.random.default_rng((seed, STREAM))
    n = len(directions)
    gains = 1 + calibration.sensor * rng.normal(size=n)
    force = 1 + calibration.force * rng.normal()
    components = calibration.transverse * rng.normal(size=(n, 2))
    transverse = np.einsum("nak,nk->na", perpendicular_bases(np.asarray(directions, dtype=float)), components)
    return ChainErrors(gains, float(force), transverse, calibration)
