"""The masses the instrumentation puts on the body, as a test engineer gives them: the accelerometers' housings
(one default, and per point where they differ) and a force gauge's structure side (one per drive point).

``--sensor-mass 0.004 1=0.025 2=0.025``: every housing weighs 4 g but those at points 1 and 2 (triaxials) 25 g;
the points are labelled as the recording labels them (its node labels; :mod:`.numbering` for the plan's test).
A housing is one accelerometer: a triaxial's three channels, or the channels sharing its point, count once.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.core.errors import MasslineError, param


HEAVIEST = 10.0  # kg: no accelerometer housing weighs more (a mass beyond is a unit slip: grams given as kg)


@dataclass(frozen=True)
class HousingMasses:
    """Housing masses, kg: ``default`` for every housing, ``by_label`` {point label: kg} where they differ."""

    default: float = 0.0
    by_label: dict = field(default_factory=dict)

    def __post_init__(self):
        for label, mass in [("", self.default), *self.by_label.items()]:
            if not (np.isfinite(mass) and 0 <= mass <= HEAVIEST):
                where = f"'{label}={mass:g}'" if label != "" else f"'{mass:g}'"
                raise MasslineError(
                    f"{param('sensor_mass', where)}: a housing's mass is a number of kg, 0 ≤ KG ≤ {HEAVIEST:g}"
                )

    @classmethod
    def parse(cls, tokens) -> HousingMasses:
        """``KG [LABEL=KG ...]`` (a float alone is the default for every housing)."""
        if isinstance(tokens, (int, float)):
            return cls(float(tokens))
        tokens = [tokens] if isinstance(tokens, str) else list(tokens)
        default, by_label = 0.0, {}
        for k, token in enumerate(tokens):
            label, has_label, value = str(token).partition("=")
            try:
                mass = float(value if has_label else label)
                key = int(label) if has_label else None
            except ValueError:
                raise MasslineError(
                    f"{param('sensor_mass', repr(str(token)))}: write KG for every housing, then LABEL=KG for a "
                    "point whose housing differs (e.g. 0.004 1=0.025)"
                ) from None
            if key is None and k:
                raise MasslineError(f"{param('sensor_mass', repr(str(token)))}: the default KG comes first, once")
            if key is None:
                default = mass
            else:
                by_label[key] = mass
        return cls(default, by_label)

    @classmethod
    def from_payload(cls, payload) -> HousingMasses:
        """plan.json's (or a truth file's) ``sensor_mass`` back: kg for every housing, or
        {"default": kg, "by_point": {label: kg}}; 0 where there is none."""
        if isinstance(payload, dict):
            return cls(float(payload["default"]), {int(k): float(v) for k, v in payload["by_point"].items()})
        return cls(float(payload or 0.0))

    @property
    def any(self) -> bool:
        """Is any housing given a mass?"""
        return self.default > 0 or any(m > 0 for m in self.by_label.values())

    def check_labels(self, labels) -> None:
        """Refuse a label that names no point of the test (``labels``: the accelerometers' point labels)."""
        unknown = sorted(set(self.by_label) - {int(x) for x in labels})
        if unknown:
            known = ", ".join(str(x) for x in sorted({int(x) for x in labels}))
            raise MasslineError(
                f"{param('sensor_mass', f'{unknown[0]}=…')}: no accelerometer is at point {unknown[0]} "
                f"(the test's points are {known})"
            )

    def of(self, labels) -> np.ndarray:
        """The housing mass (kg) at each of ``labels`` (n,)."""
        return np.array([self.by_label.get(int(x), self.default) for x in labels], dtype=float)

    def describe(self) -> str:
        """'4 g each, 25 g at points 1, 2'."""
        text = f"{1e3 * self.default:g} g each"
        groups: dict[float, list] = {}
        for label, mass in sorted(self.by_label.items()):
            groups.setdefault(mass, []).append(str(label))
        for mass, labels in groups.items():
            text += f", {1e3 * mass:g} g at point{'s' if len(labels) > 1 else ''} {', '.join(labels)}"
        return text


def sensor_mass_token(text: str) -> str:
    """One ``--sensor-mass`` token, checked on its own (``KG`` or ``LABEL=KG``); the whole list by ``parse``."""
    HousingMasses.parse(["0", text] if "=" in text else [text])
    return text


def check_exciter_mass(mass: float, given: str | None = None) -> float:
    """The gauge's structure-side mass (kg), refused unless finite and ≥ 0 (``given``: as the user wrote it)."""
    if not (np.isfinite(mass) and mass >= 0):
        name = param("exciter_mass", given or f"{mass:g}")
        raise MasslineError(f"{name}: give the force gauge's structure-side mass in kg, 0 ≤ KG < inf (0: a hammer)")
    return float(mass)


def parse_exciter_mass(text: str) -> float:
    """``--exciter-mass KG``: a force gauge's structure-side mass, kg (finite, ≥ 0)."""
    try:
        mass = float(text)
    except ValueError:
        mass = np.nan
    return check_exciter_mass(mass, f"'{text}'")
