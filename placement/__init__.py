"""massline.placement — the pre-test planner: where the accelerometers and hammer hits go.

Stands on :mod:`massline.core` (lines, rigid-body algebra, information) and :mod:`massline.meshes`
(the surface). Modules:

- the surface: :mod:`.mountable` (flat patches, edges), :mod:`.candidates` (points and lines a
  technician can use), :mod:`.sliding` (off the grid, on the patches);
- the search: :mod:`.selection` (greedy, swaps), :mod:`.relaxation` (the convex relaxation),
  :mod:`.criteria`, :mod:`.admissible` (never a singular layout), :mod:`.planner`, :mod:`.on_surface`;
- the certificate: :mod:`.certificate`, :mod:`.cell_bound`, :mod:`.certification`,
  :mod:`.criterion_relaxation`;
- the plan: :mod:`.plans` (budget, plan and its assessment), :mod:`.diagnosability`,
  :mod:`.diagnosable_plan` (the default plan), :mod:`.plan_file` (plan.json), :mod:`.hand_layouts`.
"""
