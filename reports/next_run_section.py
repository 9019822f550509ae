"""The placement report's next run (``massline plan --after``): the first run's points and the additions drawn in
two colours, and the proposals with the target's 1-σ after both runs."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from massline.reports.html import escape, html_table, num
from massline.reports.plan_scene import ADDED, HIT, SENSOR, Scene


def marked_added(doc: dict, scene: Scene) -> Scene:
    """The scene with the markers of the lines a next run adds (plan.json's ``"added": true``) of kind ``ADDED``:
    the first run's points and the additions in two colours."""
    added = {kind: {i for i, e in enumerate(doc[key]) if e.get("added")} for kind, key in ((SENSOR, "sensors"),
             (HIT, "exciters"))}  # fmt: skip
    markers = [replace(m, kind=ADDED) if added.get(m.kind, set()) & set(m.lines) else m for m in scene.markers]
    return replace(scene, markers=markers)


def next_run_html(doc: dict) -> str:
    """The next run's proposals (plan.json's ``after``), '' for a plan made from nothing."""
    after = doc.get("after")
    if not after:
        return ""
    unit = escape(after["unit"])
    before = np.nan if after["std_before"] is None else float(after["std_before"])  # null: nothing identified
    rows = [
        [str(k), escape(p["what"]), num(p["std_after"], ".3g"),
         (num(before / p["std_after"], ".3g") + "×" if np.isfinite(before) else "—")
         + (" (restores identifiability)" if p["restores_identifiability"] else "")]
        for k, p in enumerate(after["proposals"], 1)
    ]  # fmt: skip
    note = (
        f'<p class="note">After the first run ({escape(Path(after["recording"]).name)}, band '
        f'{num(after["band_hz"][0], ".4g")}–{num(after["band_hz"][1], ".4g")} Hz, noise '
        f'{num(100 * after["noise_relative"], ".3g")} %), the 1-σ of {escape(after["target"])} is '
        f'{num(before, ".3g") if np.isfinite(before) else "unbounded (the layout is not solvable)"} {unit}. The second run repeats the first with addition 1: its points are '
        '<span class="added">drawn in purple</span>, the first run\'s in blue (accelerometers) and red (hits).</p>'
    )
    head = ["#", "addition", f"1-σ after both runs ({unit})", "gain"]
    return "<section><h2>Next run</h2>" + note + html_table(head, rows, "llrl", [6, 40, 27, 27]) + "</section>"
