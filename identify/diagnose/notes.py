"""A diagnosis finding as an engineer would write it: one sentence (each effect's own, :mod:`.effects`)."""

from __future__ import annotations

from massline.identify.diagnose.effects import named
from massline.identify.diagnose.finding import Finding
from massline.core.numbers import formatted


def finding_note(finding: Finding, sensors: list, hits: list) -> str:
    """One sentence: what is wrong, where, how large, and what was done about it.

    ``sensors``, ``hits``: the channels' labels (:class:`massline.uff.recording.Channel`), indexed as the finding's.
    """
    e = finding.evidence
    names = [sensors[c] for c in finding.channels]
    if len(names) == 3 and names[0].node is not None and len({n.node for n in names}) == 1:
        who = f"the triaxial sensor at node {names[0].node}"
    else:
        who = " and ".join(f"sensor {n}" for n in names)
    hit = None if finding.exciter is None else f"hit {hits[finding.exciter]}"
    also = e.get("alternatives") or []
    tail = f" (the data fit {' or '.join(also)} there as well)" if also else ""
    moved = e.get("moved")
    shift = f"; undoing it moves identify's mass by {formatted(moved['mass_percent'], '+.3f')} %" if moved else ""
    return named(finding.effect).sentence(finding, who, hit) + tail + shift
