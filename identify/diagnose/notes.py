"""A diagnosis finding as an engineer would write it: one sentence."""

from __future__ import annotations

from massline.identify.diagnose.finding import Finding
from massline.placement.numbers import formatted, signed, value_with_sigma


def _pm(value: float, sigma: float) -> str:
    """ "value ± σ", the value to what its σ supports."""
    return " ± ".join(value_with_sigma(value, sigma))


def _mm(vector, sigma_mm: float) -> str:
    """An offset (m) in mm, each entry to the digits of the distance's 1-σ (mm)."""
    return "(" + ", ".join(signed(value_with_sigma(1e3 * v, sigma_mm)[0]) for v in vector) + ") mm"


def finding_note(finding: Finding, sensors: list, hits: list) -> str:
    """One sentence: what is wrong, where, how large, and what was done about it.

    ``sensors``, ``hits``: the channels' labels (:class:`massline.uff.recording.Channel`), indexed as the finding's.
    """
    p, e = finding.parameters, finding.evidence
    names = [sensors[c] for c in finding.channels]
    if len(names) == 3 and names[0].node is not None and len({n.node for n in names}) == 1:
        who = f"the triaxial sensor at node {names[0].node}"
    else:
        who = " and ".join(f"sensor {n}" for n in names)
    hit = None if finding.exciter is None else f"hit {hits[finding.exciter]}"
    also = e.get("alternatives") or []
    tail = f" (the data fit {' or '.join(also)} there as well)" if also else ""
    moved = e.get("moved")
    shift = f"; modelling it moves the mass by {formatted(moved['mass_percent'], '+.3f')} %" if moved else ""
    text = {
        "sensor_direction": lambda: (
            f"{who} reads {_pm(max(p['angle_deg']), max(p['angle_std_deg']))}° off its labelled axis: "
            "misalignment or transverse sensitivity beyond the datasheet (the data cannot tell them apart)"
        ),
        "sensor_gain": lambda: (
            f"{who} reads {signed(value_with_sigma(100 * (p['gain'] - 1), 100 * p['gain_std'])[0])} % of what it "
            f"should (gain {_pm(p['gain'], p['gain_std'])}): check its sensitivity in the channel table"
        ),
        "sensor_polarity": lambda: (
            f"{who} has its polarity flipped: its readings are the rigid body's with the opposite sign; corrected"
        ),
        "channel_swap": lambda: f"{who} are swapped: each channel reads what the other should; corrected",
        "sensor_location": lambda: (
            f"{who} sits {_pm(p['distance_mm'], p['distance_std_mm'])} mm from its labelled point "
            f"(offset {_mm(p['offset_m'], p['distance_std_mm'])}; along its axis an offset cannot be seen)"
        ),
        "excitation_direction": lambda: (
            f"{hit} went in {_pm(p['angle_deg'], p['angle_std_deg'])}° off its labelled direction"
        ),
        "excitation_location": lambda: (
            f"{hit} landed {_pm(p['distance_mm'], p['distance_std_mm'])} mm from its labelled point "
            f"(offset {_mm(p['offset_m'], p['distance_std_mm'])})"
        ),
        "suspension": lambda: (
            f"the suspension's tail reaches {p['tail_max']:.1%} of the massline at "
            f"{p['edge_hz']:.1f} Hz (median {p['tail_median']:.1%}): a support mode near {p['mode_hz']:.1f} Hz; "
            "modelled as that mode's tail in every FRF"
            + (
                " (the ± of the properties says how much that leaves open: a softer support, or a band from "
                f"{3 * p['mode_hz']:.0f} Hz, does better)"
                if 3 * p["mode_hz"] > p["edge_hz"]
                else ""
            )
        ),
        "residual_flexibility": lambda: (
            f"elastic modes above the band pull the masslines by up to "
            f"{p['tail_max']:.1%} at {p['edge_hz']:.0f} Hz (median {p['tail_median']:.1%}): an elastic mode near "
            f"{p['mode_hz']:.0f} Hz; modelled as that mode's tail in every FRF"
            + (
                f" (the ± of the properties says how much that leaves open: a band up to {p['mode_hz'] / 3:.0f} Hz "
                "does better)"
                if p["mode_hz"] / 3 < p["edge_hz"]
                else ""
            )
        ),
        "sensor_mass_loading": lambda: (
            f"the body is {_pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g "
            f"heavier than the mesh, as a mass at {who} would make it; taken away"
        ),
    }[finding.effect]()
    return text + tail + shift
