"""What the findings leave unexplained: identify's misfit beyond chance, located and read for its shape.

The diagnosis names an effect only when the data prove it; what no named effect explains is not given the
nearest name but reported as an ``unexplained`` finding (DESIGN.md's ``kind``): identify's rigid model on the
recording with every named fault undone still leaves a reduced χ² beyond chance (the one test,
:func:`massline.identify.suspicions.beyond_chance`). The finding says where the misfit sits and what shape it
has, in identify's standardised residuals z_ij = (A_ij − Â_ij)/σ_ij of the masslines:

* **where**: identify's estimate again with each channel (row i) left out in turn, and each hit (column j): the
  one whose absence leaves the least misfit holds the most of it. Leaving out is exact where a linear score
  test is not: each channel's transverse reading (identify's prior) takes up part of a faulty channel's misfit
  and spreads the rest over the channels that check it (a 10 % gain on the bracket's channel 5 left its
  largest residual on channel 4);
* **shape**: one channel, when the rest fit within chance without it (its gain, direction, place, housing or
  cable); one hit, likewise; one FRF, when leaving out either its channel or its hit does (a channel the others
  check through one hit only: the default plans have them); or spread, when no one channel or hit holds it
  (physics the rigid model leaves out: the support acting through the body's flexibility, elastic modes
  reaching into the band, several faults at once), its largest part still named.

Within chance in the masslines, a channel can still be off: identify reads each channel along its axis plus a
transverse part under the datasheet's prior, and takes a misaligned accelerometer up there (the bracket's 8°
tilt on channel 9: read as 7.9°, χ² 0.89). A channel read further off its label than the prior allows by
chance is the finding ``off_axis`` (:func:`off_axis`).
"""

from __future__ import annotations

import numpy as np


from massline.core.chi_square import chi2_isf
from massline.identify.diagnose.finding import Finding
from massline.identify.diagnose.signature import phrase
from massline.identify.estimator import Estimate, estimate
from massline.core.errors import MasslineError, solver_errors
from massline.core.masslines import Masslines
from massline.identify.suspicions import CHANCE, beyond_chance

SHAPES = {
    "one_channel": "the rest fit within the noise without this channel (its gain, direction, place or housing, "
    "or its cable)",
    "one_hit": "the rest fit within the noise without this hit (the excitation side: its place, direction, a "
    "force gauge's mass, the force's calibration)",
    "one_frf": "the rest fit within the noise without this one FRF, which both its channel and its hit hold "
    "(the channel's gain or direction where the others barely check it, the hit's place or force, their cables)",
    "spread": "no one channel or hit holds it (physics the rigid model leaves out: the support acting through "
    "the body's flexibility, elastic modes in the band, several faults at once)",
    "against_mesh": "the body identified is heavier than the mesh's in the pattern of a mass there",
    "in_frequency": "its lines depart in frequency from the rigid motion the other channels see, which its "
    "masslines do not show",
    "refused": "the channel farthest from the others' rigid motion (a flipped or swapped channel, or a band across a "
    "resonance)",
}


def left_out(found, axis: int, k: int):
    """identify's estimate without row ``k`` (``axis`` 0: a channel) or column ``k`` (``axis`` 1: a hit) of its
    masslines, with the same 1-σ, prior and riding masses; None when the rest cannot be estimated."""
    data, best = found.data, found.best
    rows = [i for i in range(data.values.shape[0]) if not (axis == 0 and i == k)]
    columns = [j for j in range(data.values.shape[1]) if not (axis == 1 and j == k)]
    sub = Masslines(data.values[np.ix_(rows, columns)], data.sensors[rows], data.exciters[columns])
    riding = None if best.riding is None else best.riding[columns]
    return estimated(found, sub, found.sigma[np.ix_(rows, columns)], riding)


def estimated(found, data: Masslines, sigma: np.ndarray, riding: np.ndarray | None) -> Estimate | None:
    """identify's estimate of ``data`` (1-σ ``sigma``, ``riding`` masses) with ``found``'s planarity and
    transverse prior; None when it cannot be estimated."""
    try:
        with np.errstate(invalid="ignore", divide="ignore"):
            return estimate(data, sigma, found.planar, found.best.prior, riding=riding)
    except (np.linalg.LinAlgError, MasslineError, ValueError, *solver_errors()):
        return None


def leave_one_out(found, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Σ z² identify's rigid model leaves with each channel (``axis`` 0) or hit (``axis`` 1) left out in turn, and
    its degrees of freedom (inf and 0 where the rest cannot be estimated).

    Where the masslines left have no redundancy of their own (on the structure's default plan, 9 channels × 4
    hits, leaving out any hit leaves 27 masslines for the 10 properties and the channels' 18 transverse
    readings), the datasheet's prior on those readings is what checks them: the sum is then the whole
    objective, masslines and prior rows (:func:`prior_checked`)."""
    left, dof = [], []
    for k in range(found.data.values.shape[axis]):
        e = left_out(found, axis, k)
        if e is None:
            left.append(np.inf), dof.append(0.0)
        elif np.isfinite(e.chi2) and e.dof > 0:
            left.append(e.chi2 * e.dof), dof.append(e.dof)
        else:
            total, n = prior_checked(e, np.delete(found.sigma, k, axis=axis))
            left.append(total if n > 0 else np.inf), dof.append(float(max(n, 0)))
    return np.array(left), np.array(dof)


def prior_checked(e: Estimate, sigma: np.ndarray) -> tuple[float, int]:
    """The objective of estimate ``e`` with its transverse prior counted as data, and its degrees of freedom.

    Σ_ij z_ij² + Σ_i |τ_i|²/σ_τ² (τ_i: channel i's transverse reading, σ_τ the prior's 1-σ): each of the 2 n_s
    prior rows is one datum and its τ one parameter, so the degrees of freedom are the masslines less the p
    properties. On the structure's default plan with its tilted hit left out it is 0.05 of its 17 dof; with any
    other hit left out, 6.3–11.2."""
    z = e.residual / sigma
    return float(np.nansum(z**2) + np.sum(tilts(e))), int(np.isfinite(z).sum()) - e.model.p


def within_chance(total: float, dof: float) -> bool:
    """Whether Σ z² ``total`` over ``dof`` degrees of freedom is within chance (no dof left: nothing says so)."""
    return dof > 0 and not beyond_chance(total / dof, dof)


def unexplained(found, withdrawn: list = ()) -> Finding | None:
    """The ``unexplained`` finding of identify's result ``found`` (an ``Identification``, the recording with the
    named faults undone), or None when its reduced χ² is within chance.

    ``channels``: the rows beyond chance; ``parameters``: the hits beyond chance (0-based), the shape (a key of
    ``SHAPES``), each channel's and hit's share of the misfit, and the other channels and hits whose absence
    leaves the rest within chance too (``also_channels``, ``also_hits``: a tilted sensor on the structure left the
    rest within chance without it and without the one channel that checked it); ``evidence``: the reduced χ² and
    its dof, and the faults the search proposed but identify's χ² did not prove (``withdrawn``: their effect names).
    """
    best = found.best
    if not beyond_chance(best.chi2, best.dof):
        return off_axis(found, withdrawn)
    total = float(best.chi2 * best.dof)
    (rows, row_dof), (columns, column_dof) = leave_one_out(found, 0), leave_one_out(found, 1)
    channel, hit = int(np.argmin(rows)), int(np.argmin(columns))
    by_channel = within_chance(rows[channel], row_dof[channel])
    by_hit = within_chance(columns[hit], column_dof[hit])
    shape = {(True, True): "one_frf", (True, False): "one_channel", (False, True): "one_hit"}.get(
        (by_channel, by_hit), "spread"
    )
    checked = {"channel": bool(np.isfinite(rows[channel])), "hit": bool(np.isfinite(columns[hit]))}
    parameters = {  # a spread misfit's largest part, where leaving it out can be checked at all
        "hits": [hit] if shape in ("one_hit", "one_frf") or (shape == "spread" and checked["hit"]) else [],
        "shape": shape,
        "explained_without_channel": np.where(np.isfinite(rows), 1 - rows / total, np.nan).tolist(),
        "explained_without_hit": np.where(np.isfinite(columns), 1 - columns / total, np.nan).tolist(),
    }
    channels = [channel] if shape in ("one_channel", "one_frf") or (shape == "spread" and checked["channel"]) else []
    fitting = {  # the other places whose absence leaves the rest within chance too: the data cannot tell them apart
        "also_channels": [i for i in np.argsort(rows) if i not in channels and within_chance(rows[i], row_dof[i])],
        "also_hits": [j for j in np.argsort(columns) if j not in parameters["hits"]
                      and within_chance(columns[j], column_dof[j])],
    }  # fmt: skip
    parameters.update({key: [int(k) for k in places] for key, places in fitting.items()})
    evidence = {"chi2_reduced": best.chi2, "dof": best.dof, "withdrawn": sorted({f.effect for f in withdrawn}),
                "outfitted": outfitted(withdrawn)}  # fmt: skip
    return Finding("unexplained", tuple(channels), None, parameters, evidence)


def refused_misfit(screens: dict, withdrawn: list = ()) -> Finding:
    """The ``unexplained`` finding of a file identify refuses (no rigid body fits its masslines) where no fault
    named undoes it: the misfit is there, whole, and the model-free screen places it at the channel farthest
    from the others' rigid motion (``screens``' LOCO misfit; no channel where the layout has no redundancy)."""
    misfit = screens.get("channel_consistency")
    channels = [] if not misfit or not np.isfinite(misfit).any() else [int(np.nanargmax(misfit))]
    parameters = {"hits": [], "shape": "refused", "also_channels": [], "also_hits": []}
    evidence = {"chi2_reduced": np.nan, "dof": 0.0, "withdrawn": sorted({f.effect for f in withdrawn}),
                "outfitted": outfitted(withdrawn)}  # fmt: skip
    return Finding("unexplained", tuple(channels), None, parameters, evidence)


def excess_over_mesh(loading, withdrawn: list = ()) -> Finding:
    """The ``unexplained`` finding of a body heavier than the mesh's in the pattern of a loading
    (:mod:`.mass_loading`) whose effect the library does not hold: where (the housing's channels, or the drive
    points), and how much."""
    finding = loading.finding()
    grams = finding.parameters.get("mass_kg", sum(finding.parameters.get("masses_kg", [0.0])))
    parameters = {"hits": [], "shape": "against_mesh", "also_channels": [], "also_hits": [], "mass_kg": grams,
                  "excitation_side": loading.side == "excitation"}  # fmt: skip
    evidence = {"chi2_reduced": np.nan, "dof": 0.0, "withdrawn": sorted({f.effect for f in withdrawn}),
                "outfitted": outfitted(withdrawn), "against_mesh_chi2": finding.evidence["chi2_before"]}  # fmt: skip
    return Finding("unexplained", tuple(int(c) for c in finding.channels), None, parameters, evidence)


def outfitted(withdrawn: list) -> list[dict]:
    """The withdrawn faults a factor at their place fitted as well (:func:`.shapes.outfits`): effect, place,
    factors."""
    return [{"effect": f.effect, **f.evidence["outfitted_by"]} for f in withdrawn if "outfitted_by" in f.evidence]


def tilts(best: Estimate) -> np.ndarray:
    """|τ_i|²/t² per channel: an estimate's transverse reading of each against its datasheet prior t (0 on a
    plate)."""
    return np.sum(best.transverse**2, axis=1) / best.prior**2 if best.prior > 0 else np.zeros(len(best.transverse))


def off_axis(found, withdrawn: list = ()) -> Finding | None:
    """The ``unexplained`` finding of a channel identify reads along an axis further off its label than the
    datasheet's cross-axis reading allows by chance (|τ|²/t² beyond χ²(2) at ``CHANCE``): the masslines fit,
    because identify took the tilt up; None when every channel is within its prior."""
    z2 = tilts(found.best)
    channel = int(np.argmax(z2)) if z2.size else 0
    if not z2.size or z2[channel] <= chi2_isf(CHANCE, 2):
        return None
    angle = float(np.degrees(np.arctan(np.sqrt(z2[channel]) * found.best.prior)))
    parameters = {"hits": [], "shape": "off_axis", "angle_deg": angle}
    evidence = {"chi2_reduced": found.best.chi2, "dof": found.best.dof, "prior_chi2": float(z2[channel]),
                "withdrawn": sorted({f.effect for f in withdrawn})}  # fmt: skip
    return Finding("unexplained", (channel,), None, parameters, evidence)


def sentence(finding: Finding, sensors: list, hits: list) -> str:
    """The unexplained finding as an engineer would read it: how far beyond the noise, where, which shape."""
    p, e = finding.parameters, finding.evidence
    places = [f"sensor {sensors[c]}" for c in finding.channels] + [f"hit {hits[j]}" for j in p["hits"]]
    where = f"{'the largest part' if p['shape'] == 'spread' else 'most of it'} at {' and '.join(places)}: "
    where = where if places else "the layout cannot place it (no channel or hit can be left out and checked): "
    also = [f"sensor {sensors[c]}" for c in p.get("also_channels", [])]
    also += [f"hit {hits[j]}" for j in p.get("also_hits", [])]
    where = where.replace(": ", f" (or {' or '.join(also)}, which the data cannot tell apart): ", 1) if also else where
    factors = e.get("outfitted") or []
    tried = [t for t in e.get("withdrawn") or [] if t not in {f["effect"] for f in factors}]
    unproven = f"; {' and '.join(tried)} fitted part of it but did not explain identify's misfit" if tried else ""
    unproven += "".join(f"; {factor_phrase(f, sensors, hits)}" for f in factors)
    none = (
        "the data place it but cannot tell these apart, so none is named"
        if factors
        else "no effect of the library explains it, so none is named"
    )
    shape = f"; its signature: {phrase(p['signature'])}" if "signature" in p else ""
    if p["shape"] == "in_frequency":
        return (
            f"unexplained: sensor {sensors[finding.channels[0]]}: {SHAPES['in_frequency']} "
            f"({np.sqrt(e['chi2_reduced']):.1f}× the noise on its lines){shape}; no effect of the library explains it, "
            "so none is named"
        )
    if p["shape"] == "off_axis":
        return (
            f"unexplained: identify reads sensor {sensors[finding.channels[0]]} along an axis {p['angle_deg']:.1f}° "
            f"off its label, {np.sqrt(e['prior_chi2']):.1f}× the datasheet's cross-axis reading{unproven}{shape}; "
            f"{none}"
        )
    if p["shape"] == "against_mesh":
        where = " and ".join(places) if places else ("the drive points" if p["excitation_side"] else "no one place")
        return (
            f"unexplained: the body identified is {1e3 * p['mass_kg']:.3g} g heavier than the mesh's, in the pattern "
            f"of a mass at {where}{unproven}; {none}"
        )
    if p["shape"] == "refused":
        where = f"most of it at {' and '.join(places)}, {SHAPES['refused']}" if places else "the layout cannot place it"
        return f"unexplained: identify finds no rigid body that fits the masslines; {where}{unproven}; {none}"
    return (
        f"unexplained: with every named fault undone the rigid model still leaves {np.sqrt(e['chi2_reduced']):.1f}× "
        f"the noise in the masslines (reduced χ² {e['chi2_reduced']:.3g}); {where}{SHAPES[p['shape']]}{unproven}"
        f"{shape}; {none}"
    )


def factor_phrase(shape: dict, sensors: list, hits: list) -> str:
    """A withdrawn fault a factor outfitted, as the engineer reads it."""
    places = [f"sensor {sensors[i]}" for i in shape["rows"]] + [f"hit {hits[j]}" for j in shape["columns"]]
    factors = ", ".join(f"×{g:.3g}" for g in shape["factors"])
    return (
        f"{shape['effect']} fits it, but one factor on {' and '.join(places)}'s FRFs ({factors}: a gain, a "
        "calibration, a sign) fits at least as well, counting the values each is fitted with"
    )
