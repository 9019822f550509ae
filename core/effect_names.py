"""The effects' names: one list for the simulator, the diagnosis and DESIGN.md's diagnose JSON.

An effect is what turns the ideal test (a free rigid body, every line as labelled) into the one
recorded. Faults are the engineer's to mend (instrumentation, excitation, mass loading); test
physics every real test has and the model carries (the support below the band, the elastic modes
above it).
"""

from __future__ import annotations

SENSOR_EFFECTS = (
    "sensor_direction",
    "transverse_sensitivity",
    "sensor_gain",
    "sensor_polarity",
    "sensor_location",
    "sensor_mass_loading",
    "channel_swap",
)
"""What can be wrong with an accelerometer or its channel, as the simulator conceals it."""

EXCITER_EFFECTS = ("excitation_direction", "excitation_location")
"""What can be wrong with a hammer hit."""

TEST_PHYSICS = ("suspension", "residual_flexibility")
"""The physics of every test: a support mode below the band, an elastic mode above it (tails)."""

DISCRETE = ("sensor_polarity", "channel_swap")
"""Effects without a size: a sign flipped, two channels exchanged."""

SIMULATED = SENSOR_EFFECTS + EXCITER_EFFECTS
"""The instrumentation effects ``massline simulate --effect`` conceals."""

DIAGNOSED = tuple(name for name in SIMULATED if name != "transverse_sensitivity") + TEST_PHYSICS
"""The effects ``massline diagnose`` names (DESIGN.md). Transverse sensitivity is no finding: every channel's
transverse reading is estimated under the datasheet's prior, and one beyond it is a ``sensor_direction``."""


def kind(name: str) -> str:
    """ "test_physics" for the support and the elastic modes, "fault" for everything else (DESIGN.md)."""
    return "test_physics" if name in TEST_PHYSICS else "fault"
