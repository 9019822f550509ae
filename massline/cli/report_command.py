"""``massline report PLAN.json``: the placement report of a plan, as one HTML file (``massline plan`` writes it too).

The page is assembled by :func:`massline.reports.placement_assembly.build_placement_report` (the plan's support
and band, or for a plan written before it kept them a soft cord and foam predicted on a coarse FE model; the
views rendered off-screen) and written atomically.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rich.console import Console

from massline.core.files import claim_output
from massline.cli.output import build_report, write_report


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("plan", metavar="PLAN.json", help="a plan written by 'massline plan'")
    parser.add_argument("--out", metavar="OUT.html", help="the report to write (default: report.html beside the plan)")
    parser.add_argument("--force", action="store_true", help="overwrite OUT.html if it exists")


def run(args: argparse.Namespace, console: Console) -> None:
    plan_path = Path(args.plan)
    out = claim_output(Path(args.out) if args.out else plan_path.with_name("report.html"), args.force, "--out")
    write_report(console, out, lambda: build_report(plan_path, console), args.force, status=None)
