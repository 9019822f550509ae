"""The effects' registry: one class per effect (one module each), listed once here.

Adding an effect is one new module and one line in ``EFFECTS`` (docs/adding-an-effect.md); everything that
lists effects reads this registry: ``massline simulate --effect`` (``parse_effect``, ``simulated``), the
simulator (it is handed the effect objects), the diagnosis (blocks, discrete fixes, tails, mass loading), the
findings' kind, notes, the demo and the blind scenarios. ``tests/test_effects_registry.py`` walks it.
"""

from __future__ import annotations

import math

from massline.core.errors import MasslineError, param
from massline.identify.diagnose.effects.base import Block, Effect, Scene
from massline.identify.diagnose.effects.channel_delay import ChannelDelay
from massline.identify.diagnose.effects.channel_swap import ChannelSwap
from massline.identify.diagnose.effects.excitation_direction import ExcitationDirection
from massline.identify.diagnose.effects.excitation_location import ExcitationLocation
from massline.identify.diagnose.effects.excitation_mass_loading import ExcitationMassLoading
from massline.identify.diagnose.effects.mains_interference import MainsInterference
from massline.identify.diagnose.effects.mount_resonance import MountResonance
from massline.identify.diagnose.effects.residual_flexibility import ResidualFlexibility
from massline.identify.diagnose.effects.sensor_direction import SensorDirection
from massline.identify.diagnose.effects.sensor_gain import SensorGain
from massline.identify.diagnose.effects.sensor_location import SensorLocation
from massline.identify.diagnose.effects.sensor_mass_loading import SensorMassLoading
from massline.identify.diagnose.effects.sensor_polarity import SensorPolarity
from massline.identify.diagnose.effects.suspension import Suspension
from massline.identify.diagnose.effects.transverse_sensitivity import TransverseSensitivity

EFFECTS: tuple[type[Effect], ...] = (
    SensorDirection,
    TransverseSensitivity,
    SensorGain,
    SensorPolarity,
    SensorLocation,
    SensorMassLoading,
    ChannelSwap,
    ChannelDelay,
    MountResonance,
    ExcitationDirection,
    ExcitationLocation,
    ExcitationMassLoading,
    Suspension,
    ResidualFlexibility,
    MainsInterference,
)
"""Every effect, in the order they are listed (``--help``, errors)."""

BY_NAME: dict[str, type[Effect]] = {cls.name: cls for cls in EFFECTS}


def named(name: str) -> type[Effect]:
    """The effect class of ``name`` (a KeyError for a name the registry does not hold)."""
    return BY_NAME[name]


def held(name: str) -> bool:
    """Whether the registry holds the effect ``name`` now (a test may take one out)."""
    return any(cls.name == name for cls in EFFECTS)


def simulated() -> tuple[type[Effect], ...]:
    """The effects ``massline simulate --effect`` conceals."""
    return tuple(cls for cls in EFFECTS if cls.simulated)


def modelled(model: str) -> tuple[type[Effect], ...]:
    """The effects the diagnosis models as ``model`` ("block", "discrete", "tail", "mass", "gauge", "lines", "row")."""
    return tuple(cls for cls in EFFECTS if cls.model == model)


def effect_help() -> str:
    """The ``--effect`` help: every simulated effect with its size's unit (a discrete one with its syntax)."""
    listed = ", ".join(cls.described() for cls in simulated())
    return f"an instrumentation effect (repeatable; WHERE: 1-based lines, e.g. 3,5, or all): {listed}"


def parse_effect(text: str) -> Effect:
    """``NAME[=SIZE][@WHERE]``, e.g. ``sensor_direction=3@4``, ``transverse_sensitivity=0.03@all``.

    WHERE is a 1-based sensor (or exciter) number, several numbers separated by commas, or ``all``; without it
    one line is drawn at random. Sensor numbers count channels (a triaxial accelerometer has three). An effect
    whose ``place`` is "frequency" reads WHERE as a frequency in Hz (``mains_interference=0.1@50``). SIZE must be
    finite, and each effect checks its own size and place.
    """
    head, _, where = text.partition("@")
    name, has_size, size = head.partition("=")
    name = name.strip()
    names = [cls.name for cls in simulated()]
    if name not in names:
        raise MasslineError(f"unknown effect '{name}': use one of {', '.join(names)}")
    cls = named(name)
    if not has_size and not cls.discrete:
        raise MasslineError(f"effect {name} needs a size: {cls.syntax()} (see 'massline simulate --help')")
    try:
        value = float(size) if has_size else 0.0
        place = cls.parse_place(where)
    except ValueError:
        example = "NAME=SIZE@N or NAME=SIZE@all" if cls.place == "lines" else cls.syntax()
        raise MasslineError(f"cannot read effect '{text}': write {example}") from None
    if not math.isfinite(value):
        raise MasslineError(f"{param('effect', repr(text), cli=text)}: the size must be a finite number")
    cls.check_size(value)
    cls.check_place(place)
    return cls(value, place)


__all__ = ["BY_NAME", "EFFECTS", "Block", "Effect", "Scene", "effect_help", "modelled", "named", "parse_effect"]
__all__ += ["simulated"]
