"""Read and identify 1,000 FRFs × 2,000 lines; beside a plain pyuff read of the same file.

A virtual test of the bundled structure with 334 accelerometers × 3 hits (1,002 FRFs,
2,000 lines, ascii 58) is written once; then it is read by massline's reader, the
band is chosen among the candidates (``identify_recording``), every FRF is fitted and the properties are estimated (with a
bootstrap of 100 draws), and the same file is read by ``pyuff.UFF(path).read_sets()``
alone (the baseline). Prints times, the whole identification's time by stage (read, band choice, fits,
estimate, the truncation's shift of the properties, bootstrap) and its ratio to the pyuff read: first by the wall clock, then again under tracemalloc
for the peak Python memory. tracemalloc hooks every allocation: it slows pyuff's read (many small Python
objects) some tenfold and numpy-bound code far less, so the ratios of the two passes differ widely.

    python benchmarks/identify.py [--sensors 334] [--binary]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pyuff
from common import measured, surface_lines

from massline.identify import band_masslines, pipeline, uncertainty
from massline.identify.pipeline import identify_recording
from massline.meshes import BUNDLED
from massline.placement.hand_layouts import structure_exciters
from massline.meshes.loader import load_body
from massline.uff.grid import to_recording
from massline.uff.reader import read_uff
from massline.uff.writer import write_uff
from massline.virtual.suspension import Cord, Suspension
from massline.virtual.acquisition import Acquisition, run

STAGES = {  # the pipeline's stage functions, timed where the pipeline calls them: (module, name) → stage
    (band_masslines, "choose_band"): "band choice",
    (band_masslines, "fit_band"): "fits",
    (pipeline, "estimate"): "estimate",
    (uncertainty, "truncation_std"): "truncation",
    (uncertainty, "bootstrap"): "bootstrap",
}


def identify_file(path: Path, seconds: dict):
    """``massline identify``'s pipeline: the band chosen by the model, the fits, the estimate, 100 draws;
    the read's and each stage's time (s) added to ``seconds``."""
    start = time.perf_counter()
    recording = to_recording(read_uff(path))
    seconds["read"] = time.perf_counter() - start
    with stages_timed(seconds):
        return identify_recording(recording, draws=100)


@contextmanager
def stages_timed(seconds: dict):
    """The pipeline's stage functions (STAGES) timed while inside: their seconds added up in ``seconds``."""
    originals = {place: getattr(*place) for place in STAGES}

    def timed(place, work):
        def run(*args, **kwargs):
            start = time.perf_counter()
            try:
                return work(*args, **kwargs)
            finally:
                seconds[STAGES[place]] = seconds.get(STAGES[place], 0.0) + time.perf_counter() - start

        return run

    for (module, name), work in originals.items():
        setattr(module, name, timed((module, name), work))
    try:
        yield
    finally:
        for (module, name), work in originals.items():
            setattr(module, name, work)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sensors", type=int, default=334)
    parser.add_argument("--binary", action="store_true")
    args = parser.parse_args()
    body = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density)
    nominal = body.nominal
    sensors = surface_lines(body.mesh, args.sensors, np.random.default_rng(0))
    cord = Suspension(cords=(Cord(nominal.cog + [0, 0, 0.02], nominal.mass * 9.81 / 0.25, 1.0),))
    recording, _ = run(nominal, sensors, structure_exciters(), None, cord, (), Acquisition(200.0, 2000), 1)
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "big.uff"
        write_uff(path, recording, binary=args.binary)
        n_frf = recording.frf.shape[0] * recording.frf.shape[1]
        print(f"{n_frf} FRFs × {recording.frf.shape[2]} lines, {path.stat().st_size / 2**20:.0f} MiB on disk")
        for traced in (False, True):
            print("under tracemalloc (peak memory):" if traced else "wall clock:")
            found = compare(path, traced)
    print(
        f"band {found.band.low:.1f}–{found.band.high:.1f} Hz; mass {found.body.mass:.5f} ± {found.std['mass']:.5f} kg "
        f"(true {nominal.mass:.5f})"
    )


def compare(path: Path, traced: bool):
    """pyuff's read, massline's read and the whole identification of the file, timed; prints the stages and
    ratios; returns the identification."""
    _, plain = measured("  baseline: pyuff read_sets", lambda: pyuff.UFF(str(path)).read_sets(), traced)
    _, ours_read = measured("  massline read_uff + to_recording", lambda: to_recording(read_uff(path)), traced)
    seconds = {}
    found, ours = measured(
        "  massline read + band choice + fits + estimate + 1-σ", lambda: identify_file(path, seconds), traced
    )
    seconds["rest"] = ours - sum(seconds.values())
    print("    by stage: " + ", ".join(f"{label} {t:.2f} s" for label, t in seconds.items()))
    print(f"  read {plain / ours_read:.2f}× pyuff's speed; whole identification {plain / ours:.2f}× a pyuff read's")
    return found


if __name__ == "__main__":
    main()
