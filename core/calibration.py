"""The measuring chain's type-B uncertainties: what no redundancy in the data can reveal.

Every FRF is an acceleration over a force, each read through a transducer whose sensitivity is known only as
well as it was calibrated. One budget (identify's, the plan's and the virtual test's) uses these figures:

* ``sensor``: 1-σ of each accelerometer channel's sensitivity, relative, independent from channel to channel.
  A back-to-back comparison calibration (ISO 16063-21) of an IEPE accelerometer states 1–2 % (k = 2) at its
  reference frequency; the datasheet's sensitivity alone, or a channel calibrated months ago, deserves about
  1 % 1-σ: the default.
* ``force``: 1-σ of the force transducer's (the hammer's or the force gauge's) sensitivity, relative, common to
  every FRF it measured. A hammer's sensitivity from its certificate, with the tip and the hammer's own mass
  between the gauge and the body, is known to 1–2 %; the default is 1 %. A common factor k on every FRF scales
  M⁻¹ by k, so every inertia parameter θ (mass, m·c, J) by 1/k: the mass and inertia move one for one, the CoG
  not at all.
* ``transverse``: the prior 1-σ of each channel's two transverse sensitivity components (fraction of the axial
  one). Datasheets of general-purpose accelerometers state a maximum of 3–5 % (paper §3): 3 %.

0 stands for a chain calibrated to far better than the rest of the budget.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from massline.core.errors import MasslineError, param

TRANSVERSE = 0.03  # prior 1-σ of an accelerometer's transverse sensitivity (datasheets: 3–5 %, paper §3)
SENSOR_CALIBRATION = 0.01  # 1-σ of an accelerometer channel's sensitivity, relative (see the module docstring)
FORCE_CALIBRATION = 0.01  # 1-σ of the force transducer's sensitivity, relative
MAX_CALIBRATION = 0.2  # a 1-σ beyond 20 % is no calibrated transducer
_PERCENT = re.compile(r"^\s*([^%\s]+)\s*%?\s*$")


@dataclass(frozen=True)
class Calibration:
    """The chain's type-B 1-σ, relative (fractions): each accelerometer channel's sensitivity (``sensor``,
    independent per channel), the force transducer's (``force``, common to every FRF), each channel's
    transverse sensitivity components (``transverse``), and each accelerometer housing's mass (``housings``,
    independent per housing; 0: weighed, the default, as ``--sensor-mass`` takes them)."""

    sensor: float = SENSOR_CALIBRATION
    force: float = FORCE_CALIBRATION
    transverse: float = TRANSVERSE
    housings: float = 0.0

    @classmethod
    def parse(cls, text: str, transverse: float = TRANSVERSE) -> "Calibration":
        """``SENSOR[,FORCE]`` in per cent ('%' optional): '1', '1,2', '0.5%,1%', '0' (a calibrated chain); one
        figure serves both. Refused: anything but 0 ≤ P ≤ 20 %."""
        parts = text.split(",")
        values = [_percent(p) for p in parts] if 1 <= len(parts) <= 2 else [math.nan]
        if not all(0 <= v <= MAX_CALIBRATION for v in values):
            raise MasslineError(
                f"{param('calibration', repr(text), cli=text)}: give SENSOR[,FORCE], each accelerometer's and the "
                f"force transducer's calibration 1-σ in per cent, 0 ≤ P ≤ {100 * MAX_CALIBRATION:g} (e.g. 1,1; 0 "
                "for a calibrated chain)"
            )
        return cls(values[0], values[-1], transverse)

    def with_housings(self, tolerance: float) -> "Calibration":
        """The same with each housing's mass known to ``tolerance`` (relative 1-σ, 0 ≤ it ≤ MAX_CALIBRATION)."""
        if not 0 <= tolerance <= MAX_CALIBRATION:
            raise MasslineError(
                f"{param('housing_tolerance', f'{tolerance:g}')}: give each housing's mass 1-σ as a fraction of it, "
                f"0 ≤ value ≤ {MAX_CALIBRATION:g}"
            )
        return Calibration(self.sensor, self.force, self.transverse, tolerance)

    def describe(self) -> str:
        """'accelerometers 1 %, force 1 % (1-σ), transverse 3 %'."""
        return (
            f"accelerometers {100 * self.sensor:g} %, force {100 * self.force:g} % (1-σ calibration), transverse "
            f"sensitivity {100 * self.transverse:g} %"
        )

    @property
    def payload(self) -> dict:
        return {"sensor": self.sensor, "force": self.force, "transverse": self.transverse, "housings": self.housings}


def _percent(text: str) -> float:
    """'1.5' or '1.5%' → 0.015; nan when not a number."""
    match = _PERCENT.match(text)
    try:
        return float(match.group(1)) / 100
    except (AttributeError, ValueError):
        return math.nan
