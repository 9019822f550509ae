"""One word per mount: the placement report calls each point's mount what the console and plan.json call it
(it said "glued" for a point the console called "flat", hits included)."""

import json
import re

import session_cache

from massline.placement.mounts import Mount


def test_the_report_and_the_console_say_the_same_mount(bracket_default_plan):
    folder = session_cache.command("plan", "bracket")
    html = (folder / "out" / "report.html").read_text()
    doc = json.loads(bracket_default_plan.read_text())
    words = {Mount(e["mount"]["kind"], e["mount"]["gap_m"]).text for e in doc["sensors"] + doc["exciters"]}
    console = (folder / "stdout.txt").read_text()
    assert "glued" not in html and words <= set(re.findall(r"<td[^>]*>([^<]*)</td>", html))
    assert all(re.search(rf"│\s+{re.escape(w)} │", console) for w in words)
