"""Off-screen pictures of a test plan: the body, numbered accelerometers and hammer hits, the CoG.

The scene is in the mesh's frame O xyz, in metres. pyvista (VTK) draws the body
and the arrows without a display (EGL or OSMesa); the numbers, the CoG symbol
and the leader lines are drawn on the picture afterwards, where each label's
box is known exactly and kept clear of the others (:mod:`.label_layout`).
Pictures are RGB arrays, rows top to bottom; pixel coordinates are x to the
right and y down from the top-left corner.
"""

from __future__ import annotations

import ctypes.util
import os
import sys
from dataclasses import dataclass

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from massline.core.errors import MasslineError
from massline.reports.label_layout import place_labels
from massline.reports.plan_scene import COLOURS, SENSOR, Scene, outer_end

SIZE = (800, 600)  # px of one view
FONT_PX = 26
COG_PX = 11  # radius of the CoG symbol
TRIAD = 42  # px: length of the axis triad's arms, also its distance from the corner
BODY, EDGES = (200, 203, 208), (90, 90, 90)  # RGB
RIG = (130, 80, 20)  # RGB: the support's cord and bridle legs, a dot where each is tied
FACING = 0.2  # a surface faces a view when its outward normal has this component towards the camera
AXIS_VIEWS = {  # per axis: (direction towards the camera, up, name) for + and − sides
    2: (((0, 0, 1), (0, 1, 0), "top"), ((0, 0, -1), (0, 1, 0), "bottom")),
    1: (((0, 1, 0), (0, 0, 1), "back"), ((0, -1, 0), (0, 0, 1), "front")),
    0: (((1, 0, 0), (0, 0, 1), "right"), ((-1, 0, 0), (0, 0, 1), "left")),
}
PREFERRED_SIDE = {2: 0, 1: 1, 0: 0}  # top, front, right when both sides see as many markers


@dataclass(frozen=True)
class View:
    """A parallel projection looking at the body from ``direction`` (unit, body → camera), ``up`` upwards."""

    name: str
    direction: tuple[float, float, float]
    up: tuple[float, float, float]


@dataclass(frozen=True, eq=False)
class Label:
    """A label drawn on a picture: its text, box ``(x0, y0, x1, y1)`` px, the anchor px it names."""

    text: str
    box: tuple[float, float, float, float]
    anchor: tuple[float, float]
    leader: bool


@dataclass(frozen=True, eq=False)
class Rendering:
    """One view: the RGB picture (h, w, 3), its labels, every arrow tip in px, the markers seen."""

    view: View
    image: np.ndarray
    labels: list[Label]
    tips: np.ndarray
    visible: tuple[str, ...]


def choose_views(normals: np.ndarray) -> list[View]:
    """An isometric view and one view along each axis, each from the side most markers face.

    ``normals`` (n, 3): the outward normal at each marker. Ties go to the
    isometric view from +x −y +z and to the top, front and right views.
    """
    octants = [np.array([sx, sy, sz]) for sz in (1, -1) for sx in (1, -1) for sy in (-1, 1)]
    seen = [int((normals @ (o / np.sqrt(3)) > FACING).sum()) for o in octants]
    iso = octants[int(np.argmax(seen))]
    views = [View("isometric from " + " ".join(f"{'+' if v > 0 else '−'}{a}" for v, a in zip(iso, "xyz")),
                  tuple(iso / np.sqrt(3)), (0.0, 0.0, 1.0))]  # fmt: skip
    for axis in (2, 1, 0):
        counts = [int((normals[:, axis] * (1 if side == 0 else -1) > FACING).sum()) for side in (0, 1)]
        side = PREFERRED_SIDE[axis] if counts[0] == counts[1] else int(np.argmax(counts))
        direction, up, name = AXIS_VIEWS[axis][side]
        views.append(View(f"{name} (from {'+−'[side]}{'xyz'[axis]})", direction, up))
    return views


def check_offscreen() -> None:
    """Select VTK's off-screen window when there is no display; refuse when no backend is installed.

    Without a display VTK falls back to EGL, then OSMesa, and crashes when neither
    is installed, so both are looked for first.
    """
    if sys.platform != "linux" or os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    found = {name: ctypes.util.find_library(name) for name in ("EGL", "EGL_mesa", "EGL_nvidia", "OSMesa")}
    if found["EGL"] and (found["EGL_mesa"] or found["EGL_nvidia"]):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    elif found["OSMesa"]:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkOSOpenGLRenderWindow")
    else:
        raise MasslineError(
            "no display and no off-screen OpenGL library for the report's pictures: install EGL "
            "(Debian/Ubuntu: apt-get install libegl1 libegl-mesa0) or OSMesa (libosmesa6)"
        )


def _font() -> ImageFont.FreeTypeFont:
    """The labels' font (Pillow's bundled one), ``FONT_PX`` high."""
    return ImageFont.load_default(size=FONT_PX)


def _project(renderer, points: np.ndarray, height: int) -> np.ndarray:
    """Pixel coordinates (n, 2) and depth in [0, 1] (n,) of world points (n, 3), via the renderer's camera."""
    out = np.empty((len(points), 3))
    for k, (x, y, z) in enumerate(points):
        renderer.SetWorldPoint(x, y, z, 1.0)
        renderer.WorldToDisplay()
        out[k] = renderer.GetDisplayPoint()
    out[:, 1] = height - out[:, 1]
    return out


def _frame(plotter, view: View, points: np.ndarray, margin: float = 1.18) -> tuple[np.ndarray, np.ndarray]:
    """Point the camera along ``view``, fit ``points`` (n, 3) with a margin for labels; the screen's right and up."""
    direction, up = np.array(view.direction, dtype=float), np.array(view.up, dtype=float)
    up = up - (up @ direction) * direction
    up /= np.linalg.norm(up)
    right = np.cross(up, direction)
    u, v = points @ right, points @ up
    centre = right * (u.max() + u.min()) / 2 + up * (v.max() + v.min()) / 2
    centre += direction * (points @ direction).mean()
    span = np.ptp(points @ direction) + 1.0
    plotter.camera_position = [tuple(centre + direction * span * 4), tuple(centre), tuple(up)]
    plotter.camera.parallel_scale = margin * max(np.ptp(v) / 2, np.ptp(u) / 2 / (SIZE[0] / SIZE[1]))
    plotter.renderer.ResetCameraClippingRange()
    return right, up


def _distances(plotter) -> np.ndarray:
    """Distance (h, w) from the camera plane to the nearest surface at each pixel, m (inf on the background)."""
    return -np.asarray(plotter.get_image_depth(fill_value=-np.inf, reset_camera_clipping_range=False))


def _seen(plotter, distances: np.ndarray, projected: np.ndarray, tolerance: float) -> np.ndarray:
    """True where a projected point (n, 3: px, px, depth in [0, 1]) is not hidden behind a surface."""
    h, w = distances.shape
    near, far = plotter.camera.clipping_range
    x = np.clip(projected[:, 0].astype(int), 1, w - 2)
    y = np.clip(projected[:, 1].astype(int), 1, h - 2)
    window = np.stack([distances[y + dy, x + dx] for dy in (-1, 0, 1) for dx in (-1, 0, 1)])
    return window.max(axis=0) >= near + projected[:, 2] * (far - near) - tolerance


def _draw_cog(draw: ImageDraw.ImageDraw, x: float, y: float) -> None:
    """The centre-of-gravity symbol: a disc with two black quadrants, ``COG_PX`` in radius."""
    box = (x - COG_PX, y - COG_PX, x + COG_PX, y + COG_PX)
    draw.ellipse(box, fill="white", outline="black", width=2)
    draw.pieslice(box, 180, 270, fill="black")
    draw.pieslice(box, 0, 90, fill="black")


def _draw_triad(draw: ImageDraw.ImageDraw, right: np.ndarray, up: np.ndarray, font) -> None:
    """The x, y, z axes as seen, in the bottom-left corner; an axis pointing at the viewer is a dot."""
    origin = np.array([TRIAD, SIZE[1] - TRIAD])
    for k in range(3):
        tip = origin + 0.8 * TRIAD * np.array([right[k], -up[k]])
        draw.line((*origin, *tip), fill=EDGES, width=3)
        if np.hypot(right[k], up[k]) < 0.2:
            draw.ellipse((*(tip - 4), *(tip + 4)), outline=EDGES, width=2)
        letter = tip + 0.25 * TRIAD * np.array([right[k], -up[k]]) + (6, 0)
        draw.text(tuple(letter), "xyz"[k], fill="black", font=font, anchor="mm")


def _draw_rig(draw: ImageDraw.ImageDraw, segments: np.ndarray) -> None:
    """The support's cord and bridle legs (k, 2, 2) px, drawn over the body (a leg behind it shows too), a dot
    where each is tied."""
    for a, b in segments:
        draw.line((*a, *b), fill=RIG, width=3)
    for a, _ in segments[:-1]:  # the last segment is the cord above the apex
        draw.ellipse((*(a - 5), *(a + 5)), fill=RIG)


def _annotate(
    image: np.ndarray, labels: list[Label], colours: list[tuple], cog: np.ndarray, right, up, rig=np.zeros((0, 2, 2))
) -> np.ndarray:
    """Draw the rig, the CoG symbol, the axis triad and the labels (with leader lines) on the picture."""
    picture = Image.fromarray(image)
    draw = ImageDraw.Draw(picture)
    _draw_rig(draw, rig)
    _draw_cog(draw, *cog)
    font = _font()
    _draw_triad(draw, right, up, ImageFont.load_default(size=FONT_PX - 6))
    for label, colour in zip(labels, colours):
        x0, y0, x1, y1 = label.box
        if label.leader:
            cx, cy = np.clip(label.anchor, (x0, y0), (x1, y1))
            draw.line((*label.anchor, cx, cy), fill=colour, width=2)
        draw.rectangle(label.box, fill="white", outline=colour, width=2)
        draw.text(((x0 + x1) / 2, (y0 + y1) / 2), label.text, fill=colour, font=font, anchor="mm")
    return np.asarray(picture)


def render_views(scene: Scene) -> list[Rendering]:
    """The scene from an isometric and three axis views (:func:`choose_views`), labelled, ``SIZE`` px each."""
    check_offscreen()
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    plotter.set_background("white")
    body = pv.wrap(scene.mesh)
    plotter.add_mesh(body, color=BODY, smooth_shading=False, ambient=0.25, opacity=scene.opacity)
    edges = body.extract_feature_edges(30.0)
    if edges.n_points:  # a part rounded all over (a filleted box) has none
        plotter.add_mesh(edges, color=EDGES, line_width=1.5)
    for kind in COLOURS:
        glyphs = [
            pv.Arrow(
                start=tail, direction=tip - tail, tip_length=0.3, tip_radius=0.09, shaft_radius=0.035, scale="auto"
            )
            for m, a in zip(scene.markers, scene.arrows)
            if m.kind == kind
            for tail, tip in a
        ]
        cube = 0.12 * scene.length
        glyphs += [
            pv.Cube(center=m.point, x_length=cube, y_length=cube, z_length=cube)
            for m in scene.markers
            if m.kind == kind == SENSOR
        ]
        if glyphs:
            plotter.add_mesh(pv.merge(glyphs), color=COLOURS[kind], smooth_shading=True)
    plotter.enable_parallel_projection()
    plotter.enable_anti_aliasing("ssaa")
    plotter.show(auto_close=False)  # the first render; later ones keep the cameras set here
    points = np.vstack([scene.mesh.vertices, *[a.reshape(-1, 3) for a in scene.arrows], scene.rig.reshape(-1, 3)])
    try:
        return [_render(plotter, view, scene, points) for view in choose_views(scene.normals)]
    finally:
        plotter.close()


def _render(plotter, view: View, scene: Scene, points: np.ndarray) -> Rendering:
    """One labelled picture: frame the view, render, find the markers seen, place and draw the labels."""
    right, up = _frame(plotter, view, points)
    plotter.render()
    image = np.asarray(plotter.screenshot(return_img=True))[:, :, :3]

    def project(points: np.ndarray) -> np.ndarray:
        return _project(plotter.renderer, np.asarray(points).reshape(-1, 3), image.shape[0])

    samples = np.linspace(0.0, 1.0, 6)[:, None, None]
    along = [project(a[:, 0] + samples * (a[:, 1] - a[:, 0])) for a in scene.arrows]
    distances = _distances(plotter)
    seen = [bool(_seen(plotter, distances, pts, 0.05 * scene.length).any()) for pts in along]
    shown = [i for i, s in enumerate(seen) if s]
    cog = project(scene.cog)[0, :2]
    font = _font()
    texts = [scene.markers[i].label for i in shown] + ["CoG"]
    sizes = np.array([np.array(font.getbbox(t, anchor="lt")[2:]) + (14, 10) for t in texts])
    anchors = [project(outer_end(scene.markers[i], scene.arrows[i]))[0, :2] for i in shown] + [cog]
    corner = np.stack(np.meshgrid(np.linspace(0, 2 * TRIAD, 5), SIZE[1] - np.linspace(0, 2 * TRIAD, 5)), -1)
    cog_disc = cog + np.array([[0, 0], [-COG_PX, -COG_PX], [COG_PX, COG_PX]])
    rig_line = project((scene.rig[:, :1] + samples.reshape(1, -1, 1) * np.diff(scene.rig, axis=1)).reshape(-1, 3))
    keep_clear = np.vstack([a[:, :2] for a in along] + [cog_disc, corner.reshape(-1, 2), rig_line[:, :2]])
    boxes, leader = place_labels(np.array(anchors), sizes, SIZE, keep_clear)
    labels = [Label(t, tuple(b), tuple(a), bool(ld)) for t, b, a, ld in zip(texts, boxes, anchors, leader)]
    colours = [COLOURS[scene.markers[i].kind] for i in shown] + [(0, 0, 0)]
    rig = project(scene.rig.reshape(-1, 3))[:, :2].reshape(-1, 2, 2)
    image = _annotate(image, labels, colours, cog, right, up, rig)
    tips = project(np.vstack([a[:, 1] for a in scene.arrows]))[:, :2]
    return Rendering(view, image, labels, tips, tuple(scene.markers[i].label for i in shown))
