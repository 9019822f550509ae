"""The recording as the diagnosis reads it: its usable lines, identify's properties on it as it came, and the bands.

The first stage of :func:`.pipeline.diagnose_recording`. Lines at or below 0 Hz are set aside, as identify does,
and with the mesh's FE model the support's departure from the masslines is taken off first
(:func:`massline.identify.pipeline.support_corrected`); the lines of any mains interference are set aside from the
band data (identify sets them aside itself). identify on the file as it came gives the properties before, weighed
against the mesh's mass as ``identify --mesh`` weighs them, and its band is the one the properties are estimated
on; the diagnosis band is the one given, else identify's, else one found on the record.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from massline.identify.band_choice import choose_band
from massline.identify.diagnose.effect_model import Layout
from massline.identify.diagnose.effects import held
from massline.identify.diagnose.effects.mains_interference import MainsInterference
from massline.identify.diagnose.screens import kinematic_matrix
from massline.identify.diagnose.undone import identified
from massline.identify.missing_pairs import unmeasured_notes
from massline.identify.pipeline import (
    Identification,
    against_nominal,
    as_recording,
    is_planar,
    support_corrected,
    usable_lines,
    without_mains,
)
from massline.identify.warning_codes import CodedWarning
from massline.identify.zones import given_band
from massline.core.band import Band
from massline.core.degeneracy import unseen_motion
from massline.core.errors import MasslineError
from massline.uff.recording import Recording


@dataclass(frozen=True, eq=False, kw_only=True)
class Reading:
    """A recording as the diagnosis reads it.

    Attributes
    ----------
    recording : Recording
        The recording diagnosed: its usable lines, the support's departure taken off when a support was given.
    cleaned : Recording
        ``recording`` without the lines of mains interference (``recording`` when there is none).
    mains : object or None
        The mains interference found (its lines are in ``recording``, not in ``cleaned``).
    notes : tuple of CodedWarning
        What was set aside before the diagnosis (the support modelled, an exporter's 0 Hz line, nodes without
        FRFs, the mains' lines).
    planar : bool
    layout : Layout
    before : Identification or None
        identify on the file as it came (None: it refuses it), weighed against the mesh's mass.
    refused : tuple of CodedWarning
        Why identify refused the file, or found no band of its own.
    identify_band : tuple or None
        The band every identify run of the diagnosis is given (None: identify's own).
    band : Band
        The diagnosis band (the plan's, given, or found).
    estimation : Band
        The band the properties are estimated on: identify's.
    known : dict
        identify's options for the masses the engineer gave (``sensor_mass``, ``exciter_mass``).
    """

    recording: Recording
    cleaned: Recording
    mains: object
    notes: tuple
    planar: bool
    layout: Layout
    before: Identification | None
    refused: tuple
    identify_band: tuple | None
    band: Band
    estimation: Band
    known: dict


def read(recording, band, nominal, transverse: float, known: dict, support) -> Reading:
    """The recording (a Recording, a Universal File's path, or several) read for the diagnosis on ``band`` (lo, hi)
    Hz or identify's, ``nominal`` the mesh's body (or None), ``known`` identify's options for the masses given,
    ``support`` the mesh's support model (or None)."""
    recording, notes = usable(as_recording(recording), band, transverse, known, support)
    cleaned, mains, aside = without_mains(recording) if held(MainsInterference.name) else (recording, None, ())
    planar = is_planar(recording.sensors, recording.exciters)
    layout = Layout.of(recording.sensors, recording.exciters, planar)
    check_seen(layout)
    before, refused = identified(recording, band, transverse, known)
    if before is not None:
        before = against_nominal(before, nominal)  # the mesh's mass checked as identify --mesh checks it
    used = diagnosis_band(cleaned, band, before, planar)
    return Reading(
        recording=recording,
        cleaned=cleaned,
        mains=mains,
        notes=notes + aside,
        planar=planar,
        layout=layout,
        before=before,
        refused=refused,
        identify_band=band if before is not None and before.band.rule == "given" else None,
        band=used,
        estimation=used if before is None else before.band,
        known=known,
    )


def usable(recording: Recording, band, transverse: float, known: dict, support) -> tuple[Recording, tuple]:
    """The recording with the ``support`` model's departure taken off (when given) and only its usable lines, and
    the notes saying what was done and set aside."""
    modelled = ()
    if support is not None:
        recording, fit = support_corrected(recording, band, support, transverse=transverse, **known)
        modelled = (CodedWarning("support_modelled", fit.note),)
    recording, notes = usable_lines(recording)
    return recording, modelled + notes + unmeasured_notes(recording.unmeasured_nodes)


def diagnosis_band(cleaned: Recording, band, before: Identification | None, planar: bool) -> Band:
    """The band the diagnosis examines: ``band`` given, else identify's, else one found on the record."""
    f = cleaned.frequencies
    if band:
        return given_band(f, *band)
    return before.band if before else choose_band(f, cleaned.frf, cleaned.sensors, cleaned.exciters, planar)


def check_seen(layout: Layout) -> None:
    """Refuse sensor lines that cannot see every rigid motion (identify refuses them too): nothing to diagnose."""
    need = 3 if layout.planar else 6
    rank = np.linalg.matrix_rank(kinematic_matrix(layout.sensors, layout.planar))
    if rank < need:
        why = f"the sensor lines see {rank} of a plate's 3 rigid motions" if layout.planar else None
        raise MasslineError(
            f"{why or unseen_motion(layout.sensors)}: the body can be neither identified nor diagnosed; "
            "measure more responses"
        )
