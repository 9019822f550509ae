"""identify's uncertainty budget: every reported 1-σ as the sum in quadrature of named sources (GUM, JCGM 100).

The estimate θ̃ solves the whitened least squares J x = r (:mod:`.weighted_system`: the masslines' rows
(H − model)/σ, the scale's row when weighed, the transverse prior rows τ/t), so to first order every change δr of
those rows moves it by δx = K δr, K = (JᵀJ)⁻¹Jᵀ (θ̃'s rows). Each source is a group of rows or a change of them:

* ``noise`` (type A): the masslines' rows, K_d K_dᵀ, scaled up by the fit's χ² beyond what the noise and the
  type-B sources below explain (:func:`noise_scale`); the bootstrap over the sensors, when wider than noise,
  transverse and calibration together, widens it too (a sensor the model does not explain);
* ``transverse`` (type B): the prior rows of each channel's transverse components, K_τ K_τᵀ;
* ``weighed_mass``: the scale's row, K_w K_wᵀ;
* ``sensor_calibration`` (type B): channel i's sensitivity off by ε_i (1-σ ``calibration.sensor``, independent)
  moves row i of the masslines by ε_i H_i, δx_i = K_d δr_i;
* ``force_calibration`` (type B): the force transducer's sensitivity off by ε (1-σ ``calibration.force``) moves
  every massline by ε H. M⁻¹ scales by (1 + ε), so θ by 1/(1 + ε): exact to first order, the mass and inertia
  move one for one, the CoG not (with a scale's reading or riding masses, less: K says how much);
* ``truncation`` (systematic): how far the tails' next term moves the properties (:mod:`.uncertainty`).

Each source's δθ̃ is carried to the 25 entries of ``property_vector`` through the Jacobian of θ → properties at the
body reported (:func:`massline.core.accuracy.property_jacobian`), the bare body's where housings are taken off.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.core.accuracy import property_jacobian
from massline.core.calibration import Calibration
from massline.core.model import RigidModel
from massline.core.properties import QUANTITIES, std_of
from massline.identify.weighted_system import WeightedSystem

SOURCES = ("noise", "transverse", "sensor_calibration", "force_calibration", "weighed_mass", "truncation")
"""The budget's sources, in the order every table shows them."""

SHORT_NAMES = {
    "noise": "noise",
    "transverse": "transverse",
    "sensor_calibration": "accel. cal.",
    "force_calibration": "force cal.",
    "weighed_mass": "scale",
    "truncation": "truncation",
}
"""Each source's name in a table's head."""


@dataclass(frozen=True, eq=False)
class Gains:
    """K = (JᵀJ)⁻¹Jᵀ's θ̃ rows, split by the rows of J (the weighted system at the estimate, in the tested model's
    scaled parameters): ``data`` (p, n_s·n_e) the masslines', ``scale`` (p, 0 or 1) the scale's, ``prior``
    (p, 2 n_s or 0) the transverse priors'; ``residual_maker`` (n_m, n_m) I − J (JᵀJ)⁻¹Jᵀ on the measured rows
    (masslines, then the scale's)."""

    data: np.ndarray
    scale: np.ndarray
    prior: np.ndarray
    residual_maker: np.ndarray


def gains(system: WeightedSystem) -> Gains:
    """The :class:`Gains` of ``system`` (its dense Jacobian: measured rows, then priors)."""
    J, _ = system.dense()
    n_s, n_e, p = system.A.shape
    K = np.linalg.solve(J.T @ J, J.T)
    n_d, n_m = n_s * n_e, n_s * n_e + (system.scale_row is not None)
    measured = J[:n_m]
    return Gains(K[:p, :n_d], K[:p, n_d:n_m], K[:p, n_m:], np.eye(n_m) - measured @ K[:, :n_m])


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


def noise_scale(gain: Gains, measured: np.ndarray, dof: float, type_b_rows: np.ndarray) -> float:
    """The factor on the noise's variance: the measured rows' Σ r² less what the type-B changes ``type_b_rows``
    (n_d, k) leave in them at their 1-σ, over the degrees of freedom ``dof``, at least 1 (1 with no redundancy)."""
    if dof <= 0.5:
        return 1.0
    rows = np.zeros((len(measured), type_b_rows.shape[1]))
    rows[: len(type_b_rows)] = type_b_rows
    explained = float(np.sum((gain.residual_maker @ rows) ** 2))
    return max(1.0, (float(np.sum(measured**2)) - explained) / dof)


def entries_std(jacobian: np.ndarray, covariance: np.ndarray) -> np.ndarray:
    """1-σ of the 25 property entries for θ̃'s ``covariance`` through ``jacobian`` (25, p)."""
    return np.sqrt(np.clip(np.einsum("ik,kl,il->i", jacobian, covariance, jacobian), 0, None))


def columns_std(jacobian: np.ndarray, shifts: np.ndarray) -> np.ndarray:
    """1-σ of the 25 property entries for independent θ̃ shifts (p, k), each at its 1-σ."""
    return np.sqrt(np.sum((jacobian @ shifts) ** 2, axis=1))


@dataclass(frozen=True, eq=False)
class UncertaintyBudget:
    """Each source's 1-σ (25 entries of ``property_vector``, SI) of one body's properties, and what it assumed.

    ``parts`` maps each name of SOURCES to its 1-σ; ``planar``: plate data (the out-of-plane entries are NaN).
    """

    parts: dict
    calibration: Calibration
    planar: bool = False

    @property
    def total(self) -> np.ndarray:
        """The reported 1-σ: the sources in quadrature (25 entries, SI)."""
        return np.sqrt(sum(np.asarray(v) ** 2 for v in self.parts.values()))

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
                "unit": "deg" if q.key == "principal_axes" else q.unit.replace("mm", "m").replace("·", " ").replace("²", "^2"),
                "dominant": self.dominant(q.name) if np.isfinite(sigma) else None,
                "sources": {s: {"std": row[s], "share": share[s]} for s in SOURCES},
            }
        return {"calibration": self.calibration.payload, "sources": list(SOURCES), "properties": properties}


@dataclass(frozen=True, eq=False)
class Shifts:
    """What every body's budget shares: θ̃'s covariance of each row group (in the tested model's scaling), the type-B
    shifts (p, k), the noise's scale factor."""

    noise: np.ndarray
    transverse: np.ndarray
    weighed: np.ndarray
    sensor: np.ndarray
    force: np.ndarray
    scale: np.ndarray  # the tested model's (m₀, m₀L, m₀L²) per parameter


def budget_shifts(system: WeightedSystem, model: RigidModel, masslines: np.ndarray, sigma: np.ndarray,
                  calibration: Calibration, *, chi2_measured: np.ndarray, dof: float) -> Shifts:  # fmt: skip
    """The :class:`Shifts` at an estimate: its weighted ``system`` and ``model``, its model ``masslines`` (n_s, n_e)
    and their 1-σ ``sigma``, (m/s²)/N; ``chi2_measured`` the measured rows' residuals and ``dof`` their degrees of
    freedom (the estimator's)."""
    gain = gains(system)
    sensor, force, rows = calibration_shifts(gain, masslines, sigma, calibration)
    factor = noise_scale(gain, chi2_measured, dof, rows)
    return Shifts(factor * gain.data @ gain.data.T, gain.prior @ gain.prior.T, gain.scale @ gain.scale.T, sensor,
                  force, model.scale)  # fmt: skip


def body_budget(shifts: Shifts, model: RigidModel, calibration: Calibration, *, truncation: np.ndarray,
                bootstrap: np.ndarray | None = None) -> UncertaintyBudget:  # fmt: skip
    """The budget of the body of ``model`` (the tested body's or the bare one's: θ differs by known housings, so
    every δθ is the same), with the ``truncation`` shift (25 entries, SI) and the ``bootstrap``'s 1-σ (25, or
    None) widening the noise where it is wider than the noise, transverse and sensor calibration together."""
    ratio = shifts.scale / model.scale  # δθ̃ in this model's scaling
    jacobian = property_jacobian(model) * ratio[None, :]
    parts = {
        "noise": entries_std(jacobian, shifts.noise),
        "transverse": entries_std(jacobian, shifts.transverse),
        "sensor_calibration": columns_std(jacobian, shifts.sensor),
        "force_calibration": columns_std(jacobian, shifts.force),
        "weighed_mass": entries_std(jacobian, shifts.weighed),
        "truncation": np.abs(np.nan_to_num(truncation, nan=0.0)),
    }
    if bootstrap is not None:
        seen = parts["transverse"] ** 2 + parts["sensor_calibration"] ** 2
        parts["noise"] = np.sqrt(np.fmax(parts["noise"] ** 2, np.nan_to_num(bootstrap**2 - seen, nan=0.0)))
    return UncertaintyBudget(parts, calibration, model.planar)


def source_name(source: str, calibration: Calibration) -> str:
    """How a sentence names a source: 'the force transducer's 1 % calibration'."""
    return {
        "noise": "the recording's noise",
        "transverse": f"the accelerometers' transverse sensitivity ({100 * calibration.transverse:g} % prior)",
        "sensor_calibration": f"the accelerometers' {100 * calibration.sensor:g} % calibration",
        "force_calibration": f"the force transducer's {100 * calibration.force:g} % calibration",
        "weighed_mass": "the scale's reading",
        "truncation": "the band fits' tail truncation",
    }[source]


REMEDIES = {
    "noise": "more averages, a longer record or a wider band cut it",
    "transverse": "more hits per accelerometer (each channel's transverse reading then shows) cut it",
    "sensor_calibration": "calibrated accelerometers (--calibration 0,F), or more of them, cut it",
    "force_calibration": "a calibrated hammer, or --weighed-mass, cuts it",
    "weighed_mass": "a finer scale cuts it",
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
    return [
        f"{source_name(s, budget.calibration)} limits {' and '.join(items)}: {REMEDIES[s]}"
        for s, items in by_source.items()
    ]
