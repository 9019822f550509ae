"""A scale's reading of the body, used as a prior on the identified mass (``--weighed-mass KG[±SD]``).

The seed paper's case of Bretl & Conti (§1): with the mass known, the masslines spend their information on the
CoG and the inertia alone. The reading enters the weighted estimator as one more measured row,
(m_W − m)/σ_W, beside the masslines (:mod:`.estimator`).

Default 1-σ: 0.05 % of the reading. A trade-class bench scale (OIML R 76 class III, 3000–6000 divisions e)
used near its capacity errs by up to 1.5 e in service, 0.025–0.05 % of the reading; a scale read well below
its capacity, or one with fewer divisions, deserves an explicit ±SD.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from massline.core.errors import MasslineError

RELATIVE_SD = 5e-4  # default 1-σ of a reading, fraction of it (see the module docstring)
READING = re.compile(r"^\s*([^±+]+?)\s*(?:(?:±|\+-|\+/-)\s*([^%\s]+)\s*(%?))?\s*$")


@dataclass(frozen=True)
class WeighedMass:
    """A mass read on a scale.

    Attributes
    ----------
    mass : float
        The reading, kg.
    sd : float
        Its 1-σ, kg.
    """

    mass: float
    sd: float

    @classmethod
    def parse(cls, text: str) -> "WeighedMass":
        """``KG``, ``KG±SD`` (kg; ``+-`` or ``+/-`` for ±) or ``KG±P%``; SD defaults to 0.05 % of KG."""
        match = READING.match(text)
        try:
            mass = float(match.group(1))
            sd = RELATIVE_SD * mass if match.group(2) is None else float(match.group(2))
        except (AttributeError, ValueError):
            mass = sd = np.nan
        if match and match.group(3):
            sd *= mass / 100
        if not (np.isfinite(mass) and np.isfinite(sd) and mass > 0 and sd > 0):
            raise MasslineError(
                f"--weighed-mass '{text}': give the bare body's scale reading KG > 0 kg, optionally ±SD with "
                "0 < SD < inf kg or ±P% (e.g. 4.012, 4.012±0.002 or 4.012±0.05%)"
            )
        return cls(mass, sd)

    def plus(self, mass: float) -> "WeighedMass":
        """The same reading with ``mass`` (kg, taken as exact) added: the body as tested, accelerometers on."""
        return WeighedMass(self.mass + mass, self.sd)
