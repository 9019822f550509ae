"""A finding: one effect the recording shows, where, its fitted parameters and the evidence for it;
and the finding an accepted effect of a fit makes."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.identify.diagnose.effect_fit import Fit
from massline.identify.diagnose.effects import named
from massline.identify.mains import MainsLines
from massline.identify.tails import BandData
from massline.core.effect_names import KINDS

UNEXPLAINED = KINDS[2]  # the finding no effect of the library explains: its effect name is its kind


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

    @property
    def kind(self) -> str:
        """ "fault" (the engineer's to mend), "test_physics" (the support and the elastic modes: modelled) or
        "unexplained" (a located misfit no effect of the library explains: :mod:`.unexplained`)."""
        return UNEXPLAINED if self.effect == UNEXPLAINED else named(self.effect).kind


def faults_first(findings: list) -> list:
    """The findings with the faults first, then the test physics, then what is unexplained, each group in its
    order (DESIGN.md)."""
    return [f for kind in KINDS for f in findings if f.kind == kind]


def accepted_finding(result: Fit, band: BandData, what, evidence: dict, resonances: dict | None = None) -> Finding:
    """The accepted effect (a block, or a tail law's name) with its fitted parameters (SI, with 1-σ where the fit
    gives them): a block's from its effect's ``parameters``, a tail law's from its ``tail_parameters`` with the
    frequency of the mode behind it (``resonances``: law → Hz, nan when the record does not resolve it)."""
    if isinstance(what, str):
        effect = named(what)
        mode = (resonances or {}).get(what, np.nan)
        parameters = effect.tail_parameters(band, result.problem.data, mode)
        return Finding(what, (), None, parameters, {**evidence, **effect.tail_evidence(result.problem.data)})
    effect = named(what.effect)
    parameters = effect.parameters(result, what)
    evidence = {"values": result.problem.layout.size(what), **evidence}  # the free values it paid for (BIC)
    if effect.perturbs == "sensor":
        return Finding(what.effect, tuple(result.problem.layout.channels(what)), None, parameters, evidence)
    return Finding(what.effect, (), what.target, parameters, evidence)


def mains_finding(mains: MainsLines) -> Finding:
    """The mains interference identify set aside (:mod:`massline.identify.mains`), as a test-physics finding: its
    fundamental (Hz), the harmonics found, their size relative to the FRFs' level and the lines set aside."""
    return Finding("mains_interference", (), None, mains.parameters, mains.evidence)


def finding_payload(finding: Finding, recording) -> dict:
    """DESIGN.md's finding: effect, kind, sensor / excitation as {"node", "dir"}, parameters, evidence."""

    def channel(labels, index):
        if labels is None:
            return {"node": None, "dir": None, "index": index + 1}
        node, code = labels[index]
        return {"node": int(node), "dir": int(code)}

    sensor = channel(recording.sensor_labels, finding.channels[0]) if finding.channels else None
    excitation = None if finding.exciter is None else channel(recording.exciter_labels, finding.exciter)
    parameters = dict(finding.parameters)
    if "hits" in parameters:  # an unexplained misfit's hits, 0-based
        parameters["hits"] = [channel(recording.exciter_labels, j) for j in parameters["hits"]]
    if len(finding.channels) > 1:
        parameters["channels"] = [channel(recording.sensor_labels, c) for c in finding.channels]
    evidence = {k: (np.asarray(v).tolist() if isinstance(v, np.ndarray) else v) for k, v in finding.evidence.items()}
    return {
        "effect": finding.effect,
        "kind": finding.kind,
        "sensor": sensor,
        "excitation": excitation,
        "parameters": parameters,
        "evidence": evidence,
    }
