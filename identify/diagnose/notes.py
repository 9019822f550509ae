"""A diagnosis finding as an engineer would write it: one sentence."""

from __future__ import annotations

from massline.identify.diagnose.finding import Finding
from massline.core.numbers import formatted, signed, value_with_sigma


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
    shift = f"; undoing it moves identify's mass by {formatted(moved['mass_percent'], '+.3f')} %" if moved else ""
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
            f"test physics, the support: its tail reaches {p['tail_max']:.1%} of the FRF matrix's scale at "
            f"{p['edge_hz']:.1f} Hz (median {p['tail_median']:.1%})"
            + (f"; its top mode is at {p['mode_hz']:.3g} Hz" if p.get("mode_hz") else "")
            + "; modelled in every FRF, as identify does"
        ),
        "residual_flexibility": lambda: (
            f"test physics, the elastic modes above the band: their tail reaches {p['tail_max']:.1%} of the FRF "
            f"matrix's scale at {p['edge_hz']:.0f} Hz (median {p['tail_median']:.1%})"
            + (f"; the first is at {p['mode_hz']:.3g} Hz" if p.get("mode_hz") else "")
            + "; modelled in every FRF, as identify does"
        ),
        "sensor_mass_loading": lambda: (
            (
                f"every accelerometer housing ({p['housings']}) weighs "
                f"{_pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g: "
                f"the body as tested is {formatted(1e3 * p['mass_kg'] * p['housings'], '.0f')} g heavier than the "
                "mesh in their pattern; taken off (identify --sensor-mass does the same)"
            )
            if p.get("every_housing")
            else (
                f"the body is {_pm(1e3 * p['mass_kg'], 1e3 * p['mass_std_kg'])} g heavier than the mesh, as a mass "
                f"at {who} would make it; taken off"
            )
        ),
    }[finding.effect]()
    return text + tail + shift
