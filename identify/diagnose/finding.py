"""A finding: one effect the recording shows, where, its fitted parameters and the evidence for it;
and the finding an accepted effect of a fit makes."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from massline.identify.diagnose.effect_fit import Fit
from massline.identify.tails import BandData
from massline.core.effect_names import kind


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
        """ "fault" (the engineer's to mend) or "test_physics" (the support and the elastic modes: modelled)."""
        return kind(self.effect)


def faults_first(findings: list) -> list:
    """The findings with the faults first, each group in its order (DESIGN.md)."""
    return [f for f in findings if f.kind == "fault"] + [f for f in findings if f.kind != "fault"]


def accepted_finding(result: Fit, band: BandData, what, evidence: dict, resonances: dict | None = None) -> Finding:
    """The accepted effect with its fitted parameters (SI, with 1-σ where the fit gives them).

    A tail law (test physics) carries its size at the band's edge relative to the FRF matrix's scale (the RMS
    of every massline: a small cross massline is no scale) and the frequency of the mode behind it where the
    record resolves its peak (``resonances``: law → Hz, nan when it does not), never a fitted pole's.
    """
    if isinstance(what, str):
        size = band.tail_size(result.problem.data, what)
        edge = band.frequencies[0] if what == "suspension" else band.frequencies[-1]
        mode = (resonances or {}).get(what, np.nan)
        parameters = {
            "edge_hz": float(edge),
            "tail_median": float(np.median(size)),
            "tail_max": float(size.max()),
            "mode_hz": None if not np.isfinite(mode) else float(mode),
        }
        if what == "suspension":  # its tail the rigid body's, s_iᵀ X e_j on every FRF, or each FRF's own
            evidence = {**evidence, "tail": "rigid_body" if result.problem.data.shared else "per_frf"}
        return Finding(what, (), None, parameters, evidence)
    layout = result.problem.layout
    theta, tau, values = result.parts
    v = values[result.blocks.index(what)]
    sigma = result.block_std(what)
    if what.effect.startswith("sensor"):
        channels = layout.channels(what)
        d = layout.sensors.directions[channels]
        if what.effect == "sensor_direction":
            T = layout.sensor_bases[list(channels)]
            axis = d + np.einsum("nak,nk->na", T, tau[list(channels)])
            angles = np.degrees(np.arctan(np.linalg.norm(tau[list(channels)], axis=1)))
            spread = np.degrees(np.linalg.norm(result.tau_std[list(channels)], axis=1))
            parameters = {
                "angle_deg": angles.tolist(),
                "angle_std_deg": spread.tolist(),
                "effective_axis": (axis / np.linalg.norm(axis, axis=1)[:, None]).tolist(),
            }
        elif what.effect == "sensor_gain":
            parameters = {"gain": float(1 + v[0]), "gain_std": float(sigma[0])}
        else:
            offset = v if len(v) == 3 else layout.sensor_bases[channels[0]] @ v
            parameters = {
                "offset_m": offset.tolist(),
                "distance_mm": float(1e3 * np.linalg.norm(offset)),
                "distance_std_mm": float(1e3 * np.linalg.norm(sigma)),
            }
        return Finding(what.effect, tuple(channels), None, parameters, evidence)
    j = what.target
    U = layout.exciter_bases[j]
    if what.effect == "excitation_direction":
        f = layout.exciters.directions[j] + U @ v
        angle = np.degrees(np.arccos(np.clip(f @ layout.exciters.directions[j] / np.linalg.norm(f), -1, 1)))
        parameters = {
            "angle_deg": float(angle),
            "angle_std_deg": float(np.degrees(np.linalg.norm(sigma))),
            "direction": (f / np.linalg.norm(f)).tolist(),
        }
    else:
        parameters = {
            "offset_m": (U @ v).tolist(),
            "distance_mm": float(1e3 * np.linalg.norm(v)),
            "distance_std_mm": float(1e3 * np.linalg.norm(sigma)),
        }
    return Finding(what.effect, (), j, parameters, evidence)


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
