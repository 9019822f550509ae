"""massline.virtual — the virtual test: the suspended body, its instrumentation and its recordings, simulated.

The body's elastic modes come from a finite-element model of the solid
(:mod:`.elastic`, meshed by :mod:`.tetmesh`); the suspension, sensor masses and
instrumentation effects (objects of the registry, :mod:`massline.identify.diagnose.effects`,
handed in by the caller) are added on top, and :mod:`.measurement` turns the
result into the FRFs a test system would record (:mod:`.virtual_test` runs one test,
:mod:`.scenarios` the blind ones); :mod:`.band` predicts the massline band before the test,
and :mod:`.analyser` sets an impact test up around it as a test engineer would.
"""

from massline.virtual.elastic import ElasticBody, Material
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Cord, Foam, Suspension
from massline.virtual.acquisition import Acquisition, run

__all__ = ["Acquisition", "Cord", "ElasticBody", "Foam", "Material", "Suspension", "SuspendedBody", "run"]
