"""A finding: one effect the recording shows, where, its fitted parameters and the evidence for it."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Finding:
    """One effect of the library, found in the data.

    Attributes
    ----------
    effect : str
        The effect's name (DESIGN.md's list).
    channels : tuple of int
        Sensor channels it concerns (0-based; empty for an exciter or a global effect).
    exciter : int or None
        The exciter it concerns (0-based).
    parameters, evidence : dict
        JSON-ready: fitted values (SI, angles in degrees) and the statistics that support it.
    """

    effect: str
    channels: tuple = ()
    exciter: int | None = None
    parameters: dict = field(default_factory=dict)
    evidence: dict = field(default_factory=dict)
