"""A moved accelerometer's or hit's offset as identify's masslines read it.

An accelerometer glued δ from its labelled point p reads along s = (d, (p + δ) × d): its masslines are linear
in δ at a given body, A_ij = s_iᵀ M⁻¹ ℓ_j. The line-level search fits δ together with the body, the tails and
every other effect, and where the offset is large against the channel's leverage the two trade (on the
bracket's default plan an 8 mm offset on channel 8 was fitted as 11.7 mm in another direction, its Δ(p × d)
uncorrelated with the truth's, and identify's χ² left 80 % of the misfit). Here δ is read on identify's
masslines: the weighted least-squares offset of the channel's own masslines on a body, in the plane ⊥ d (along
d an offset cannot be seen), or in 3-D for a triaxial's channels, which move as one; the body and δ refined in
turn, from the line-level fit's δ and from the body of the other channels, the better kept (on the structure's
default plan the other eight channels' body alone read a 7.9 mm offset 2 mm off, χ² 32 where the line-level's
left 0.39). A hit landing δ from its labelled point drives along ℓ_j = (d, (p + δ) × d): the same reading on its
column (on the structure's default plan an 8 mm hit offset read at the line level left identify's χ² 16 on 8
degrees of freedom).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import minimize

from massline.core.information import sensitivities
from massline.core.lines import Lines
from massline.core.masslines import Masslines
from massline.identify.diagnose.effects.base import moved_lines, offset_parameters
from massline.identify.diagnose.shapes import objective
from massline.identify.diagnose.unexplained import estimated

STEP = 1e-3  # m: the difference step (the masslines are linear in δ: any step is exact to rounding)
ROUNDS = 4  # refinements of the offset and the body in turn, from each start
PROFILE = 1e-4  # m: the step the objective is profiled over for the offset's 1-σ


def offset_basis(directions: np.ndarray) -> np.ndarray:
    """(k, 3) unit vectors an offset of these channels is fitted along: the plane ⊥ the one channel's axis,
    or every axis for a triaxial's channels."""
    if len(directions) > 1:
        return np.eye(3)
    d = directions[0] / np.linalg.norm(directions[0])
    return np.linalg.svd(d[None, :])[2][1:]  # the two unit vectors ⊥ d


def masslines_at(model, sensors: Lines, exciters: Lines, riding, readings=None) -> np.ndarray:
    """A_ij (n_s, n_e), (m/s²)/N: the masslines of ``model``'s body for these lines, each sensor reading along
    its axis plus its transverse reading (``readings`` (n_s, 3), identify's estimate's; None: along its axis)."""
    return sensitivities(model, read_along(model, sensors, readings), model.coordinates(exciters), riding)[1]


def read_along(model, sensors: Lines, readings) -> np.ndarray:
    """The sensors' line coordinates as identify's estimate reads them: (d + τ, r × (d + τ)), τ the transverse
    reading (the estimator's s_i + L_i τ_i); the axes alone for a plate or without ``readings``."""
    if readings is None or model.planar:
        return model.coordinates(sensors)
    d = sensors.directions + readings
    return np.hstack([d, np.cross(sensors.points, d)])


@dataclass(frozen=True)
class Place:
    """Where an offset is read: ``places`` (channels of one accelerometer, or one hit) on ``side`` "sensor" or
    "exciter"; the masslines are read as rows (the channels') or columns (the hit's, transposed)."""

    side: str
    places: tuple

    def lines(self, data: Masslines) -> Lines:
        return (data.sensors if self.side == "sensor" else data.exciters)[list(self.places)]

    def rows(self, values: np.ndarray) -> np.ndarray:
        """The place's masslines (or 1-σ) as rows: (k, n_other)."""
        return values[list(self.places)] if self.side == "sensor" else values[:, list(self.places)].T

    def masslines(self, model, data: Masslines, lines: Lines, riding, readings) -> np.ndarray:
        """The place's masslines on ``model``'s body with its lines at ``lines``, as rows (``readings``: every
        sensor's transverse reading, (n_s, 3))."""
        if self.side == "sensor":
            return masslines_at(model, lines, data.exciters, riding, readings[list(self.places)])
        own = None if riding is None else riding[list(self.places)]
        return masslines_at(model, data.sensors, lines, own, readings).T

    def others(self, data: Masslines, sigma: np.ndarray, riding) -> tuple[Masslines, np.ndarray, object]:
        """The masslines, 1-σ and riding masses without the place."""
        if self.side == "sensor":
            rest = [i for i in range(len(data.sensors)) if i not in self.places]
            return Masslines(data.values[rest], data.sensors[rest], data.exciters), sigma[rest], riding
        rest = [j for j in range(len(data.exciters)) if j not in self.places]
        kept = None if riding is None else riding[rest]
        return Masslines(data.values[:, rest], data.sensors, data.exciters[rest]), sigma[:, rest], kept

    def completed(self, others, data: Masslines):
        """The estimate ``others`` (without the place) with a transverse reading for every channel: none for the
        place's own channels, which it did not see."""
        if self.side != "sensor":
            return others
        readings = np.zeros((len(data.sensors), 3))
        readings[[i for i in range(len(data.sensors)) if i not in self.places]] = others.transverse
        return replace(others, transverse=readings)

    def moved(self, data: Masslines, offset: np.ndarray) -> Masslines:
        """The masslines with the place's points moved by ``offset`` (m)."""
        lines = data.sensors if self.side == "sensor" else data.exciters
        for k in self.places:
            lines = moved_lines(lines, k, point=lines.points[k] + offset)
        if self.side == "sensor":
            return Masslines(data.values, lines, data.exciters)
        return Masslines(data.values, data.sensors, lines)


def on_body(fit, data: Masslines, sigma: np.ndarray, riding, place: Place) -> tuple[np.ndarray, np.ndarray]:
    """The offset (3,) m of ``place`` that fits its masslines best on the body of identify's estimate ``fit``
    (its every channel read with its transverse reading, ``fit.transverse``), by weighted least squares (exact:
    the masslines are linear in it), and its 1-σ per basis vector (scaled by the rows' misfit where it exceeds
    the noise); NaNs where its masslines cannot determine it. Read along their axes alone, the structure's
    channels' 1 % transverse readings had left a 9.08 mm offset read right within 0.2 mm with a 1-σ of 11.6 mm."""
    model, readings = fit.model, fit.transverse
    lines = place.lines(data)
    base = place.masslines(model, data, lines, riding, readings)
    basis = offset_basis(lines.directions)
    moved = [Lines(lines.points + STEP * b, lines.directions) for b in basis]
    columns = [(place.masslines(model, data, m, riding, readings) - base) / STEP for m in moved]
    w = 1 / place.rows(sigma)
    values = place.rows(data.values)
    seen = np.isfinite(w) & np.isfinite(values)
    A = np.stack([c[seen] * w[seen] for c in columns], axis=1)
    r = (values - base)[seen] * w[seen]
    if A.shape[0] <= A.shape[1] or np.linalg.matrix_rank(A) < A.shape[1]:
        return np.full(3, np.nan), np.full(len(basis), np.nan)
    v, *_ = np.linalg.lstsq(A, r, rcond=None)
    spread = max(float(np.sum((r - A @ v) ** 2)) / (A.shape[0] - A.shape[1]), 1.0)
    return basis.T @ v, np.sqrt(np.diag(np.linalg.inv(A.T @ A)) * spread)


def read_offset(finding, without):
    """``finding`` (a ``sensor_location`` or an ``excitation_location``) with its offset and the offset's 1-σ
    read on identify's masslines ``without`` (identify with every other fault undone), the finding unchanged
    where none can be read.

    Two starts, the line-level fit's offset and the one the body of the other channels (or hits) gives (the
    faulty place left out, so that it does not bend the body), each refined by ``ROUNDS`` of: identify's body on
    every line with the offset applied, then the offset on that body (exact, :func:`on_body`). The one of least
    identify objective (masslines and transverse prior, :func:`.shapes.objective`) is kept and taken to the
    profile's minimum (:func:`profile_minimum`). Its 1-σ is the larger of the profile's (the body's uncertainty
    in it) and the place's own masslines' on that body (their misfit in it, where the model leaves some: a clean
    plate file's 0.127 mm offset read has 0.038 mm from the profile and 0.12 mm from its channel's four
    masslines)."""
    data, sigma, riding = without.data, without.sigma, without.best.riding
    place = Place("sensor", tuple(finding.channels)) if finding.channels else Place("exciter", (finding.exciter,))
    others = estimated(without, *place.others(data, sigma, riding))
    starts = [np.asarray(finding.parameters.get("offset_m", np.zeros(3)), dtype=float)]
    starts += [] if others is None else [on_body(place.completed(others, data), data, sigma, riding, place)[0]]
    best = None
    for offset in starts:
        for _ in range(ROUNDS + 1):
            fit = estimated(without, place.moved(data, offset), sigma, riding)
            if fit is None:
                break
            cost = objective(fit)
            if best is None or cost < best[0]:
                best = (cost, offset, fit)
            offset = on_body(fit, data, sigma, riding, place)[0]
            if not np.all(np.isfinite(offset)):
                break
    if best is None:
        return finding
    fitted = lambda moved: estimated(without, place.moved(data, moved), sigma, riding)  # noqa: E731
    basis = offset_basis(place.lines(data).directions)
    cost, offset, fit = profile_minimum(fitted, best, basis)
    std = np.fmax(profiled_std(fitted, offset, cost, basis, fit.chi2), on_body(fit, data, sigma, riding, place)[1])
    return replace(finding, parameters={**finding.parameters, **offset_parameters(offset, np.linalg.norm(offset), std)})


def profile_minimum(fitted, start: tuple, basis: np.ndarray) -> tuple:
    """(objective, offset, estimate) at the least of identify's objective profiled over the body (``fitted``,
    as in :func:`profiled_std`), from ``start`` (the alternation's best) along ``basis``: Nelder–Mead over the
    offset's two or three components. The alternation alone converges slowly where the offset and the channels'
    transverse readings trade (the structure's 8 mm hit offset: 8.54 mm after four rounds, χ² 8.2)."""
    cost0, offset0, fit0 = start

    def cost(v: np.ndarray) -> float:
        fit = fitted(offset0 + basis.T @ v)
        return np.inf if fit is None else objective(fit)

    simplex = np.vstack([np.zeros(len(basis)), PROFILE * np.eye(len(basis))])
    found = minimize(cost, np.zeros(len(basis)), method="Nelder-Mead",
                     options={"initial_simplex": simplex, "xatol": 1e-7, "fatol": 1e-4, "maxfev": 200})  # fmt: skip
    if not found.fun < cost0:
        return start
    offset = offset0 + basis.T @ found.x
    return float(found.fun), offset, fitted(offset)


def profiled_std(fitted, offset: np.ndarray, cost: float, basis: np.ndarray, chi2: float) -> np.ndarray:
    """The offset's 1-σ along each ``basis`` vector from identify's objective profiled over the body: the
    objective rises by (h/σ)² when the offset moves h from its best (``cost`` there), the body estimated again
    (``fitted(offset)``: identify's estimate with the place moved by it), scaled up by the reduced χ² where the
    fit is worse than the noise, as identify's ± is. The channel's own rows alone on a fixed body had given the
    structure's 8 mm offset in tests/test_offsets.py (seed 3) a 1-σ of 6.6 µm where it was read 87 µm off."""
    sigmas = []
    for b in basis:
        sides = [fitted(offset + sign * PROFILE * b) for sign in (1.0, -1.0)]
        rise = np.mean([objective(f) for f in sides]) - cost if all(f is not None for f in sides) else np.nan
        sigmas.append(PROFILE / np.sqrt(rise) if rise > 0 else np.nan)
    return np.array(sigmas) * np.sqrt(max(chi2, 1.0) if np.isfinite(chi2) else 1.0)
