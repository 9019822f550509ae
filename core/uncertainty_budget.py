"""The uncertainty budget's arithmetic: every 1-σ as the sum in quadrature of named sources (GUM, JCGM 100).

The properties come from the whitened least squares J x = r over the masslines' rows (H − model)/σ, a scale's row
when weighed, and the transverse prior rows τ/t (identify's :mod:`massline.identify.weighted_system`, and the
plan's prediction of it, :mod:`massline.placement.predicted_budget`), so to first order every change δr of those
rows moves θ̃ by δx = K δr, K = (JᵀJ)⁻¹Jᵀ (θ̃'s rows). Each source is a group of rows or a change of them:

* ``noise`` (type A): the masslines' rows, K_d K_dᵀ;
* ``transverse`` (type B): the prior rows of each channel's transverse components, K_τ K_τᵀ;
* ``weighed_mass``: the scale's row, K_w K_wᵀ;
* ``sensor_calibration`` (type B): channel i's sensitivity off by ε_i (1-σ ``calibration.sensor``, independent)
  moves row i of the masslines by ε_i H_i, δx_i = K_d δr_i;
* ``force_calibration`` (type B): the force transducer's sensitivity off by ε (1-σ ``calibration.force``) moves
  every massline by ε H. M⁻¹ scales by (1 + ε), so θ by 1/(1 + ε): exact to first order, the mass and inertia
  move one for one, the CoG not (with a scale's reading or riding masses, less: K says how much);
* ``housings`` (type B): each accelerometer housing's mass known to ``calibration.housings`` (relative): the bare
  body is the tested one less the housings' θ_k, so housing k's error moves it by its θ_k times that;
* ``truncation`` (systematic): how far the band fits' tails' next term moves the properties.

Each source's δθ̃ is carried to the 25 entries of ``property_vector`` through the Jacobian of θ → properties
(:func:`massline.core.accuracy.property_jacobian`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import reduce

import numpy as np

from massline.core.calibration import Calibration
from massline.core.properties import QUANTITIES, std_of

SOURCES = ("noise", "transverse", "sensor_calibration", "force_calibration", "weighed_mass", "housings", "truncation")
"""The budget's sources, in the order every table shows them."""

SHORT_NAMES = {
    "noise": "noise",
    "transverse": "transverse",
    "sensor_calibration": "accel. cal.",
    "force_calibration": "force cal.",
    "weighed_mass": "scale",
    "housings": "housings",
    "truncation": "truncation",
}
"""Each source's name in a table's head."""


@dataclass(frozen=True, eq=False)
class Gains:
    """K = (JᵀJ)⁻¹Jᵀ's θ̃ rows, split by the rows of J (the weighted system at the estimate, in its model's
    scaled parameters): ``data`` (p, n_s·n_e) the masslines', ``scale`` (p, 0 or 1) the scale's, ``prior``
    (p, 2 n_s or 0) the transverse priors'; ``residual_maker`` (n_m, n_m) I − J (JᵀJ)⁻¹Jᵀ on the measured rows
    (masslines, then the scale's)."""

    data: np.ndarray
    scale: np.ndarray
    prior: np.ndarray
    residual_maker: np.ndarray


def gains(J: np.ndarray, p: int, n_data: int, n_scale: int) -> Gains:
    """The :class:`Gains` of the whitened Jacobian ``J`` (rows: ``n_data`` masslines, ``n_scale`` scale rows, then
    the priors; columns: θ̃'s ``p``, then the transverse components)."""
    K = np.linalg.solve(J.T @ J, J.T)
    n_m = n_data + n_scale
    return Gains(K[:p, :n_data], K[:p, n_data:n_m], K[:p, n_m:], np.eye(n_m) - J[:n_m] @ K[:, :n_m])


def dense_jacobian(A: np.ndarray, D: np.ndarray | None, transverse: float, scale_row: np.ndarray | None = None):
    """The whole whitened Jacobian: the masslines' rows ``A`` (n_s, n_e, p) beside their transverse columns ``D``
    (n_s, n_e, 2; None: exact axes), the scale's row, then the transverse prior rows I/t."""
    n_s, n_e, p = A.shape
    width = p + (0 if D is None else 2 * n_s)
    rows = [A.reshape(-1, p)]
    if D is not None:
        block = np.zeros((n_s, n_e, n_s, 2))
        block[np.arange(n_s), :, np.arange(n_s)] = D
        rows = [np.hstack([rows[0], block.reshape(n_s * n_e, 2 * n_s)])]
    if scale_row is not None:
        rows.append(np.pad(scale_row, (0, width - p))[None, :])
    if D is not None:
        rows.append(np.hstack([np.zeros((2 * n_s, p)), np.eye(2 * n_s) / transverse]))
    return np.vstack(rows)


def calibration_shifts(gain: Gains, model_masslines: np.ndarray, sigma: np.ndarray, calibration: Calibration):
    """δθ̃ of each calibration error at its 1-σ: (p, n_s) one column per channel, (p, 1) the force's; and the
    rows' change δr of each (n_s·n_e, n_s + 1), masslines (m/s²)/N and their 1-σ ``sigma`` (inf: missing)."""
    n_s, n_e = model_masslines.shape
    whitened = np.where(np.isfinite(sigma), np.nan_to_num(model_masslines) / sigma, 0.0)
    rows = np.zeros((n_s, n_e, n_s))
    rows[np.arange(n_s), :, np.arange(n_s)] = whitened
    sensor = calibration.sensor * rows.reshape(n_s * n_e, n_s)
    force = calibration.force * whitened.reshape(-1, 1)
    return gain.data @ sensor, gain.data @ force, np.hstack([sensor, force])


def entries_std(jacobian: np.ndarray, covariance: np.ndarray) -> np.ndarray:
    """1-σ of the 25 property entries for θ̃'s ``covariance`` through ``jacobian`` (25, p)."""
    return np.sqrt(np.clip(np.einsum("ik,kl,il->i", jacobian, covariance, jacobian), 0, None))


def columns_std(jacobian: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """1-σ of the 25 property entries for independent θ̃ shifts (p, k), each at its 1-σ."""
    return np.sqrt(np.sum((jacobian @ shifts) ** 2, axis=1))


def json_unit(q) -> str:
    """A quantity's unit in the JSON (SI, ASCII): 'kg', 'm', 'kg m^2', 'deg'."""
    if q.key == "principal_axes":
        return "deg"
    return q.unit.replace("mm", "m").replace("·", " ").replace("²", "^2")


@dataclass(frozen=True, eq=False)
class UncertaintyBudget:
    """Each source's 1-σ (25 entries of ``property_vector``, SI) of one body's properties, and what it assumed.

    ``parts`` maps each name of SOURCES to its 1-σ; ``planar``: plate data (the out-of-plane entries are NaN);
    ``misfit``: the factor on the noise's variance for a fit that leaves more than the noise and the calibration
    explain (1: none; then the noise's 1-σ is mostly that misfit's, and a sentence says so).
    """

    parts: dict
    calibration: Calibration
    planar: bool = False
    misfit: float = 1.0

    @property
    def total(self) -> np.ndarray:
        """The reported 1-σ: the sources in quadrature (25 entries, SI), as hypotenuses (no square overflows where a
        band beside a resonance leaves a source's 1-σ near the float's range)."""
        return reduce(np.hypot, (np.abs(np.asarray(v, dtype=float)) for v in self.parts.values()))

    @property
    def statistical(self) -> np.ndarray:
        """The 1-σ of the data's own scatter and priors: noise, transverse and the scale, in quadrature."""
        return np.sqrt(sum(self.parts[k] ** 2 for k in ("noise", "transverse", "weighed_mass")))

    def std(self, source: str | None = None) -> dict:
        """identify's std keys of one source's 1-σ, or of the total (None)."""
        return std_of(self.total if source is None else self.parts[source], planar=self.planar)

    def table(self) -> dict:
        """{quantity name: {source: 1-σ}} (SI, degrees for a principal axis) of every reported quantity."""
        stds = {name: self.std(name) for name in SOURCES}
        return {q.name: {name: q.sigma(stds[name]) for name in SOURCES} for q in QUANTITIES}

    def dominant(self, name: str) -> str:
        """The source with the largest 1-σ of the quantity ``name``."""
        row = self.table()[name]
        return max(SOURCES, key=lambda s: np.nan_to_num(row[s], nan=-1.0))

    def payload(self) -> dict:
        """identify JSON's ``uncertainty_budget``: the calibration assumed, and per quantity the total 1-σ and
        each source's 1-σ and share of the variance (SI; degrees for a principal axis)."""
        stds, total = self.table(), self.std()
        properties = {}
        for q in QUANTITIES:
            sigma = q.sigma(total)
            row = stds[q.name]
            share = {s: (row[s] ** 2 / sigma**2 if sigma > 0 else np.nan) for s in SOURCES}
            properties[q.name] = {
                "std": sigma,
                "unit": json_unit(q),
                "dominant": self.dominant(q.name) if np.isfinite(sigma) else None,
                "sources": {s: {"std": row[s], "share": share[s]} for s in SOURCES},
            }
        return {"calibration": self.calibration.payload, "sources": list(SOURCES), "properties": properties}


def source_name(source: str, calibration: Calibration) -> str:
    """How a sentence names a source: 'the force transducer's 1 % calibration'."""
    return {
        "noise": "the recording's noise",
        "transverse": f"the accelerometers' transverse sensitivity ({100 * calibration.transverse:g} % prior)",
        "sensor_calibration": f"the accelerometers' {100 * calibration.sensor:g} % calibration",
        "force_calibration": f"the force transducer's {100 * calibration.force:g} % calibration",
        "weighed_mass": "the scale's reading",
        "housings": f"the accelerometer housings' {100 * calibration.housings:g} % mass tolerance",
        "truncation": "the band fits' tail truncation",
    }[source]


REMEDIES = {
    "noise": "more averages, a longer record or a wider band cut it",
    "transverse": "more hits per accelerometer (each channel's transverse reading then shows) cut it",
    "sensor_calibration": "calibrated accelerometers (--calibration 0,F), or more of them, cut it",
    "force_calibration": "a calibrated hammer, or --weighed-mass, cuts it",
    "weighed_mass": "a finer scale cuts it",
    "housings": "weighing the housings cuts it",
    "truncation": "a softer support, or a band further from the resonances, cuts it",
}


def limits(budget: UncertaintyBudget, body) -> list[str]:
    """One sentence per source that dominates the mass, the CoG or the principal moments of ``body`` (the body
    reported, SI): 'the force transducer's 1 % calibration limits the mass to ±1.0 %: a calibrated hammer, or
    --weighed-mass, cuts it'."""
    total, table = budget.std(), budget.table()
    moments = np.asarray(body.principal_moments, dtype=float)
    groups = {
        "the mass": (["mass"], f"±{100 * total['mass'] / body.mass:.2g} %"),
        "the CoG": ([f"CoG {a}" for a in "xyz"], f"±{1e3 * np.nanmax(total['cog']):.2g} mm"),
        "the principal moments": (
            [f"principal moment {k + 1}" for k in range(3)],
            f"±{100 * np.nanmax(total['principal_moments'] / np.abs(moments)):.2g} %",
        ),
    }
    by_source: dict[str, list[str]] = {}
    for what, (names, size) in groups.items():
        rows = [table[n] for n in names if np.isfinite(sum(table[n].values()))]
        if not rows:
            continue
        source = max(SOURCES, key=lambda s: sum(np.nan_to_num(r[s]) ** 2 for r in rows))
        by_source.setdefault(source, []).append(f"{what} to {size}")
    return [f"{limiting(s, budget)} limits {' and '.join(said)}: {remedy(s, budget)}" for s, said in by_source.items()]


MISFIT_SAID = 4.0  # a noise variance scaled up more than this is said to be the fit's misfit, not the recording's noise


def limiting(source: str, budget: UncertaintyBudget) -> str:
    """A source as the sentence names it: the noise scaled up by a misfit is that misfit."""
    if source == "noise" and budget.misfit > MISFIT_SAID:
        return f"the fit's misfit ({np.sqrt(budget.misfit):.2g}× the noise, beyond the calibration's)"
    return source_name(source, budget.calibration)


def remedy(source: str, budget: UncertaintyBudget) -> str:
    """What cuts a source (a misfit: finding what leaves it)."""
    if source == "noise" and budget.misfit > MISFIT_SAID:
        return "massline diagnose says what leaves it"
    return REMEDIES[source]
