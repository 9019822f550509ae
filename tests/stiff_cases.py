"""The blind suite's stiff-cord fault cases, named right or not: ``python tests/stiff_cases.py SEED [BENCH...]``
(``FAULTS=a,b`` only those; ``None`` the clean test).

The virtual tests are cached as UFF files (with their truth) under $STIFF_CACHE (default /tmp/stiff) so that
two versions of the diagnosis are compared on the same files.
"""

from __future__ import annotations

import json
import os
import pickle
import sys
import time
from pathlib import Path

from blind_measures import outcome
from test_diagnose_blind import STIFF, bench

from massline.identify.diagnose.effects import BY_NAME
from massline.identify.diagnose.pipeline import diagnose_recording
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.virtual.scenarios import FAULTS, PLANAR_FAULTS, scenario, write_case


def case_file(b, name: str, fault: str, seed: int) -> tuple[Path, dict]:
    """The cached UFF file and truth of one stiff case (simulated once)."""
    folder = Path(os.environ.get("STIFF_CACHE", "/tmp/stiff"))
    path, meta = folder / f"{name}-{fault}-{seed}.uff", folder / f"{name}-{fault}-{seed}.truth"
    if not meta.exists():
        recording, truth = scenario(b, fault, seed, STIFF, effects=BY_NAME)
        write_case(path, recording, STIFF)
        meta.write_bytes(pickle.dumps(truth))
    return path, pickle.loads(meta.read_bytes())


def main(seed: int, names) -> None:
    for name in names:
        b = bench(name)
        faults = PLANAR_FAULTS if name == "plate" else FAULTS
        chosen = os.environ.get("FAULTS", "").split(",") if os.environ.get("FAULTS") else None
        for fault in [f for f in faults if f != "suspension"] + [None]:
            if chosen is not None and str(fault) not in chosen:
                continue
            try:
                path, truth = case_file(b, name, fault, seed)
            except ValueError as error:  # no planned band on the stiff cord to place an elastic mode against
                print(json.dumps({"bench": name, "seed": seed, "fault": fault, "skipped": str(error)}), flush=True)
                continue
            start = time.perf_counter()
            found = diagnose_recording(
                to_recording(read_uff(path)), truth["planned_band_hz"] and tuple(truth["planned_band_hz"]), b.body
            )
            r = outcome(found, truth, b.body, b.planar)
            row = {
                "bench": name,
                "seed": seed,
                "fault": fault,
                "right": r["right"],
                "named": r["named"],
                "frequency_errors": [round(e, 3) for e in r["frequency_errors"]],
                "worse_sigma": round(r["worse_sigma"], 2),
                "within": r["within"] or r["covered"],
                "seconds": round(time.perf_counter() - start, 1),
            }
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2:] or ("bracket", "structure", "plate"))
