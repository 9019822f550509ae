"""massline: plan and evaluate the modal test that identifies a body's mass, CoG and inertia tensor.

The package is the test's data flow, one sub-package per stage; each imports only the ones below it
(the README's "Layout"):

- ``massline`` (this folder, ``cli/``): the command ``massline`` — argument parsing, console
  output, exit codes; no science.
- :mod:`massline.reports`: HTML pages, scenes, renderings and figures.
- :mod:`massline.identify`: recordings → masslines → properties; :mod:`massline.identify.diagnose`,
  the mismatch diagnosis.
- :mod:`massline.virtual`: the virtual test (FE modes, suspension, instrumentation, measurement).
- :mod:`massline.uff`: Universal Files read and written, and the ``Recording`` type.
- :mod:`massline.placement`: the pre-test planner.
- :mod:`massline.core`: the kernel — lines, rigid-body algebra, the paper's methods, properties, errors;
  it imports nothing else of the project.
- :mod:`massline.meshes`: the bundled bodies and the mesh loader.
"""

from massline.core import __version__

__all__ = ["__version__"]
