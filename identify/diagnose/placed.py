"""Where the data put a fault: findings kept only at the place that holds identify's misfit.

identify's estimate with each channel, and each hit, left out (:mod:`.unexplained`) says where a file's misfit
sits. A fault the line-level search names elsewhere is a stand-in for it (a hit moved to absorb a channel's
gain); a fault named there that leaves its place's misfit beyond chance explained only part of it. Either way
the name is not what the data prove, and the findings' proof on identify's χ² (:mod:`.undone`) runs without it.
"""

from __future__ import annotations

from massline.identify.diagnose.shapes import SCALE_EFFECTS
from massline.identify.diagnose.undone import proven_apart, undoable


GROSS = 10.0  # reduced χ² left beyond which a misfit no one place holds still condemns the faults at its places


def where_the_misfit_is(found: list, misfit) -> tuple[list, list]:
    """The findings, less the faults named away from the one channel or hit that holds identify's whole misfit
    (``misfit``: the file's :func:`.unexplained.unexplained`; the rest fit within chance without that place),
    and those faults: the data put the fault there, and a fault elsewhere is a stand-in for it (a hit moved to
    absorb a channel's gain). Faults with no place (a gauge on every drive point) stay, unless the misfit is one
    channel's: a gauge's mass is on the excitation side, and one channel's misfit is not (an 8 mm sensor offset
    took a gauge's mass for 94 % of its χ² and left the rest 150× the noise). Where several places each hold it
    (the rest fit within chance without either), a fault at any of them stays (a tilted sensor on the structure,
    whose misfit leaving out the one channel that checks it fitted as well, had been set aside)."""
    if misfit is None or misfit.parameters["shape"] == "spread":
        return found, []
    p = misfit.parameters  # the place, and any other whose absence leaves the rest within chance too
    channels, hits = {*misfit.channels, *p.get("also_channels", ())}, {*p["hits"], *p.get("also_hits", ())}

    def elsewhere(f) -> bool:
        if f.kind != "fault" or proven_apart(f):
            return False
        if not f.channels and f.exciter is None:
            return misfit.parameters["shape"] == "one_channel"
        return not (set(f.channels) & channels or f.exciter in hits)

    return [f for f in found if not elsewhere(f)], [f for f in found if elsewhere(f)]


def at_the_misfit(findings: list, left) -> list:
    """The faults named at the one channel or hit that still holds identify's misfit with every fault undone
    (``left``: :func:`.unexplained.unexplained` of that; None or spread: none). The effect fitted part of its
    place's misfit and left the rest beyond chance there: the name is not what the data prove (the bracket's
    8 mm sensor offset on channel 5 was named an offset that left χ² 229 on 10 degrees of freedom). A factor's
    own effects (a gain, a sign) are the misfit's library-free shape (:mod:`.shapes`) and stay where what they
    leave is another misfit, reported beside them (a −11.7 % gain on the structure's channel 1, read as ×0.881,
    left 3.5× χ²'s dof at that channel's one FRF with one hit, which one more factor did not lower); a gain that
    leaves its whole row beyond chance is no factor on that row, and goes (with the sensor offset out of the
    library, an offset was named a gain that left χ² 9.7× its dof at its channel). Where the misfit left is gross
    (reduced χ² above ``GROSS``) and the data cannot tell its place from others (``also_channels``, ``also_hits``),
    a fault at any of them is one named where the misfit may still be (with the gauge's mass out of the library, a
    20 g gauge at the bracket's every drive point was named a 5° tilt of hit 3 that left χ² 167, which leaving out
    hit 1, 3 or 4 brought within chance); a small one that many places could each hold is not (a bracket's 9 mm
    sensor offset left χ² 2.1 that 7 channels and 4 hits could each take)."""
    if left is None or left.parameters["shape"] not in ("one_channel", "one_hit", "one_frf"):
        return []
    p = left.parameters  # the place, and where the misfit left is gross any other the data cannot tell from it
    channels, hits = set(left.channels), set(p["hits"])
    if left.evidence.get("chi2_reduced", 0.0) > GROSS:
        channels, hits = channels | set(p.get("also_channels", ())), hits | set(p.get("also_hits", ()))
    here = [f for f in undoable(findings) if set(f.channels) & channels or f.exciter in hits]
    row_left = left.parameters["shape"] == "one_channel"
    kept = tuple(e for e in SCALE_EFFECTS if e != "sensor_gain") if row_left else SCALE_EFFECTS
    return [f for f in here if not proven_apart(f) and f.effect not in kept]


def same_place(a, b) -> bool:
    """Whether two findings name one effect at one place (a finding and the one identify's proof returned)."""
    return (a.effect, a.channels, a.exciter) == (b.effect, b.channels, b.exciter)


def beside_a_spread_misfit(findings: list, left) -> list:
    """The faults named while identify's misfit with every fault undone is still beyond chance and held by no one
    channel or hit (``left``: :func:`.unexplained.unexplained` of that, shape ``spread``): a residual with structure
    left. Each fault explained part of a misfit no fault in the library explains, so none is what the data prove
    (with the gauge's mass out of the library, a 20 g gauge at the bracket's every drive point was named a 5° tilt
    of hit 3, χ² 6,714 → 167). Faults the mesh proves (an excess over its mass) stay: the masslines alone cannot
    show them."""
    if left is None or left.parameters["shape"] != "spread":
        return []
    return [f for f in undoable(findings) if not proven_apart(f)]
