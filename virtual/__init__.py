"""massline.virtual — the virtual test: the suspended body, its instrumentation and its recordings, simulated.

The body's elastic modes come from a finite-element model of the solid
(:mod:`.elastic`, meshed by :mod:`.tetmesh`, kept between runs by :mod:`.fe_cache`); the suspension, sensor
masses and instrumentation effects (objects of the registry, :mod:`massline.identify.diagnose.effects`,
handed in by the caller) are added on top, and :mod:`.measurement` turns the
result into the FRFs a test system would record (:mod:`.acquisition` runs one test,
:mod:`.scenarios` the blind ones); :mod:`.band_prediction` predicts the massline band before the test,
and :mod:`.analyser` sets an impact test up around it as a test engineer would. Pipelines: the test a plan
sets up, its support and band (:mod:`.planned_test`), and the virtual test of a plan (:mod:`.simulation`).
"""

from massline.virtual.elastic import ElasticBody, Material
from massline.virtual.suspended import SuspendedBody
from massline.virtual.suspension import Cord, Foam, Suspension
from massline.virtual.acquisition import Acquisition, run

__all__ = ["Acquisition", "Cord", "ElasticBody", "Foam", "Material", "Suspension", "SuspendedBody", "run"]
