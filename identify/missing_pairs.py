"""What the masslines present can say when not every response–reference pair was measured (a recording
assembled from test runs that each measured some pairs, a channel lost in one of them).

A pair with no FRF (or too few lines in the band) has no massline: its σ is infinite and it weighs nothing in
the estimate. Three things follow from it:

- the paper's methods, which start the iterative estimate, need the whole matrix: :func:`completed` fills the
  missing pairs from a body that fits the present ones;
- the properties are determined by the present pairs when their sensitivities to the p parameters,
  g_ij = ∂H_ij/∂θ̃ (``core.information``; the kinematic eq. 6 and dynamic eq. 9 steps joined), have rank p:
  :func:`undetermined` says which parameter combination is lost otherwise, and which missing FRF would restore
  it;
- :func:`missing_warnings` lists what is missing, by code, and :func:`unmeasured_notes` the geometry's nodes that no
  FRF measures at all (a file cut short loses whole channels, which only its geometry still shows).
"""

from __future__ import annotations

import numpy as np

from massline.core.degeneracy import describe_motion
from massline.core.errors import MasslineError
from massline.core.information import sensitivities
from massline.core.masslines import Masslines
from massline.core.methods import starting_body
from massline.core.model import RigidModel
from massline.core.rigid_body import RigidBody
from massline.identify.warning_codes import CodedWarning

RANK_TOLERANCE = 1e-7  # a singular value of the scaled sensitivities below this fraction of the largest is 0
TIE = 1e-6  # a singular value within this fraction of the cut counts as 0; a gain within it of the best ties
NAMED = 0.3  # a parameter is named when its share of the lost directions is at least this fraction of the largest
SHOWN = 4  # missing pairs named in a warning
WORDS = {"m": "the mass", "mc_x": "the CoG's x", "mc_y": "the CoG's y", "mc_z": "the CoG's z"}


def symmetric_solution(data: Masslines, present: np.ndarray) -> np.ndarray:
    """The symmetric X (q, q) of least squares H_ij = ℓ_iᵀ X w_j over the present pairs (minimum norm): M⁻¹
    where the present masslines determine it, linear in its q(q+1)/2 entries."""
    S, W = data.sensors.coordinates, data.exciters.coordinates
    rows, columns = np.nonzero(present)
    a, b = np.triu_indices(S.shape[1])
    design = S[rows][:, a] * W[columns][:, b] + np.where(a != b, S[rows][:, b] * W[columns][:, a], 0.0)
    x = np.linalg.lstsq(design, data.values[rows, columns], rcond=None)[0]
    X = np.zeros((S.shape[1],) * 2)
    X[a, b] = X[b, a] = x
    return X


def completed(data: Masslines, present: np.ndarray, planar: bool, rounds: int = 3) -> Masslines:
    """The masslines with the missing pairs filled: from :func:`symmetric_solution`, then ``rounds`` times from
    the body the paper's methods 2 + 3 (the plate's eqs. 10–13) find in the filled matrix."""
    S, W = data.sensors.coordinates, data.exciters.coordinates
    filled = np.where(present, data.values, S @ symmetric_solution(data, present) @ W.T)
    for _ in range(rounds):
        body = starting_body(Masslines(filled, data.sensors, data.exciters), planar)
        model = RigidModel(body, planar)
        H = model.coordinates(data.sensors) @ model.mass_matrix_inverse @ model.coordinates(data.exciters).T
        filled = np.where(present, data.values, H)
    return Masslines(filled, data.sensors, data.exciters)


def generic_body(data: Masslines) -> RigidBody:
    """A body of the layout's size (1 kg, CoG at the points' centre, unequal moments) to judge rank on when the
    masslines give none."""
    points = np.vstack([data.sensors.points, data.exciters.points])
    size = max(float(np.ptp(points, axis=0).max()), 1e-3)
    return RigidBody(1.0, points.mean(axis=0), np.diag([1.0, 1.3, 1.7]) * size**2 / 12)


def numerical_rank(s: np.ndarray) -> int:
    """How many singular values ``s`` (descending) are not 0: those above RANK_TOLERANCE × the largest.

    A lost direction's singular value is rounding (≲ 1e-15 of the largest), a determined layout's smallest
    ≳ 1e-5 of it (the structure's 12 × 3 with two hits at one response each: 8e-5 kept, 3e-17 lost): the cut
    sits decades from both, where no machine's rounding moves a decision. A value within TIE of the cut
    (relatively) counts as 0, the side that refuses: what it determines, it determines to no useful ±.
    """
    if not len(s) or s[0] <= 0:
        return 0
    return int(np.sum(s > RANK_TOLERANCE * (1 + TIE) * s[0]))


def null_shares(null: np.ndarray) -> np.ndarray:
    """Each parameter's share of the lost directions (the rows of ``null``, orthonormal, in scaled θ̃), (p,):
    the length of its axis projected on them, √ of the diagonal of the projector VₙᵀVₙ; 1 for a parameter lost
    entirely, 0 for one the present pairs determine. It is the same whichever basis of the null space the SVD
    returns (which differs between machines when the null space has two dimensions or more); for one lost
    direction it is that direction's components' size."""
    return np.sqrt(np.einsum("rk,rk->k", null, null))


def parameter_words(null: np.ndarray, names: tuple) -> str:
    """The parameters the lost directions of the sensitivities (``null``: (r, p) orthonormal rows, scaled θ̃)
    take most, 'the mass and J_xy': those whose share (:func:`null_shares`) is at least NAMED × the largest (or
    within TIE under it), in the order of ``names``."""
    share = null_shares(np.atleast_2d(null))
    big = share >= (1 - TIE) * NAMED * share.max()
    words = [WORDS.get(name, name) for name, shown in zip(names, big) if shown]
    return words[0] if len(words) == 1 else ", ".join(words[:-1]) + " and " + words[-1]


def most_restoring(gain: np.ndarray) -> int:
    """The index of the largest ``gain``; among gains within TIE of it (relatively), the first (the missing
    pairs' order: by response, then reference), so a tie is not broken by rounding."""
    return int(np.flatnonzero(gain >= (1 - TIE) * gain.max())[0])


def column_motions(data: Masslines, present: np.ndarray, planar: bool, model: RigidModel, references: list) -> str:
    """The first column whose present sensors cannot see every rigid motion (eq. 6 for that column), in words
    (``references``: the columns' labels)."""
    S = model.coordinates(data.sensors)
    scale = max(float(np.ptp(data.sensors.points, axis=0).max()), 1e-3)
    for j, exciter in enumerate(references):
        rows = S[present[:, j]]
        rank = numerical_rank(np.linalg.svd(rows, compute_uv=False)) if len(rows) else 0
        if rank < S.shape[1]:
            seen = f"{rank} of {S.shape[1]} motions"
            if planar or rank < S.shape[1] - 1:  # one unseen motion is put in words, several counted
                return f"reference {exciter}'s present responses see {seen}"
            null = np.linalg.svd(np.vstack([rows, np.zeros((6, 6))]))[2][rank]
            # a motion and its negative are one: the sign that makes its first component within TIE of the
            # largest positive (the SVD's sign is either, machine to machine)
            null = null * np.sign(null[np.flatnonzero(np.abs(null) >= (1 - TIE) * np.abs(null).max())[0]])
            return f"reference {exciter}'s present responses see {seen} ({describe_motion(null, scale)})"
    return ""


def undetermined(data: Masslines, present: np.ndarray, planar: bool, body: RigidBody | None, labels: tuple) -> str:
    """Why the present pairs leave the properties undetermined, and which missing FRF would restore them; ''
    when they determine them.

    ``labels``: the rows' and the columns' channel labels. The sensitivities g_ij of the present pairs at ``body``
    (a generic body of the layout's size when None, or no body) must have rank p (:func:`numerical_rank`).
    Otherwise their null space Vₙ names the parameters lost (:func:`parameter_words`), and the missing pair with
    the largest ‖Vₙ g_ij‖ / ‖g_ij‖, the share of its sensitivity in the lost directions, is the FRF that would
    restore the most (:func:`most_restoring`). Both read the null space, not one vector of a basis of it.
    """
    model = RigidModel(body or generic_body(data), planar)
    G, _ = sensitivities(model, model.coordinates(data.sensors), model.coordinates(data.exciters))
    if not np.isfinite(G).all():  # a start from too few masslines can be no body
        return undetermined(data, present, planar, None, labels)
    s, Vt = np.linalg.svd(G[present], full_matrices=True)[1:]
    rank = numerical_rank(s)
    if rank == model.p:
        return ""
    null = Vt[rank:]
    words = parameter_words(null, model.names)
    lost = f"the FRFs present leave {words} undetermined ({(~present).sum()} of {present.size} pairs missing)"
    responses, references = labels
    kinematic = column_motions(data, present, planar, model, references)
    lost += f"; {kinematic}" if kinematic else ""
    rows, columns = np.nonzero(~present)
    if not len(rows):
        return lost
    g = G[rows, columns]
    gain = np.linalg.norm(g @ null.T, axis=1) / np.maximum(np.linalg.norm(g, axis=1), 1e-300)
    if gain.max() < RANK_TOLERANCE:
        return f"{lost}: no missing FRF restores it; add responses or references that see it"
    k = most_restoring(gain)
    return (
        f"{lost}: measure response {responses[rows[k]]} against reference {references[columns[k]]}, the missing "
        "FRF that restores the most"
    )


def check_determined(data: Masslines, present: np.ndarray, planar: bool, labels: tuple) -> None:
    """Refuse the present pairs when they leave a parameter undetermined (:func:`undetermined`, at the body
    :func:`completed` starts from; ``labels``: the rows' and columns' channel labels).

    Raises
    ------
    MasslineError
        The present pairs do not determine the properties: which, and the FRF that would restore them.
    """
    if present.all():
        return
    try:
        start = starting_body(completed(data, present, planar), planar)
    except (MasslineError, np.linalg.LinAlgError):
        start = None
    why = undetermined(data, present, planar, start, labels)
    if why:
        raise MasslineError(why)


def missing_statement(missing: list, pairs: int, reason: str = "no FRF") -> str:
    """'2 of 28 response-reference pairs have no FRF (7:+X / 103:+X, …)' (``missing``: (response, reference)
    labels of ``pairs``); '' when none is missing."""
    if not missing:
        return ""
    return f"{len(missing)} of {pairs} response-reference pairs have {reason} ({listed(f'{s} / {e}' for s, e in missing)})"


def missing_warnings(missing: list, pairs: int, reason: str = "no FRF") -> list[CodedWarning]:
    """The pairs left out of the estimate (``missing``: (response, reference) labels), by code."""
    if not missing:
        return []
    return [
        CodedWarning(
            "frf_missing",
            f"{missing_statement(missing, pairs, reason)}: the properties and their ± are from the pairs present",
        )
    ]


def listed(items, shown: int = SHOWN) -> str:
    """The first ``shown`` of ``items``, joined, with '…' when there are more."""
    items = [str(x) for x in items]
    return ", ".join(items[:shown]) + (", …" if len(items) > shown else "")


def unmeasured_notes(nodes: tuple) -> tuple[CodedWarning, ...]:
    """The geometry's ``nodes`` (numbers) that no FRF has as its response or reference, by code: said, never
    estimated from."""
    if not nodes:
        return ()
    return (CodedWarning("frf_missing", f"{unmeasured_statement(nodes)}: no response or reference there (a channel "
                         "lost or a file cut short, or a wireframe's points)"),)  # fmt: skip


def unmeasured_statement(nodes: tuple) -> str:
    """'2 node(s) of the file's geometry have no FRF (8, 9)'; '' for none."""
    return f"{len(nodes)} node(s) of the file's geometry have no FRF ({listed(nodes)})" if nodes else ""


def incomplete(missing: list, pairs: int, nodes: tuple) -> str:
    """What a file lacks, for a refusal: the ``missing`` pairs of ``pairs`` and the geometry's ``nodes`` without an
    FRF, in one clause ('' when it lacks nothing)."""
    said = [x for x in (missing_statement(missing, pairs), unmeasured_statement(nodes)) if x]
    return f"the file is incomplete: {'; '.join(said)}" if said else ""
