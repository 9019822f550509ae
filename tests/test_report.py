"""The placement report: one self-contained HTML page, legible pictures, printable on A4, openable offline."""

import base64
import io
import json
import re
import shutil
import subprocess

import numpy as np
import pytest
import session_cache
from conftest import FIXTURE_MESHES, bundled
from PIL import Image
from rich.console import Console
from test_cli import cli, massline

from massline.placement.candidates import CandidateOptions
from massline.core.files import to_json
from massline.core.information import NoiseModel
from massline.core.lines import Lines
from massline.meshes.loader import load_body
from massline.placement.on_surface import plan
from massline.placement.plan_file import plan_to_dict
from massline.placement.planner import Budget
from massline.cli.output import build_report
from massline.reports.label_layout import overlap_matrix, place_labels
from massline.reports.plan_scene import scene_of
from massline.reports.viewer3d import MAX_FACES, viewer_html

A4_WIDTH_PX = 794  # 210 mm at 96 px per inch
A4_PRINTABLE_PX = 186 / 25.4 * 96  # 210 mm less the report's 12 mm page margins
BUNDLED_PLANS = {"plate": Budget(6, 3), "structure": Budget(6, 4, 2), "bracket": Budget(6, 3)}
CHROMIUM = next((shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)), None)
PROBE = """<script>
addEventListener("load", () => {
  const rights = [...document.body.querySelectorAll("*")].map(e => e.getBoundingClientRect().right);
  const canvas = document.getElementById("view3d");
  const pixels = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
  let painted = 0;
  for (let k = 3; k < pixels.length; k += 4) painted += pixels[k] > 0;
  const out = document.createElement("pre");
  out.id = "probe";
  out.textContent = JSON.stringify({
    scrollWidth: document.documentElement.scrollWidth,
    right: Math.max(...rights),
    bodyWidth: document.body.getBoundingClientRect().width,
    images: document.images.length,
    loaded: [...document.images].filter(i => i.complete && i.naturalWidth > 0).length,
    painted,
  });
  document.body.appendChild(out);
});
</script>"""


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """The report of the default plan of each bundled mesh (triaxials on the structure), by name."""
    out = {}
    for name, budget in BUNDLED_PLANS.items():
        body = bundled(name)
        found = plan(body, budget, CandidateOptions(n_samples=400), NoiseModel(0.01, 0.02))
        path = tmp_path_factory.mktemp(name) / "plan.json"
        path.write_text(to_json(plan_to_dict(found, name, "m", body.density)))
        out[name] = build_report(path, Console(quiet=True))
    return out


def overlapping_pairs(boxes: np.ndarray) -> list[tuple[int, int]]:
    """Index pairs of boxes (n, 4) that share area."""
    i, j = np.nonzero(np.triu(overlap_matrix(boxes, boxes), k=1))
    return list(zip(i.tolist(), j.tolist()))


def pictures(html: str) -> list[np.ndarray]:
    """Every embedded image, decoded (it must be a PNG), as RGB."""
    found = re.findall(r'src="data:image/png;base64,([A-Za-z0-9+/=]+)"', html)
    images = []
    for data in found:
        image = Image.open(io.BytesIO(base64.b64decode(data)))
        assert image.format == "PNG"
        images.append(np.asarray(image.convert("RGB")))
    return images


@pytest.mark.slow
@pytest.mark.parametrize("name", BUNDLED_PLANS)
def test_report_is_one_self_contained_page(reports, name):
    html = reports[name].html
    assert html.startswith("<!DOCTYPE html>") and html.count("<html") == 1
    assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", html), "nothing is fetched from a network"
    assert "http://" not in html and "https://" not in html and "<link" not in html
    assert "@page { size: A4" in html and "max-width: 100%" in html
    assert not re.search(r"<script[^>]*\ssrc=", html)
    for words in ("Predicted accuracy", "certified D-efficiency", "Massline band", "recommended: cord", "kg·m²"):
        assert words in html


@pytest.mark.slow
@pytest.mark.parametrize("name", BUNDLED_PLANS)
def test_pictures_are_pngs_showing_the_body(reports, name):
    images = pictures(reports[name].html)
    assert len(images) == len(reports[name].renderings) == 4
    for image in images:
        assert image.std() > 20, "a rendering is blank"
        grey = (np.ptp(image, axis=2) < 12) & (image.mean(axis=2) > 90) & (image.mean(axis=2) < 235)
        assert grey.mean() > 0.01, "the body's grey surface is missing"
        blue = (image[..., 2] > 140) & (image[..., 0] < 90)
        assert blue.sum() > 50, "no accelerometer arrow is drawn"


def assert_legible(rendering) -> set:
    """Labels apart and inside the picture, every arrow tip inside it, a label for each visible marker and
    the CoG; returns the markers it shows."""
    h, w = rendering.image.shape[:2]
    boxes = np.array([label.box for label in rendering.labels])
    assert overlapping_pairs(boxes) == [], rendering.view.name
    assert (boxes[:, :2] >= 0).all() and (boxes[:, 2] <= w).all() and (boxes[:, 3] <= h).all()
    assert ((rendering.tips >= 0) & (rendering.tips <= (w, h))).all(), rendering.view.name
    assert {label.text for label in rendering.labels} == {*rendering.visible, "CoG"}
    return set(rendering.visible)


@pytest.mark.slow
@pytest.mark.parametrize("name", BUNDLED_PLANS)
def test_labels_do_not_overlap_and_arrows_are_in_the_pictures(reports, name):
    seen = set()
    for rendering in reports[name].renderings:
        assert len(rendering.tips), rendering.view.name
        seen |= assert_legible(rendering)
    html = reports[name].html
    everyone = set(re.findall(r'<span class="(?:sensor|hit)">(\d+)</span>', html))
    assert everyone and seen == everyone, "every accelerometer and hit is seen in some view"


@pytest.mark.slow
def test_a_triaxial_accelerometer_is_one_number_with_three_arrows(reports):
    html = reports["structure"].html
    assert html.count("triaxial: ") == 2
    data = json.loads(re.search(r'id="view3d-data">(.*?)</script>', html).group(1))
    assert len(data["arrows"]) == 6 + 2 * 3 + 4
    assert sum(bool(a["label"]) for a in data["arrows"]) == 6 + 2 + 4


def test_label_layout_separates_a_crowd():
    rng = np.random.default_rng(1)
    anchors = 300 + rng.normal(scale=25, size=(14, 2))
    boxes, leader = place_labels(anchors, np.tile([46, 32], (14, 1)), (800, 600), keep_clear=anchors)
    assert overlapping_pairs(boxes) == []
    assert (boxes[:, :2] >= 0).all() and (boxes[:, 2:] <= (800, 600)).all()
    assert leader.any()


def test_the_3d_view_of_a_large_cad_mesh_is_decimated():
    body = load_body(FIXTURE_MESHES / "ADIS16480.STL", "m", 2700)
    assert len(body.mesh.faces) > MAX_FACES
    points = body.mesh.vertices[[0, 100, 2000]]
    scene = scene_of(body.mesh, Lines(points, np.eye(3)), Lines(points[:1], np.eye(3)[:1]), body.nominal.cog)
    data = json.loads(re.search(r'id="view3d-data">(.*?)</script>', viewer_html(scene)).group(1))
    assert 0.8 * MAX_FACES <= len(data["faces"]) <= MAX_FACES
    assert np.max(data["faces"]) < len(data["vertices"]) and len(data["arrows"]) == 4


def chromium(*args, timeout=90):
    return subprocess.run(
        [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *map(str, args)],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


@pytest.mark.slow
@pytest.mark.skipif(CHROMIUM is None, reason="headless Chromium is absent (.ci/run installs Debian's chromium as root)")
@pytest.mark.parametrize("name", BUNDLED_PLANS)
def test_report_opens_in_headless_chromium_at_a4_width(reports, tmp_path, name):
    assert_a4_page(reports[name].html, tmp_path, images=4)


def assert_a4_page(html: str, tmp_path, images: int) -> None:
    """Headless Chromium at A4 width: a screenshot that is not blank, every image loaded, nothing cut
    off, the page within A4's print margins, the 3-D view drawn, and A4 pages when printed."""
    page = tmp_path / "report.html"
    page.write_text(html.replace("</body>", PROBE + "</body>"))
    shot = tmp_path / "shot.png"
    chromium(f"--window-size={A4_WIDTH_PX},1123", f"--screenshot={shot}", page.as_uri())
    image = np.asarray(Image.open(shot).convert("RGB"))
    assert image.shape[:2] == (1123, A4_WIDTH_PX) and image.std() > 20, "the screenshot is blank"
    dom = chromium(
        f"--window-size={A4_WIDTH_PX},1123", "--virtual-time-budget=5000", "--dump-dom", page.as_uri()
    ).stdout
    probe = json.loads(re.search(r'<pre id="probe">(.*?)</pre>', dom).group(1))
    assert probe["images"] == images and probe["loaded"] == images, "every image loaded"
    assert probe["scrollWidth"] <= A4_WIDTH_PX and probe["right"] <= A4_WIDTH_PX, "nothing is cut off at A4 width"
    assert probe["bodyWidth"] <= A4_PRINTABLE_PX + 0.5, "the page fits A4 within its print margins"
    assert probe["painted"] > 10_000, "the 3-D view drew the body"
    pdf = tmp_path / "report.pdf"
    chromium("--no-pdf-header-footer", f"--print-to-pdf={pdf}", page.as_uri())
    boxes = re.findall(rb"/MediaBox \[0 0 ([\d.]+) ([\d.]+)\]", pdf.read_bytes())
    assert boxes and all(abs(float(w) - 595) < 1 and abs(float(h) - 842) < 1 for w, h in boxes), "A4 pages"


@pytest.mark.slow
def test_plan_writes_the_report_and_report_rebuilds_it(tmp_path):
    planned = session_cache.command("plan", "plate") / "out"  # the session's plate plan, copied to be written over
    assert (planned / "report.html").stat().st_size > 20_000
    for name in ("plan.json", "report.html"):
        shutil.copy(planned / name, tmp_path / name)
    again = massline("report", tmp_path / "plan.json")
    assert again.returncode == 2 and "--force" in again.stderr and len(again.stderr.strip().splitlines()) == 1
    other = tmp_path / "other.html"
    assert massline("report", tmp_path / "plan.json", "--out", other).returncode == 0
    assert other.read_text().count("data:image/png;base64,") == 4
    assert massline("report", tmp_path / "plan.json", "--force").returncode == 0


@pytest.mark.parametrize(
    "content,words", [(None, "does not exist"), ("{", "not valid JSON"), ('{"sensors": []}', "no sensors")]
)
def test_bad_plan_file_is_one_line_and_exit_2(tmp_path, content, words):
    path = tmp_path / "plan.json"
    if content is not None:
        path.write_text(content)
    run = cli("report", path)
    assert run.returncode == 2 and words in run.stderr
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr
    assert not (tmp_path / "report.html").exists()
