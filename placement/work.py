"""Work budgets: a search that may run long counts its work in units of the same size on any machine (not in
seconds, so that where it stops is reproducible on a machine, whatever its load) and stops at its limit, saying
what it reached. The count itself is not the same on every CPU: the diagnosable search meets trials tied in
exact arithmetic, which the BLAS kernel's rounding orders (docs/validation.md, planned supports and bands).

The diagnosable search (:mod:`.diagnosable_plan`) counts diagnosability evaluations: one per layout whose
leverages and confusions (:mod:`.diagnosability`) are computed, a stack of trials counting as many as it holds.
The D certificate (:mod:`.certification`) counts relaxation steps: one per step of the first-order relaxation
(:func:`.relaxation.relax_first_order`) of any branch-and-bound node; its parts stop at marks on one count.
"""

from __future__ import annotations

from dataclasses import dataclass

STEPS = "relaxation steps"  # the D certificate's unit of work (:mod:`.certification`)
DEFAULT_STEPS = 100_000  # a branch and bound run with no budget given


class WorkSpent(Exception):
    """A search's work budget ran out (:class:`Work`); the search unwinds to where it can say what it reached."""


@dataclass(eq=False)
class Work:
    """Units of work a search may spend (``limit``), those spent so far, and what one unit is (``unit``, plural).

    Mutable on purpose: one budget is shared by every planner of a search and spent as they evaluate.
    """

    limit: int
    unit: str
    spent: int = 0

    def tally(self, units: int = 1) -> None:
        """Count ``units`` without stopping: a search that checks :meth:`reached` itself (the certificate)."""
        self.spent += units

    def reached(self, mark: int | None = None) -> bool:
        """Whether the units spent have come to ``mark`` (default: the limit)."""
        return self.spent >= (self.limit if mark is None else mark)

    def spend(self, units: int) -> None:
        """Count ``units``; past the limit, raise :class:`WorkSpent` (what was spent stays counted)."""
        self.spent += units
        if self.spent > self.limit:
            raise WorkSpent(f"{self.spent} of {self.limit} {self.unit}")

    @property
    def fraction(self) -> float:
        """The part of the budget spent, 0 to 1."""
        return min(self.spent / self.limit, 1.0) if self.limit > 0 else 1.0


@dataclass(frozen=True)
class Reached:
    """What a budgeted search spent and reached: ``spent`` of ``limit`` ``unit``, ``stopped`` when its budget ended
    it, and ``what`` it reached (a phrase)."""

    spent: int
    limit: int
    unit: str
    stopped: bool
    what: str

    @property
    def sentence(self) -> str:
        """"stopped after N of M units; reached …" when stopped, else what it found and what that took."""
        if self.stopped:
            return f"stopped after {self.spent} of {self.limit} {self.unit}; reached {self.what}"
        return f"{self.what} ({self.spent} of {self.limit} {self.unit})"

    def as_dict(self) -> dict:
        """JSON-ready, the sentence included."""
        return {
            "stopped": self.stopped,
            "spent": self.spent,
            "limit": self.limit,
            "unit": self.unit,
            "reached": self.what,
            "sentence": self.sentence,
        }
