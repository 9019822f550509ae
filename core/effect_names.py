"""The effects' vocabulary: what every effect is made of, for the simulator, the diagnosis and DESIGN.md's JSON.

An effect is what turns the ideal test (a free rigid body, every line as labelled) into the one
recorded. Faults are the engineer's to mend (instrumentation, excitation, mass loading); test
physics every real test has and the model carries (the support below the band, the elastic modes
above it); ``unexplained`` (a later finding kind) is a located misfit no registered effect explains.

The effects themselves are classes in :mod:`massline.identify.diagnose.effects` (the registry). The
layers below ``identify`` (the virtual test) cannot import it: they are handed effect objects and use
them through :class:`SimulatedEffect` only.
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

KINDS = ("fault", "test_physics", "unexplained")
"""A finding's ``kind`` in the diagnose JSON (DESIGN.md), faults first."""

PERTURBS = ("sensor", "exciter", "support", "modes")
"""What an effect changes in a simulated test: an accelerometer line (or its channel), a hit line, the
support the body hangs on, the body's elastic modes. Only the first two are ``--effect`` arguments; the
support and the modes are simulated by the virtual test's own support and FE model."""


class SimulatedEffect(Protocol):
    """An effect as the virtual test applies it (duck-typed: the registry's classes are these).

    Attributes
    ----------
    name : str
        The effect's name (DESIGN.md's list).
    size : float
        Its size, in the effect's unit (degrees, fraction, m, kg; 0 for a discrete effect).
    where : tuple of int, "all", float or None
        0-based lines it sits on, every line, or None for one drawn at random; a frequency (Hz) when ``place``
        is "frequency" (the effect is on every line).
    perturbs : str
        "sensor" or "exciter": which lines ``where`` counts.
    place : str
        What ``where`` is: "lines" or "frequency".
    """

    name: str
    size: float
    where: tuple | str | float | None
    perturbs: str
    place: str

    def simulate(self, state, lines, targets: list[int], rng: np.random.Generator) -> dict:
        """Change ``state`` (the instrumentation being built: points, vectors, masses, channel order) on the
        ``targets`` among ``lines``; return what was drawn (perpendiculars, offsets) for the truth file."""
        ...
