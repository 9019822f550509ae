"""What a blind case is measured by, and the suite's report: the confusion matrix, the property errors
before → after per effect, the frequency checks.

A case is right when its injected faults are the first faults named, each at its place, and the injected
test physics (a support or an elastic mode reaching into the band) is reported as such; a clean case names
no fault. The properties are weighed against the bare body (the mesh's: the tool is told nothing of the
housings' masses): identify's bounds (``BOUNDS``) or, as identify promises where a support or the record
limits it (tests/lab_matrix.py), within 2σ with a warning saying why; and after no worse than before by more
than 1σ.
"""

from __future__ import annotations

from collections import Counter, defaultdict

import numpy as np

TAILS = ("suspension", "residual_flexibility")
BOUNDS = {"mass": 0.003, "cog_m": 1e-3, "moments": 0.01}  # the accuracy identify is held to: 0.3 %, 1 mm, 1 %


def label(finding) -> str:
    """The scenario name of a finding: a loading of every housing is ``every_sensor_mass``."""
    if finding.effect == "sensor_mass_loading" and finding.parameters.get("every_housing"):
        return "every_sensor_mass"
    return finding.effect


def placed(fault: dict, finding) -> bool:
    """The finding sits where the fault was put (an accelerometer's group counts for its channels)."""
    if fault["lines"] is None:
        return True
    where = [line - 1 for line in fault["lines"]]
    if fault["name"] == "channel_swap":
        return set(finding.channels) == set(where)
    if fault["name"].startswith("excitation"):
        return finding.exciter == where[0]
    return where[0] in finding.channels


def named_right(injected: list, faults: list, physics: set) -> bool:
    """The injected instrument faults are the first faults named, each at its place; the injected test
    physics is reported; a clean case names no fault."""
    wanted = [f for f in injected if f["name"] not in TAILS]
    first = faults[: len(wanted)]
    if len(first) < len(wanted) or (not wanted and faults):
        return False
    for fault in wanted:
        match = [x for x in first if label(x) == fault["name"] and placed(fault, x)]
        if not match:
            return False
        first.remove(match[0])
    return all(f["name"] in physics for f in injected if f["name"] in TAILS)


def errors(body, true, planar: bool) -> np.ndarray:
    """Signed errors: mass (fraction), CoG (m, per coordinate), moments (fraction, per axis)."""
    if planar:
        moments = [body.inertia_cog[k, k] / true.inertia_cog[k, k] - 1 for k in (0, 1)]
        return np.concatenate([[body.mass / true.mass - 1], body.cog[:2] - true.cog[:2], moments])
    moments = body.principal_moments / true.principal_moments - 1
    return np.concatenate([[body.mass / true.mass - 1], body.cog - true.cog, moments])


def sigmas(found, true, planar: bool) -> np.ndarray:
    """1-σ of ``errors``' entries from identify's reported standard deviations."""
    s = found.std
    cog = np.asarray(s["cog"])[:2] if planar else np.asarray(s["cog"])
    if planar:
        moments = [s["inertia_cog"][k][k] / true.inertia_cog[k, k] for k in (0, 1)]
    else:
        moments = np.asarray(s["principal_moments"]) / true.principal_moments
    return np.concatenate([[s["mass"] / true.mass], cog, moments])


def summary(e: np.ndarray) -> dict:
    """Mass error, worst CoG coordinate, worst moment, from ``errors``' vector."""
    cog = e[1:3] if len(e) == 5 else e[1:4]
    return {"mass": float(e[0]), "cog_m": float(np.abs(cog).max()), "moments": float(np.abs(e[1 + len(cog) :]).max())}


def frequency_errors(found, truth: dict) -> list:
    """Relative errors of every printed support / first elastic frequency."""
    true = {"suspension": max(truth["suspension"]["modes_hz"], default=np.nan)}
    true["residual_flexibility"] = truth["elastic_hz"][0] if truth["elastic_hz"] else np.nan
    out = []
    for x in found.findings:
        mode = x.parameters.get("mode_hz") if x.kind == "test_physics" else None
        if mode is not None:
            out.append(abs(mode / true[x.effect] - 1))
    return out


def outcome(found, truth: dict, bare, planar: bool) -> dict:
    """The measures of one case (``found``: a DiagnosisRun; ``bare``: the body without any housing)."""
    faults = [x for x in found.findings if x.kind == "fault"]
    physics = {x.effect for x in found.findings if x.kind == "test_physics"}
    injected = truth["faults"]
    after = errors(found.after_body, bare, planar)
    sigma = sigmas(found.after, bare, planar)
    before = errors(found.before.body, bare, planar) if found.before is not None else np.full_like(after, np.nan)
    worse = np.nanmax((np.abs(after) - np.abs(before)) / sigma) if found.before is not None else 0.0
    if found.before is not None:  # the same on identify's own ± (a before that is off by a tenth of it is luck)
        worse_on_identify = np.nanmax((np.abs(after) - np.abs(before)) / sigmas(found.before, bare, planar))
    else:
        worse_on_identify = 0.0
    a, b = summary(after), summary(before)
    return {
        "injected": "+".join(f["name"] for f in injected) or "none",
        "named": "+".join([label(x) for x in faults[: max(1, len(injected))]] + sorted(physics & set(TAILS))) or "none",
        "right": named_right(injected, faults, physics),
        "faults_named": len(faults),
        "within": abs(a["mass"]) < BOUNDS["mass"] and a["cog_m"] < BOUNDS["cog_m"] and a["moments"] < BOUNDS["moments"],
        "covered": bool(found.after.warnings) and float(np.max(np.abs(after) / sigma)) <= 2.0,
        "mass_sigma": abs(after[0]) / sigma[0],
        "worse_sigma": float(worse),
        "worse_identify_sigma": float(worse_on_identify),
        "frequency_errors": frequency_errors(found, truth),
        **{k: v for k, v in a.items()},
        **{f"{k}_before": v for k, v in b.items()},
    }


def confusion(rows: list) -> str:
    """Injected × named (first faults named, then reported test physics of the injected kind), sparse."""
    by = defaultdict(Counter)
    for r in rows:
        by[r["injected"]][r["named"]] += 1
    lines = [f"{'injected':>40} | n | right | named (count)"]
    for injected in sorted(by, key=lambda k: (k != "none", "+" in k, k)):
        n = sum(by[injected].values())
        right = sum(r["right"] for r in rows if r["injected"] == injected)
        named = ", ".join(f"{k}×{v}" for k, v in by[injected].most_common())
        lines.append(f"{injected:>40} | {n} | {right} | {named}")
    return "\n".join(lines)


def properties(rows: list) -> str:
    """Property errors before → after per effect (median | worst), and the worst after − before in σ."""
    lines = ["property errors before → after (median | worst): mass %, CoG mm, moments %; worst (|after|−|before|)/σ"]
    for injected in sorted({r["injected"] for r in rows}, key=lambda k: (k != "none", "+" in k, k)):
        group = [r for r in rows if r["injected"] == injected]
        cells = []
        for key, scale in (("mass", 100), ("cog_m", 1e3), ("moments", 100)):
            b = np.abs([r[f"{key}_before"] for r in group]) * scale
            a = np.abs([r[key] for r in group]) * scale
            cells.append(f"{np.nanmedian(b):.3g}|{np.nanmax(b):.3g} → {np.median(a):.3g}|{a.max():.3g}")
        within = sum(r["within"] or r["covered"] for r in group)
        worse = max(r["worse_sigma"] for r in group)
        lines.append(f"{injected:>40}: " + "; ".join(cells) + f"; within {within}/{len(group)}; worse {worse:.2f}σ")
    return "\n".join(lines)


def report(rows: list) -> str:
    """The whole suite's report."""
    faulty = [r for r in rows if r["injected"] != "none"]
    clean = [r for r in rows if r["injected"] == "none"]
    freq = [e for r in rows for e in r["frequency_errors"]]
    seconds = [r.get("seconds", 0.0) for r in rows]
    supports = sorted({r.get("support", "") for r in faulty})
    by_support = ", ".join(
        f"{k} {sum(r['right'] for r in faulty if r.get('support') == k)}/{sum(r.get('support') == k for r in faulty)}"
        for k in supports
    )
    return "\n".join(
        [
            confusion(rows),
            properties(rows),
            (
                f"named right at their places: {sum(r['right'] for r in faulty)} of {len(faulty)}; "
                f"clean with no fault: {sum(r['faults_named'] == 0 for r in clean)} of {len(clean)}; "
                f"within bounds: {sum(r['within'] for r in rows)}, or covered (2σ, warned): "
                f"{sum(r['within'] or r['covered'] for r in rows)} of {len(rows)}; "
                f"worse than before by > 1σ: {sum(r['worse_sigma'] > 1 for r in rows)} "
                f"(by > 1 of identify's σ: {sum(r.get('worse_identify_sigma', 0) > 1 for r in rows)})"
            ),
            f"named right by support: {by_support}",
            (
                f"printed frequencies: {len(freq)}, worst error {100 * max(freq, default=0):.2f} %, "
                f"beyond 10 %: {sum(e > 0.1 for e in freq)}"
            ),
            f"diagnose time per case: median {np.median(seconds):.1f} s, worst {np.max(seconds):.1f} s",
        ]
    )
