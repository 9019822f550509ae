"""What every effect class is, and the algebra the effects share.

An effect (DESIGN.md, "An effect") is one subclass of :class:`Effect` in its own module, listed once in
the registry (:mod:`massline.identify.diagnose.effects`). An instance is the effect as concealed in a
virtual test (``size`` at ``where``); the class holds the rest as class attributes and hooks:

* what it is: ``name``, ``kind`` ("fault" | "test_physics"), ``unit`` of its size, ``perturbs`` (the lines,
  the support or the modes), ``discrete`` (no size), ``summary`` (the ``--help`` line);
* the simulator: ``simulate`` (what it changes in the instrumentation), ``check_place`` (``--effect`` syntax),
  ``blind_range`` / ``blind_size`` (the blind scenarios' realistic size);
* the diagnosis: ``model`` ("block", "discrete", "tail", "mass", "gauge" or None: knowingly not diagnosed), the block
  hooks (``blocks``, ``values``, ``channels``, ``displace``, ``plausible``, ``parameters``), ``undo_rows``
  (discrete), ``correct`` (undone on the recording), ``identify_option`` / ``option_value`` (undone by identify
  itself), ``sentence`` (notes), ``concealed`` (the demo's words).

Hooks get the diagnosis's layout and fits duck-typed (:mod:`..effect_model`, :mod:`..effect_fit`), so that
the registry stays below them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from massline.core.errors import MasslineError
from massline.core.lines import Lines
from massline.core.numbers import signed, value_with_sigma

MISALIGNMENT = 0.35  # prior 1-σ of a released axis (≈ 20°): a mounting error, not a datasheet's cross-axis reading


@dataclass(frozen=True)
class Block:
    """One effect at one place in the diagnosis: ``target`` is a channel (gain), an accelerometer (index into
    ``Layout.groups``: direction, location) or an exciter."""

    effect: str
    target: int


@dataclass(eq=False)
class MeasuredLines:
    """The lines as the model's effects place them (mutated by ``Effect.displace``): sensor points (n_s, 3) m
    and gains (n_s,), hit directions (n_e, 3) (unit) and points (n_e, 3) m; ``T``, ``U`` the sensors' and
    hits' perpendicular bases (n, 3, 2)."""

    points: np.ndarray
    gains: np.ndarray
    forces: np.ndarray
    hits: np.ndarray
    T: np.ndarray
    U: np.ndarray


@dataclass(frozen=True)
class Scene:
    """Where a concealed fault sits, as the demo names it: the first channel's label, every channel's, the
    hit's label, and the planned band (Hz)."""

    sensor: str | None
    sensors: tuple
    hit: str | None
    band: tuple


@dataclass(frozen=True)
class Effect:
    """One effect as concealed in a virtual test: ``size`` (in ``unit``) at ``where`` (0-based lines,
    "all", or None for one at random). Subclasses set the class attributes and override the hooks."""

    size: float = 0.0
    where: tuple | str | float | None = None

    name: ClassVar[str] = ""
    kind: ClassVar[str] = "fault"
    unit: ClassVar[str] = ""  # of the size: "degrees", "fraction", "m", "kg", "Hz"; "" for none
    perturbs: ClassVar[str] = "sensor"  # core.effect_names.PERTURBS
    summary: ClassVar[str] = ""  # what it does to the named line(s), for --help
    discrete: ClassVar[bool] = False  # no size: a sign flipped, two channels exchanged
    place: ClassVar[str] = "lines"  # what @WHERE is: "lines" (1-based numbers or all) or "frequency" (Hz)
    simulated: ClassVar[bool] = True  # an --effect of the simulator (else simulated by the support / FE modes)
    model: ClassVar[str | None] = "block"  # how the diagnosis models it; None: knowingly not diagnosed
    widens_prior: ClassVar[bool] = False  # its block releases the channels' transverse prior (no values)
    moves: ClassVar[str] = ""  # what of its line a block changes: "point", "axis", "gain"
    rank: ClassVar[int] = 0  # order among the search's candidates (ties in score keep it)
    undone_on: ClassVar[str | None] = "recording"  # where it is undone: "recording", "body", "identify", None
    identify_option: ClassVar[str | None] = None  # undone by identify itself: the keyword it is given
    blind_range: ClassVar[tuple | None] = None  # a realistic size in the blind scenarios (None: no size)
    lines_needed: ClassVar[int] = 1  # lines a blind scenario draws for it
    adds_mass: ClassVar[bool] = False  # a mass on the body: a blind scenario hangs the cord above the loaded CoG

    @classmethod
    def syntax(cls) -> str:
        """The ``--effect`` argument."""
        return f"{cls.name}[@WHERE]" if cls.discrete else f"{cls.name}=SIZE[@WHERE]"

    @classmethod
    def described(cls) -> str:
        """The effect in the ``--effect`` help: its syntax when discrete, else its name and its size's unit."""
        return cls.syntax() if cls.discrete else f"{cls.name} ({cls.unit})"

    @classmethod
    def parse_place(cls, where: str):
        """``@WHERE`` as written: '3,5' → (2, 4) (1-based numbers on the command line, 0-based inside), 'all', or
        None when not given (a ValueError when it is no list of numbers)."""
        if not where:
            return None
        return "all" if where.strip() == "all" else tuple(int(w) - 1 for w in where.split(","))

    @classmethod
    def check_place(cls, where) -> None:
        """Raise a MasslineError when ``where`` cannot hold this effect (parsing ``--effect``)."""

    @classmethod
    def check_size(cls, size: float) -> None:
        """Raise a MasslineError when ``size`` cannot be this effect's (parsing ``--effect``): NaN or infinite."""
        need(bool(np.isfinite(size)), f"effect {cls.name}: its size must be a finite number, not {size:g}")

    # ---- the simulator -------------------------------------------------------------------------------
    def simulate(self, state, lines: Lines, targets: list[int], rng: np.random.Generator) -> dict:
        """Change ``state`` (:class:`massline.virtual.effects.Instrumentation`) on ``targets``; return what was
        drawn, for the truth file."""
        raise NotImplementedError(f"{self.name} is simulated by the virtual test's {self.perturbs}")

    @classmethod
    def blind_size(cls, rng: np.random.Generator, body_mass: float, band: tuple) -> float:
        """A size drawn from ``blind_range`` (the blind scenarios); ``band`` (Hz) places a tail."""
        return float(rng.uniform(*cls.blind_range))

    # ---- the diagnosis -----------------------------------------------------------------------------------
    @classmethod
    def blocks(cls, layout) -> list[Block]:
        """Every place the search tries this effect at (none unless ``model`` is "block")."""
        return []

    @classmethod
    def values(cls, layout, target: int) -> int:
        """The block's free values (a widened prior has none: its τ are estimated anyway)."""
        return 2

    @classmethod
    def channels(cls, layout, target: int) -> list[int]:
        """The sensor channels a sensor block acts on: the accelerometer's."""
        return list(layout.groups[target])

    @classmethod
    def displace(cls, lines: MeasuredLines, layout, target: int, v: np.ndarray) -> None:
        """Move ``lines`` as the block's values ``v`` say (mismatch notes §3 B, C)."""

    @classmethod
    def plausible(cls, result, block: Block, v: np.ndarray, tau: np.ndarray) -> bool:
        """Fitted values a technician could have produced (notes §6)."""
        return True

    @classmethod
    def parameters(cls, result, block: Block) -> dict:
        """The finding's JSON-ready parameters from an accepted fit (SI, angles in degrees, with 1-σ)."""
        return {}

    @classmethod
    def undo_rows(cls, frf: np.ndarray, channels) -> None:
        """A discrete effect undone in place on FRF rows (n_s, ...)."""

    @classmethod
    def proposals(cls, n_channels: int) -> list[tuple]:
        """The channels a discrete screen tries this effect on."""
        return []

    @classmethod
    def correct(cls, frf: np.ndarray, sensors: Lines, exciters: Lines, finding) -> tuple:
        """The recording's FRFs and lines with the finding undone: a discrete effect's rows by ``undo_rows`` (the
        lines unchanged); anything else unchanged unless the effect says how."""
        cls.undo_rows(frf, finding.channels)
        return frf, sensors, exciters

    @classmethod
    def correct_lines(cls, frequencies: np.ndarray, frf: np.ndarray, finding) -> np.ndarray:
        """The FRFs (n_s, n_e, n_f) with what the finding does in frequency undone at ``frequencies`` (Hz): unchanged
        unless the effect acts line by line (:class:`RowEffect`)."""
        return frf

    @classmethod
    def option_value(cls, finding) -> float:
        """What identify is given (``identify_option``) to undo the finding (an effect undone by identify)."""
        raise NotImplementedError(f"{cls.name} is not undone by identify")

    @classmethod
    def sentence(cls, finding, who: str, hit: str | None) -> str:
        """The finding as an engineer would write it (``who``: the sensors, ``hit``: the hit, as named)."""
        raise NotImplementedError

    @classmethod
    def concealed(cls, size: float, scene: Scene) -> str:
        """The effect as concealed in a virtual test, in words (the demo)."""
        raise NotImplementedError

    @classmethod
    def located(cls, finding, channels: list, hit: int | None) -> bool:
        """Whether ``finding`` names this effect at its concealed place (channels 0-based, or the hit)."""
        if hit is not None:
            return finding.exciter == hit
        return not channels or channels[0] in finding.channels


class LocationEffect(Effect):
    """A line glued or hit away from its labelled point: an offset δ of the point (m)."""

    moves = "point"

    @classmethod
    def check_size(cls, size: float) -> None:
        """A distance from 0 to 1 m: a point farther than that from its label is another point of the plan."""
        super().check_size(size)
        need(0 <= size <= 1.0, f"effect {cls.name}: an offset of {size:g} m is no mounting error: give 0 to 1 m")

    @classmethod
    def plausible(cls, result, block: Block, v: np.ndarray, tau: np.ndarray) -> bool:
        """An offset of more than three times the layout's size is none."""
        return np.linalg.norm(v) < 3 * result.problem.layout.extent


class TailEffect(Effect):
    """Test physics the band fit carries as a tail law (:mod:`massline.identify.tails`): a mode outside the band
    whose tail reaches into it. Simulated by the virtual test's support or FE modes, never an ``--effect``."""

    kind: ClassVar[str] = "test_physics"
    simulated: ClassVar[bool] = False
    model: ClassVar[str | None] = "tail"
    undone_on: ClassVar[str | None] = None  # modelled in every FRF, as identify does: no correction
    edge_line: ClassVar[int] = 0  # the band's line where its tail is largest: 0 the lower edge, -1 the upper
    rigid_tail: ClassVar[bool] = False  # its tail may be the rigid body's, s_iᵀ X e_j, shared by every FRF

    @classmethod
    def tail_parameters(cls, band, reduced, resonance: float) -> dict:
        """Its size at the band's edge relative to the FRF matrix's scale (the RMS of every massline: a small
        cross massline is no scale) and the frequency of the mode behind it where the record resolves its peak
        (``resonance`` Hz, nan when it does not), never a fitted pole's."""
        size = band.tail_size(reduced, cls.name)
        return {
            "edge_hz": float(band.frequencies[cls.edge_line]),
            "tail_median": float(np.median(size)),
            "tail_max": float(size.max()),
            "mode_hz": None if not np.isfinite(resonance) else float(resonance),
        }

    @classmethod
    def tail_evidence(cls, reduced) -> dict:
        """What the evidence adds about the tail's form (nothing by default)."""
        return {}


class RowEffect(Effect):
    """A sensor's chain reading its row through a factor of frequency F(f; p), the same on every FRF of the channel
    (a front end's delay, a mount's resonance). Its masslines barely show it (F → 1 as f → 0, and each FRF's tails
    take up a smooth rise), so the diagnosis fits p on the band's lines of the row, jointly with the rigid motion at
    every line (:mod:`massline.identify.diagnose.row_factors`); undone by dividing the row by F."""

    model: ClassVar[str | None] = "row"
    parameter: ClassVar[str] = ""  # the parameters' key of p (SI), its 1-σ under ``parameter + "_std"``
    signature: ClassVar[str] = ""  # what its factor looks like in frequency (:mod:`..signature`)

    @classmethod
    def factor(cls, frequencies: np.ndarray, value: float) -> np.ndarray:
        """F(f; p) at ``frequencies`` (Hz): what the channel reads per unit of what its point does."""
        raise NotImplementedError

    @classmethod
    def search_range(cls, top: float) -> tuple[float, float, bool]:
        """(low, high, logarithmic) of p searched on a band whose top line is ``top`` Hz."""
        raise NotImplementedError

    def simulate(self, state, lines, targets, rng):
        for t in targets:
            state.add_response(t, lambda f, value=self.size: type(self).factor(f, value))
        return {}

    @classmethod
    def value_of(cls, finding) -> float:
        """p of a finding."""
        return float(finding.parameters[cls.parameter])

    @classmethod
    def row_parameters(cls, value: float, sigma: float) -> dict:
        """The finding's parameters: p and its 1-σ."""
        return {cls.parameter: float(value), f"{cls.parameter}_std": float(sigma)}

    @classmethod
    def lines_fit(cls, finding) -> str:
        """The channel's misfit on the band's lines before and after, in the noise's units (√ of its row's reduced χ²
        against the others' rigid motion)."""
        fit = finding.evidence.get("row_chi2_reduced")
        if not fit or not np.isfinite([fit["before"], fit["after"]]).all():
            return ""
        before, after = np.sqrt(fit["before"]), np.sqrt(fit["after"])
        return f"; its lines {before:.2f}× → {after:.2f}× the noise off the others' rigid motion"

    @classmethod
    def correct_lines(cls, frequencies, frf, finding):
        """The channel's FRFs ÷ F(f; p)."""
        channels = list(finding.channels)
        frf[channels] = frf[channels] / cls.factor(frequencies, cls.value_of(finding))
        return frf


def accelerometers(lines: Lines, targets: list[int]) -> list[tuple[int, list[int]]]:
    """(line, its accelerometer's lines) for each target whose accelerometer no earlier target moved."""
    done, out = set(), []
    for t in targets:
        group = lines.triaxial[t]
        block = [t] if group < 0 else list(np.flatnonzero(lines.triaxial == group))
        if t not in done:
            out.append((t, block))
        done.update(block)
    return out


def perpendicular(d: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """A random unit vector ⊥ d."""
    v = rng.normal(size=3)
    v -= (v @ d) * d
    return v / np.linalg.norm(v)


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation matrix about unit ``axis`` by ``angle`` rad."""
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def moved_lines(lines: Lines, index: int, point=None, direction=None) -> Lines:
    """``lines`` with line ``index`` at a new point (m) and/or along a new direction."""
    points, directions = lines.points.copy(), lines.directions.copy()
    if point is not None:
        points[index] = point
    if direction is not None:
        directions[index] = direction
    return Lines(points, directions, lines.triaxial)


def block_values(result, block: Block) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A fitted block's values, their 1-σ and every channel's transverse components τ (n_s, 2)."""
    _, tau, values = result.parts
    return values[result.blocks.index(block)], result.block_std(block), tau


def pm(value: float, sigma: float) -> str:
    """ "value ± σ", the value to what its σ supports."""
    return " ± ".join(value_with_sigma(value, sigma))


def mm(vector, sigma_mm: float) -> str:
    """An offset (m) in mm, each entry to the digits of the distance's 1-σ (mm)."""
    return "(" + ", ".join(signed(value_with_sigma(1e3 * v, sigma_mm)[0]) for v in vector) + ") mm"


def offset_parameters(offset: np.ndarray, distance: float, sigma: np.ndarray) -> dict:
    """A location's parameters: the offset (m), its length ``distance`` (m) and the length's 1-σ, in mm."""
    return {
        "offset_m": offset.tolist(),
        "distance_mm": float(1e3 * distance),
        "distance_std_mm": float(1e3 * np.linalg.norm(sigma)),
    }


def need(condition: bool, message: str) -> None:
    """Raise a MasslineError with ``message`` unless ``condition``."""
    if not condition:
        raise MasslineError(message)
