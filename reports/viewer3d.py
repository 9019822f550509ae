"""A 3-D view of the plan the reader turns with the mouse: a canvas and a small inline script.

No library and no network: the triangles (mm, frame O xyz of the mesh) and the
arrows are embedded as JSON and drawn back to front (painter's algorithm, back
faces culled; a translucent body shows what lies inside) on a 2-D canvas.
Dragging turns the body about the vertical z axis and tilts it.
"""

from __future__ import annotations

import json

import numpy as np
import trimesh

from massline.reports.plan_scene import COLOURS, Scene, outer_end

MAX_FACES = 4000  # larger meshes are decimated for the viewer

SCRIPT = """
(function () {
  const data = JSON.parse(document.getElementById("view3d-data").textContent);
  const canvas = document.getElementById("view3d");
  const g = canvas.getContext("2d");
  const v = data.vertices, f = data.faces;
  const lo = [0, 1, 2].map(k => Math.min(...v.map(p => p[k])));
  const hi = [0, 1, 2].map(k => Math.max(...v.map(p => p[k])));
  const centre = lo.map((a, k) => (a + hi[k]) / 2);
  const radius = Math.hypot(...hi.map((b, k) => b - lo[k])) / 2 + data.arrow;
  let yaw = -0.6, pitch = 0.45, drag = null;
  function turn(p) {
    const x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    const cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
    const xr = cy * x - sy * y, yr = sy * x + cy * y;
    return [xr, yr * cp - z * sp, yr * sp + z * cp];
  }
  function screen(q) {
    const s = 0.48 * Math.min(canvas.width, canvas.height) / radius;
    return [canvas.width / 2 + s * q[0], canvas.height / 2 - s * q[2]];
  }
  function draw() {
    const t = v.map(turn), items = [], labels = [];
    for (const [a, b, c] of f) {
      const u = t[b].map((x, k) => x - t[a][k]), w = t[c].map((x, k) => x - t[a][k]);
      const ny = u[2] * w[0] - u[0] * w[2], n = Math.hypot(u[1] * w[2] - u[2] * w[1], ny, u[0] * w[1] - u[1] * w[0]);
      if (n === 0 || ny >= 0) continue;
      items.push({depth: (t[a][1] + t[b][1] + t[c][1]) / 3, face: [a, b, c], light: -ny / n});
    }
    for (const m of data.arrows) {
      const tail = turn(m.tail), tip = turn(m.tip);
      items.push({depth: (tail[1] + tip[1]) / 2 - 1e-6, arrow: m, tail, tip});
    }
    items.sort((p, q) => q.depth - p.depth);
    g.clearRect(0, 0, canvas.width, canvas.height);
    g.lineJoin = "round";
    for (const it of items) {
      if (it.face) {
        const shade = Math.round(110 + 130 * it.light);
        g.fillStyle = g.strokeStyle = `rgb(${shade},${shade},${shade + 6})`;
        g.globalAlpha = data.opacity;
        g.beginPath();
        it.face.forEach((k, i) => { const p = screen(t[k]); i ? g.lineTo(...p) : g.moveTo(...p); });
        g.closePath(); g.fill();
        if (data.opacity === 1) g.stroke();
        g.globalAlpha = 1;
        continue;
      }
      const a = screen(it.tail), b = screen(it.tip), dx = b[0] - a[0], dy = b[1] - a[1];
      const len = Math.hypot(dx, dy) || 1, ux = dx / len, uy = dy / len;
      g.strokeStyle = g.fillStyle = it.arrow.colour; g.lineWidth = 2.5;
      g.beginPath(); g.moveTo(...a); g.lineTo(...b); g.stroke();
      g.beginPath(); g.moveTo(...b);
      g.lineTo(b[0] - 9 * ux - 4 * uy, b[1] - 9 * uy + 4 * ux);
      g.lineTo(b[0] - 9 * ux + 4 * uy, b[1] - 9 * uy - 4 * ux);
      g.closePath(); g.fill();
      if (it.arrow.label) labels.push({text: it.arrow.label, at: screen(turn(it.arrow.anchor)), colour: it.arrow.colour});
    }
    const c = screen(turn(data.cog));
    g.fillStyle = "#000"; g.beginPath(); g.arc(c[0], c[1], 5, 0, 2 * Math.PI); g.fill();
    labels.push({text: "CoG", at: c, colour: "#000"});
    place(labels);
  }
  // Labels last, each at the first of eight spots around its anchor that overlaps no label placed before it
  // (the nearest spot when all do), with a white halo: numbers stay apart and legible as the body turns.
  function place(labels) {
    const boxes = [], h = 13;
    g.font = "bold 13px sans-serif"; g.lineWidth = 3; g.strokeStyle = "#fff";
    for (const l of labels) {
      const w = g.measureText(l.text).width, [x, y] = l.at;
      const spots = [[6, -6], [6, h + 6], [-w - 6, -6], [-w - 6, h + 6], [-w / 2, -h - 4], [-w / 2, h + 14],
                     [12, 4], [-w - 12, 4]].map(([dx, dy]) => [x + dx, y + dy]);
      const free = spots.find(([sx, sy]) => !boxes.some(([bx, by, bw]) =>
        sx < bx + bw + 2 && bx < sx + w + 2 && sy - h < by + 2 && by - h < sy + 2)) || spots[0];
      boxes.push([free[0], free[1], w]);
      g.fillStyle = l.colour; g.strokeText(l.text, ...free); g.fillText(l.text, ...free);
    }
  }
  canvas.addEventListener("pointerdown", e => {
    drag = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointerup", () => { drag = null; });
  canvas.addEventListener("pointermove", e => {
    if (!drag) return;
    yaw += (e.clientX - drag[0]) * 0.01;
    pitch = Math.max(-1.55, Math.min(1.55, pitch + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  draw();
})();
"""


def _viewer_mesh(mesh: trimesh.Trimesh) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) m and triangles (k, 3), decimated by VTK to about ``MAX_FACES`` when larger."""
    if len(mesh.faces) <= MAX_FACES:
        return mesh.vertices, mesh.faces
    import pyvista as pv

    coarse = pv.wrap(mesh).decimate(1.0 - MAX_FACES / len(mesh.faces))
    return np.asarray(coarse.points), coarse.faces.reshape(-1, 4)[:, 1:]


def _mm(x) -> list:
    """Metres to millimetres rounded to 0.1 mm, as nested lists."""
    return np.round(np.asarray(x) * 1e3, 1).tolist()


def _hex(colour: tuple[int, int, int]) -> str:
    return "#" + "".join(f"{c:02x}" for c in colour)


def viewer_html(scene: Scene) -> str:
    """The canvas, its data (the scene in mm) and its script, as an HTML fragment."""
    vertices, faces = _viewer_mesh(scene.mesh)
    items = []
    for marker, arrows in zip(scene.markers, scene.arrows):
        anchor = _mm(outer_end(marker, arrows))
        colour = _hex(COLOURS[marker.kind])
        for k, (tail, tip) in enumerate(arrows):
            label = "" if k else marker.label
            items.append({"tail": _mm(tail), "tip": _mm(tip), "colour": colour, "label": label, "anchor": anchor})
    data = {"vertices": _mm(vertices), "faces": np.asarray(faces).tolist(), "arrows": items}
    data |= {"cog": _mm(scene.cog), "arrow": scene.length * 1e3, "opacity": scene.opacity}
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    return (
        '<canvas id="view3d" width="680" height="440" aria-label="3-D view of the plan; drag to turn"></canvas>\n'
        f'<script type="application/json" id="view3d-data">{payload}</script>\n'
        f"<script>{SCRIPT}</script>"
    )
