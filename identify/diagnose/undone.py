"""identify on the recording with the diagnosis's faults undone: the properties after, and each fault's proof;
and identify on the file as it came, the properties before (:func:`identified`).

One estimator and one χ²: a fault the diagnosis proposes is named only when undoing it lowers identify's χ² of
the masslines (Σ z², its σ from the band fits; with its transverse prior's) by more than ``EVIDENCE`` with the
other faults undone as well (leave one out). (A mass loading found against the mesh is proven by the mesh.) A
fault that does not is a name the line-level search gave a misfit it could not otherwise place (a plate on foam
took two hit locations that do not exist, and its properties after were worse than before): it is withdrawn,
the rest identified again, and what it was fitted to stays in identify's misfit, reported as
:mod:`.unexplained` when beyond chance.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from massline.identify.diagnose.corrections import corrected
from massline.identify.diagnose.criterion import EVIDENCE  # the same "very strong" evidence, on identify's χ²
from massline.identify.diagnose.effects import held, named
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.offsets import read_offset
from massline.identify.diagnose.shapes import channel_factor, objective, outfits, place_of
from massline.identify.pipeline import Identification, identify_recording
from massline.identify.suspicions import beyond_chance
from massline.identify.warning_codes import CodedWarning
from massline.core.errors import MasslineError
from massline.core.rigid_body import RigidBody

SIZED = 3.0  # an offset named must lie this many of its σ from none
MOST = 0.9  # share of identify's misfit beyond its dof the named faults must explain when they leave it beyond chance


def moved(without: RigidBody, with_: RigidBody) -> dict:
    """How far undoing a fault moves identify's properties: mass %, CoG mm, principal moments %."""
    return {
        "mass_percent": 100 * (with_.mass / without.mass - 1),
        "cog_mm": (1e3 * (with_.cog - without.cog)).tolist(),
        "principal_moments_percent": (100 * (with_.principal_moments / without.principal_moments - 1)).tolist(),
    }


def total_chi2(found: Identification) -> float:
    """identify's objective: the χ² of the masslines, Σ z², and of its transverse prior, Σ |τ_i|²/t² (nan with no
    redundancy). A misaligned accelerometer shows in the prior's term: identify reads it along its true axis."""
    return objective(found.best)


def undoable(findings: list) -> list:
    """The faults identify can be run with undone: on the recording, or by identify's own options."""
    return [f for f in findings if f.kind == "fault" and named(f.effect).undone_on in ("recording", "identify")]


def identified_after(recording, findings: list, band, transverse: float, before: Identification | None,
                     known: dict) -> tuple[Identification | None, list, list]:  # fmt: skip
    """identify (on ``band``: None, its own) on the recording with every fault undone; the findings, each fault's
    with how far undoing it moved the properties and how much of identify's χ² it explains (identify with all
    faults undone against with all but that one; no bootstrap); and the faults withdrawn.

    A fault that explains less than ``EVIDENCE`` of identify's χ² is withdrawn, and the others identified again
    (and a fault whose size does not say it is one, :func:`sized`);
    so are all of them when together they leave identify's χ² beyond chance having explained less than ``MOST`` of
    it (:func:`explains_the_misfit`). A gain is stated as identify reads it (:func:`by_identify`), and the other
    faults are proven with it so stated.
    When identify refuses the corrected recording, the properties stay ``before`` and the findings as they came
    (no finding says it moved them); where identify refused the file as it came too, the faults undid nothing
    identify can see and are withdrawn (a swapped pair on the structure, the swap out of the library, had been
    named a sensor's direction that left identify refusing the file). ``known``: identify's options for the
    masses the engineer gave (``sensor_mass``, ``exciter_mass``).
    """
    faults = undoable(findings)
    if not faults:
        return before, findings, []
    withouts = each_left_out(recording, faults, band, transverse, before, known)
    valued = {id(f): by_identify(f, without) for f, without in zip(faults, withouts)}
    read_again = any(valued[id(f)] is not f for f in faults)
    stated, faults = [valued.get(id(f), f) for f in findings], [valued[id(f)] for f in faults]
    if read_again and len(faults) > 1:  # a gain read again: the others' leave-one-out with it
        withouts = each_left_out(recording, faults, band, transverse, before, known)
    after = attempt(corrected(recording, faults), band, transverse, 100, **known | identify_options(faults))
    if before is None and not mends(after):  # refused as it came, and not mended: nothing is proven
        return None, [f for f in findings if f not in faults], faults
    if after is None:  # identify refuses the corrected recording
        return before, findings, []
    findings, proof = stated, {id(f): without for f, without in zip(faults, withouts)}
    sharing = shared_places(recording, faults, band, transverse, known)
    marked, withdrawn = judged(findings, proof, after, before, sharing)
    if withdrawn:
        again, kept, more = identified_after(recording, marked, band, transverse, before, known)
        return again, kept, withdrawn + more
    stand_ins = [f for f in undoable(marked) if not proven_apart(f)]
    if stand_ins and before is not None and not explains_the_misfit(before, after):
        again, kept, _ = identified_after(recording, [f for f in marked if f not in stand_ins], band, transverse,
                                          before, known)  # fmt: skip
        return again, kept, stand_ins
    return after, marked, []


def judged(findings: list, proof: dict, after: Identification, before: Identification | None,
           sharing: dict) -> tuple[list, list]:  # fmt: skip
    """The findings kept, each fault's with its evidence on identify's χ² (``proof``: identify with all faults but
    that one undone, by the finding's id), and those withdrawn: a fault that explains less than ``EVIDENCE``, one a
    factor at its place explains as well (:func:`.shapes.outfits`; the factor named instead where it is a gain,
    :func:`as_gain`), one whose size does not say it is one (:func:`sized`)."""
    marked, withdrawn, gains = [], [], set()
    for finding in findings:
        if id(finding) in proof and before is not None:
            without = proof[id(finding)]
            if without is not None:
                gain = total_chi2(without) - total_chi2(after)
                evidence = {**finding.evidence, "moved": moved(without.body, after.body), "chi2_explained": gain}
                finding = replace(finding, evidence=evidence)
                if not proven_apart(finding):
                    if gain < EVIDENCE:  # nan (no redundancy): nothing can check it
                        withdrawn.append(finding)
                        continue
                    place = place_of(finding)
                    here, standing = sharing.get(place, (without, finding))  # several faults there: all at once
                    shape = outfits(here, after, standing)
                    if shape is not None:  # a factor at its place explains as much: the name is not proven
                        withdrawn.append(replace(finding, evidence={**evidence, "outfitted_by": shape}))
                        marked += [] if place in gains else as_gain(finding, shape)
                        gains.add(place)
                        continue
        if not sized(finding):  # a sign read as a gain, or an offset within its own σ of none
            withdrawn.append(finding)
            continue
        marked.append(finding)
    return marked, withdrawn


def mends(after: Identification | None) -> bool:
    """Whether faults undone mend a file identify refused as it came: identify accepts the recording with them
    undone, and its rigid model then fits the masslines within chance (a finite reduced χ², not
    :func:`.suspicions.beyond_chance`). With no fit to prove against, that is the only proof: a sensor's direction
    named on a file cut short (two channels and two pairs gone, a gain inside) left χ² 13.4 over 14 and a body 23σ
    heavy."""
    return after is not None and np.isfinite(after.best.chi2) and not beyond_chance(after.best.chi2, after.best.dof)


def sized(finding) -> bool:
    """Whether a fault's size says it is one: a gain's factor positive (a negative one is a sign), an offset
    ``SIZED`` of its 1-σ from none (a plate's clean file had a 0.127 ± 0.123 mm sensor offset named on a χ² drop
    of 12.9); other faults, yes."""
    p = finding.parameters
    if finding.effect == "sensor_gain":
        return p.get("gain", 1.0) > 0
    if "distance_mm" in p and np.isfinite(p.get("distance_std_mm", np.nan)):
        return p["distance_mm"] > SIZED * p["distance_std_mm"]
    return True


def shared_places(recording, faults: list, band, transverse: float, known: dict) -> dict:
    """For each place that holds several faults: identify with the faults elsewhere undone, and one finding
    standing for them all (their values summed), for :func:`.shapes.outfits` to weigh them together against one
    factor there (None where identify refuses). Weighed one by one, each with the other undone, neither was
    outfitted: a 10 % gain on the structure's channel 3, the gain out of the library, was named a 23 mm offset
    with a tilt at that channel, each proven with the other, where the factor alone fits as well (χ² 5.63 against
    5.72)."""
    by_place = {}
    for f in faults:
        by_place.setdefault(place_of(f), []).append(f)
    out = {}
    for place, here in by_place.items():
        if len(here) < 2 or not any(place):
            continue
        rest = [f for f in faults if place_of(f) != place]
        values = sum(f.evidence.get("values", 0) for f in here)
        stand = replace(here[0], evidence={**here[0].evidence, "values": values})
        without = attempt(corrected(recording, rest), band, transverse, 0, **known | identify_options(rest))
        out[place] = (without, stand) if without is not None else None
    return {place: v for place, v in out.items() if v is not None}


def each_left_out(recording, faults: list, band, transverse: float, before: Identification | None,
                  known: dict) -> list:  # fmt: skip
    """identify (no bootstrap) with every fault but each one undone, in turn (None each where identify refuses,
    and all where there is no ``before`` to prove against)."""
    if before is None:
        return [None] * len(faults)
    out = []
    for k in range(len(faults)):
        rest = faults[:k] + faults[k + 1 :]
        out.append(attempt(corrected(recording, rest), band, transverse, 0, **known | identify_options(rest)))
    return out


def as_gain(finding, shape: dict) -> list:
    """The gain a one-channel factor is: a positive factor on one sensor's row, the shape that outfitted
    ``finding`` there, is the library's ``sensor_gain`` itself (to be proven as every fault is, and stated as
    identify reads it); [] for any other shape (a hit's column, several channels, a sign), or with no
    ``sensor_gain`` in the registry."""
    if not held("sensor_gain") or shape["columns"] or len(shape["rows"]) != 1 or not shape["factors"][0] > 0:
        return []
    evidence = {"instead_of": finding.effect, "outfitted": shape}
    return [Finding("sensor_gain", tuple(shape["rows"]), None, {"gain": shape["factors"][0], "gain_std": np.nan},
                    evidence)]  # fmt: skip


def by_identify(finding, without: Identification | None):
    """A gain as identify's estimator reads it: the channel's factor on identify's objective with the other faults
    undone (``without``), θ estimated again (:func:`.shapes.channel_factor`), in place of the line-level fit's, so
    that the gain stated is the one whose undoing gives the properties after; a sensor's or a hit's offset
    likewise, on the body the other channels (or hits) give (:func:`.offsets.read_offset`); other findings as
    they are."""
    if without is not None and finding.effect in ("sensor_location", "excitation_location"):
        return read_offset(finding, without)
    if finding.effect != "sensor_gain" or without is None:
        return finding
    line_std = finding.parameters.get("gain_std", np.nan)
    gain, std = channel_factor(without, finding.channels[0], line_std if np.isfinite(line_std) else None)
    if not np.isfinite(gain) or gain <= 0:  # a sign is no gain: left to the line-level's, withdrawn if negative
        return finding
    std = std if np.isfinite(std) and std > 0 else line_std  # no curvature to read: the line-level fit's 1-σ
    return replace(finding, parameters={**finding.parameters, "gain": gain, "gain_std": std})


def explains_the_misfit(before: Identification, after: Identification) -> bool:
    """Whether the faults undone leave identify's χ² within chance, or explain at least ``MOST`` of its excess
    over its degrees of freedom: a fault that takes a little off a misfit of another kind and leaves the rest is
    a stand-in (a stiff cord's misfit on the structure took a 'moved sensor' for 20 % of it)."""
    if not np.isfinite(after.best.chi2) or not beyond_chance(after.best.chi2, after.best.dof):
        return True
    excess = total_chi2(before) - before.best.dof
    return total_chi2(before) - total_chi2(after) >= MOST * excess


def best_undone(recording, findings: list, candidates: list, band, transverse: float, known: dict) -> list:
    """Of ``candidates`` (findings at one place), the one of least BIC on identify's masslines, χ² + k ln n (k the
    effect's values, n the masslines), with ``findings``' faults undone as well, as a list ([] when identify
    refuses every one); the other effects within ``EVIDENCE`` of it are its ``alternatives`` (the place is
    proven; which of them, the masslines cannot tell: one FRF's misfit is one number, a gain or a moved sensor)."""
    faults = undoable(findings)
    scored = []
    for candidate in candidates:
        trial = faults + [candidate]
        found = attempt(corrected(recording, trial), band, transverse, 0, **known | identify_options(trial))
        if found is not None:
            cost = candidate.evidence.get("values", 1) * np.log(np.count_nonzero(np.isfinite(found.sigma)))
            scored.append((total_chi2(found) + cost, candidate))
    if not scored:
        return []
    least, best = min(scored, key=lambda s: s[0])
    close = sorted({c.effect for chi2, c in scored if chi2 - least < EVIDENCE and c.effect != best.effect})
    return [replace(best, evidence={**best.evidence, "alternatives": close})]


def proven_by_mesh(finding) -> bool:
    """Whether the finding's evidence is the body's excess over the mesh (:mod:`.mass_loading`), which the
    masslines alone cannot show: a mass riding at every drive point looks, to them, like a heavier body."""
    return bool(finding.parameters.get("against_mesh"))


def proven_apart(finding) -> bool:
    """Whether the finding is proven where identify's masslines cannot show it: by the mesh (:func:`proven_by_mesh`)
    or by the band's lines (a channel's factor of frequency, :mod:`.row_factors`: a delay's phase and a mount's
    rise are taken up by each FRF's tails in identify's massline fit)."""
    return proven_by_mesh(finding) or named(finding.effect).model == "row"


def identify_options(findings: list) -> dict:
    """identify's options that undo the findings undone by identify itself (a gauge's mass: ``exciter_mass``)."""
    effects = [(named(f.effect), f) for f in findings]
    return {e.identify_option: e.option_value(f) for e, f in effects if e.undone_on == "identify"}


def attempt(recording, band, transverse: float, draws: int, **options) -> Identification | None:
    """identify on ``recording`` (with ``options``), or None when it refuses it or its solve fails."""
    try:
        return identify_recording(recording, band, transverse, draws=draws, **options)
    except (MasslineError, np.linalg.LinAlgError, ValueError):
        return None


def identified(recording, band, transverse: float, known: dict) -> tuple[Identification | None, tuple]:
    """identify's result on the file as it came (its own band; the diagnosis band ``band`` only when identify
    finds none), or None and a note saying why identify refuses it (a gross fault can leave the masslines
    fitting no body: the diagnosis is what finds it)."""
    try:
        return identify_recording(recording, None, transverse, **known), ()
    except MasslineError as reason:
        if band:
            try:
                return identify_recording(recording, band, transverse, **known), (
                    CodedWarning(
                        "identify_no_band", f"identify finds no band ({reason}): the properties are on the given band"
                    ),
                )
            except MasslineError as again:
                reason = again
        return None, (CodedWarning("identify_refused", f"identify refuses the file as it came ({reason})"),)
