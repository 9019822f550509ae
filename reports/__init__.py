"""massline.reports — what a test engineer prints: HTML pages, pictures of the test, figures.

Pages (self-contained, A4, offline): :mod:`.placement_report`, :mod:`.identification_report`,
:mod:`.diagnosis_report`, built from :mod:`.html`'s pieces. Pictures: the scene of a test
(:mod:`.plan_scene`, :mod:`.body_scene`) rendered off-screen (:mod:`.rendering`, labels placed by
:mod:`.label_layout`) and as a 3-D view to turn (:mod:`.viewer3d`). Figures as PNG bytes:
:mod:`.figures`, :mod:`.identification_figures`, :mod:`.diagnosis_figures`. Assembly: the placement report of a
plan file (:mod:`.placement_assembly`); the demo's whole story, plan to diagnosis report (:mod:`.demo_story`).

Nothing is imported here: rendering needs VTK and plotting matplotlib, loaded when a page is built.
"""

__all__ = [
    "body_scene",
    "demo_story",
    "diagnosis_figures",
    "diagnosis_report",
    "figures",
    "html",
    "identification_figures",
    "identification_report",
    "label_layout",
    "placement_assembly",
    "placement_report",
    "plan_scene",
    "rendering",
    "viewer3d",
]
