"""Draw a setup.uff as test software shows it: the part's wireframe (dataset 82) and every point's coordinate
system (2420), its +Z (the accelerometer's axis or the hit's direction) long — read back with pyuff, so the
picture is what the file holds.

    python benchmarks/setup_picture.py plan/setup.uff docs/images/setup.png
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pyuff  # noqa: E402


def main(uff: str, png: str) -> None:
    sets = pyuff.UFF(uff).read_sets()
    nodes = next(s for s in sets if s["type"] in (15, 2411))
    systems = next(s for s in sets if s["type"] in (2420,))
    points = {int(n): np.array(p) for n, *p in zip(nodes["node_nums"], nodes["x"], nodes["y"], nodes["z"])}
    size = np.ptp(np.array(list(points.values())), axis=0).max()
    ax = plt.figure(figsize=(7, 6)).add_subplot(projection="3d")
    for line in (s for s in sets if s["type"] == 82):
        trace = [int(n) for n in line["nodes"]]
        for a, b in zip(trace, trace[1:]):
            if a and b:
                ax.plot(*np.array([points[a], points[b]]).T, color="0.55", lw=1)
    for label, matrix in zip(systems["CS_sys_labels"], systems["CS_matrices"]):
        origin, hit = matrix[3], label > 100
        for k, (color, scale) in enumerate((("tab:red", 0.06), ("tab:green", 0.06), ("tab:blue", 0.16))):
            ax.quiver(*origin, *(matrix[k] * scale * size), color=color, lw=1.5 if k == 2 else 0.8)
        ax.text(*(origin + matrix[2] * 0.18 * size), str(label), color="tab:red" if hit else "black", fontsize=8)
    ax.set_box_aspect(np.ptp(np.array(list(points.values())), axis=0))
    ax.set_axis_off()
    ax.set_title("setup.uff: wireframe (82), one system per point (2420), +Z blue", fontsize=9)
    plt.savefig(png, dpi=130, bbox_inches="tight")


if __name__ == "__main__":
    main(*sys.argv[1:3])
