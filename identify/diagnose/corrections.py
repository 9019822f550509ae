"""The recording with the faults a diagnosis found undone, for identify to estimate the properties again.

One estimator: the diagnosis says what is wrong; the properties before and after are identify's, on the
recording as it came and as corrected. Each fault is undone where it entered:

    sensor_polarity     the channel's FRFs × −1
    channel_swap        the two channels' FRFs exchanged
    sensor_gain         the channel's FRFs ÷ its gain
    sensor_direction    the channel's direction set to the axis it was found to read along
    sensor_location     the channel's point moved by the offset found
    excitation_direction, excitation_location   the hit's direction or point, likewise

Test physics (the support, the elastic modes) is no correction: identify models both in every band fit.
Mass loading is undone on the body, not the recording (:func:`.mass_loading.mass_loading`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from massline.identify.diagnose.finding import Finding
from massline.core.lines import Lines


def moved_lines(lines: Lines, index: int, point=None, direction=None) -> Lines:
    """``lines`` with line ``index`` at a new point (m) and/or along a new direction."""
    points, directions = lines.points.copy(), lines.directions.copy()
    if point is not None:
        points[index] = point
    if direction is not None:
        directions[index] = direction
    return Lines(points, directions, lines.triaxial)


def undone(recording, finding: Finding):
    """The recording with one fault undone (test physics and mass loading: unchanged)."""
    p, frf, sensors, exciters = finding.parameters, recording.frf.copy(), recording.sensors, recording.exciters
    channels = list(finding.channels)
    if finding.effect == "sensor_polarity":
        frf[channels] *= -1
    elif finding.effect == "channel_swap":
        frf[channels] = frf[channels[::-1]]
    elif finding.effect == "sensor_gain":
        frf[channels] /= p["gain"]
    elif finding.effect == "sensor_direction":
        for c, axis in zip(channels, p["effective_axis"]):
            sensors = moved_lines(sensors, c, direction=np.asarray(axis))
    elif finding.effect == "sensor_location":
        for c in channels:
            sensors = moved_lines(sensors, c, point=sensors.points[c] + np.asarray(p["offset_m"]))
    elif finding.effect == "excitation_direction":
        exciters = moved_lines(exciters, finding.exciter, direction=np.asarray(p["direction"]))
    elif finding.effect == "excitation_location":
        j = finding.exciter
        exciters = moved_lines(exciters, j, point=exciters.points[j] + np.asarray(p["offset_m"]))
    return replace(recording, frf=frf, sensors=sensors, exciters=exciters)


def corrected(recording, findings: list):
    """The recording with every fault among ``findings`` undone, in their order."""
    for finding in findings:
        recording = undone(recording, finding)
    return recording
