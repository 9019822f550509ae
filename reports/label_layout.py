"""Where the numbers go on a picture: label boxes that keep clear of one another.

Pure geometry in pixel coordinates of one image: x to the right, y down, origin
at the top-left corner; a box is ``(x0, y0, x1, y1)`` with x0 < x1, y0 < y1.
"""

from __future__ import annotations

import numpy as np

GAP = 3.0  # px kept between a box and its anchor, and between two boxes
RINGS = (0.0, 0.6, 1.3, 2.2, 3.3, 4.6, 6.2, 8.0)  # distances from the anchor tried, in label heights
ANGLES = np.deg2rad(np.arange(45.0, 405.0, 22.5))  # first up-right, then anticlockwise
COVER_PENALTY = 2.5  # cost, in label heights, of covering something that should stay seen
LEADER_AFTER = 0.9  # a box this many label heights away from its anchor gets a leader line


def overlap_matrix(a: np.ndarray, b: np.ndarray, gap: float = 0.0) -> np.ndarray:
    """(n, m) bool: box a[i] and box b[j] (each (·, 4)), grown by ``gap`` / 2 px each, share area."""
    a, b = np.asarray(a, dtype=float).reshape(-1, 1, 4), np.asarray(b, dtype=float).reshape(1, -1, 4)
    return (
        (a[..., 0] < b[..., 2] + gap)
        & (b[..., 0] < a[..., 2] + gap)
        & (a[..., 1] < b[..., 3] + gap)
        & (b[..., 1] < a[..., 3] + gap)
    )


def covered(boxes: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(n,) int: how many of ``points`` (k, 2) px fall inside each of ``boxes`` (n, 4)."""
    b, p = np.asarray(boxes, dtype=float).reshape(-1, 1, 4), np.asarray(points, dtype=float).reshape(1, -1, 2)
    inside = (p[..., 0] >= b[..., 0]) & (p[..., 0] <= b[..., 2]) & (p[..., 1] >= b[..., 1]) & (p[..., 1] <= b[..., 3])
    return inside.sum(axis=1)


def _candidates(anchor: np.ndarray, size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Boxes (c, 4) around the anchor, nearest first, and each one's distance from it in label heights.

    In direction θ the box's centre moves out until the box, grown by the ring's
    distance, just clears the anchor.
    """
    w, h = size
    c, s = np.cos(ANGLES), np.sin(ANGLES)
    boxes, rings = [], []
    for ring in RINGS:
        r = GAP + ring * h
        with np.errstate(divide="ignore"):
            t = np.minimum((w / 2 + r) / np.abs(c), (h / 2 + r) / np.abs(s))
        cx, cy = anchor[0] + t * c, anchor[1] - t * s
        boxes.append(np.column_stack([cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2]))
        rings.append(np.full(len(ANGLES), ring))
    return np.concatenate(boxes), np.concatenate(rings)


def _clamped(box: np.ndarray, image_size: tuple[int, int]) -> np.ndarray:
    """The box shifted into the image (as far as it fits)."""
    shift = np.maximum(-box[:2], 0) - np.maximum(box[2:] - np.asarray(image_size, dtype=float), 0)
    return box + np.tile(shift, 2)


def place_labels(
    anchors: np.ndarray, sizes: np.ndarray, image_size: tuple[int, int], keep_clear: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Boxes for labels of the given sizes, each near its anchor, none overlapping another.

    Labels are placed one after the other, the most crowded first; each takes the
    nearest free spot on rings around its anchor, preferring spots that do not
    cover ``keep_clear`` points (arrows, mounting points, other anchors). A box
    never leaves the image. Only when every spot is taken does a box overlap
    another, the least it can.

    Parameters
    ----------
    anchors : (n, 2) array
        The point each label names, px.
    sizes : (n, 2) array
        Width and height of each label, px.
    image_size : (width, height)
        The picture, px.
    keep_clear : (k, 2) array, optional
        Points that labels should not hide, px.

    Returns
    -------
    boxes : (n, 4) array
        ``(x0, y0, x1, y1)`` of each label, px.
    leader : (n,) bool array
        True where the box sits far enough from its anchor to need a leader line.
    """
    anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
    sizes = np.asarray(sizes, dtype=float).reshape(-1, 2)
    clear = np.zeros((0, 2)) if keep_clear is None else np.asarray(keep_clear, dtype=float).reshape(-1, 2)
    n = len(anchors)
    boxes = np.zeros((n, 4))
    leader = np.zeros(n, dtype=bool)
    scale = sizes[:, 1].max() if n else 1.0
    crowding = [(np.linalg.norm(anchors - a, axis=1) < 4 * scale).sum() for a in anchors]
    placed: list[int] = []
    for i in sorted(range(n), key=lambda k: (-crowding[k], k)):
        others = np.delete(anchors, i, axis=0)
        candidates, rings = _candidates(anchors[i], sizes[i])
        inside = (
            (candidates[:, 0] >= 0)
            & (candidates[:, 1] >= 0)
            & (candidates[:, 2] <= image_size[0])
            & (candidates[:, 3] <= image_size[1])
        )
        costs = rings + COVER_PENALTY * (covered(candidates, clear) + covered(candidates, others))
        costs += 1000.0 * overlap_matrix(candidates, boxes[placed], GAP).sum(axis=1)
        costs[~inside] = np.inf
        k = int(np.argmin(costs))
        boxes[i] = candidates[k] if np.isfinite(costs[k]) else _clamped(candidates[0], image_size)
        leader[i] = rings[k] >= LEADER_AFTER
        placed.append(i)
    return boxes, leader
