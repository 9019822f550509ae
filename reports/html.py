"""The pieces every report page is made of: its look, escaped text, numbers, tables, pictures, the page.

Pages are self-contained: pictures are embedded as base64 PNG and nothing is fetched from a network;
they print on A4 (``STYLE``).
"""

from __future__ import annotations

import base64
import html
import io
import re
from dataclasses import dataclass

import numpy as np
from PIL import Image

from massline.core.numbers import formatted, number, value_with_sigma
from massline.reports.plan_scene import Marker
from massline.reports.rendering import Rendering

STYLE = """
@page { size: A4; margin: 12mm; }
* { box-sizing: border-box; }
body { font: 10pt/1.35 "DejaVu Sans", Arial, sans-serif; color: #222; max-width: 186mm; margin: 0 auto; padding: 6px; }
h1 { font-size: 16pt; margin: 0 0 2mm; } h2 { font-size: 12pt; margin: 5mm 0 2mm; border-bottom: 1px solid #999; }
table { border-collapse: collapse; width: 100%; table-layout: fixed; font-size: 8.5pt; margin-bottom: 2mm; }
th, td { padding: 1.5px 4px; border-bottom: 1px solid #ddd; text-align: right; overflow-wrap: anywhere; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
img, canvas { max-width: 100%; height: auto; display: block; }
.views { display: grid; grid-template-columns: 1fr 1fr; gap: 3mm; }
figure { margin: 0; break-inside: avoid; } figcaption { font-size: 8.5pt; color: #444; }
.sensor { color: #1f5fb4; font-weight: bold; } .hit { color: #c8281e; font-weight: bold; } .added { color: #9628aa; font-weight: bold; }
.note { font-size: 8.5pt; color: #444; } .warnings { border-left: 3px solid #c60; padding-left: 8px; } section { break-inside: avoid; }
canvas { border: 1px solid #ccc; cursor: grab; touch-action: none; }
@media print { .screen { display: none; } body { padding: 0; } }
"""


@dataclass(frozen=True, eq=False)
class Report:
    """A page and the pictures in it (their label boxes and arrow tips, for checks)."""

    html: str
    renderings: list[Rendering]


def png_data_uri(image: np.ndarray) -> str:
    """An RGB picture (h, w, 3) as a data: URI of a palette PNG (256 colours)."""
    buffer = io.BytesIO()
    Image.fromarray(image).quantize(256, method=Image.Quantize.MEDIANCUT).save(buffer, "PNG", optimize=True)
    return "data:image/png;base64," + base64.b64encode(buffer.getvalue()).decode("ascii")


def escape(text) -> str:
    """Text escaped for HTML, a command or option quoted in backticks (`simulate --check`) set as code."""
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", html.escape(str(text)))


def num(value, fmt: str = ".4g") -> str:
    """A number for a table, with a true minus sign and never "−0"; '—' for a missing one."""
    return "—" if value is None or not np.isfinite(value) else formatted(value, fmt)


def html_table(head: list[str] | None, rows: list[list[str]], align: str, widths: list[int]) -> str:
    """An HTML table: ``align`` has one letter per column ('l' left, 'r' right), ``widths`` in % of the table."""
    cls = [' class="l"' if a == "l" else "" for a in align]
    cols = "".join(f'<col style="width:{w}%">' for w in widths)
    th = "<thead><tr>" + "".join(f"<th{c}>{h}</th>" for c, h in zip(cls, head)) + "</tr></thead>" if head else ""
    body = "".join("<tr>" + "".join(f"<td{c}>{v}</td>" for c, v in zip(cls, r)) + "</tr>" for r in rows)
    return f"<table><colgroup>{cols}</colgroup>{th}<tbody>{body}</tbody></table>"


def rendering_figure(rendering: Rendering, markers: list[Marker]) -> str:
    """One view as a figure: the embedded picture, its name and the markers it hides."""
    hidden = [m.label for m in markers if m.label not in rendering.visible]
    note = f"; hidden: {', '.join(hidden)}" if hidden else ""
    name = escape(rendering.view.name)
    return (
        f'<figure><img src="{png_data_uri(rendering.image)}" alt="{name}" '
        f'width="{rendering.image.shape[1]}" height="{rendering.image.shape[0]}">'
        f"<figcaption>{name}{escape(note)}</figcaption></figure>"
    )


def png_uri(data: bytes) -> str:
    """PNG bytes as a data: URI."""
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def plot_figure(data: bytes, alt: str, caption: str) -> str:
    """A plot as a figure with its caption."""
    return f'<figure><img src="{png_uri(data)}" alt="{html.escape(str(alt))}"><figcaption>{caption}</figcaption></figure>'


def page(title: str, parts: list[str]) -> str:
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{escape(title)}</title><style>{STYLE}</style></head>\n<body>\n"
        + "\n".join(parts)
        + "\n</body></html>\n"
    )


def with_sigma(value: float, sigma: float | None, scale: float) -> str:
    """ "value ± σ" (both × ``scale``), the value rounded to what its σ supports; the value alone when σ is
    None or not finite; "unobservable" for a NaN value."""
    if not np.isfinite(value):
        return "unobservable"
    if sigma is None or not np.isfinite(sigma):
        return number(value * scale)
    return " ± ".join(value_with_sigma(value * scale, sigma * scale))
