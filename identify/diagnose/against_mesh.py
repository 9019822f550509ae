"""The body after weighed against the mesh's: a mass loading the masslines alone cannot show.

The fourth stage of :func:`.pipeline.diagnose_recording`, a rule beside the model-selection loop
(:mod:`.selection`): a mass riding at every housing or every drive point moves every massline as a heavier body
would, so no candidate on the lines or on identify's χ² can see it; only the mesh's body can. When identify's
body after fits the masslines within chance, its excess over the mesh's is weighed (:mod:`.mass_loading`): at the
housings it is taken off the properties after; at the drive points it is undone by identify (``exciter_mass``)
and proven as every fault is; with its effect out of the registry it is reported ``unexplained``.
"""

from __future__ import annotations

from massline.identify.diagnose.diagnosis import Diagnosis
from massline.identify.diagnose.effects import held
from massline.identify.diagnose.finding import faults_first
from massline.identify.diagnose.gauge_mass import gauge_pattern
from massline.identify.diagnose.mass_loading import MassLoading, mass_loading, weighed
from massline.identify.diagnose.selection import Proven, Prover, Selection
from massline.identify.diagnose.unexplained import excess_over_mesh
from massline.identify.pipeline import Identification
from massline.identify.suspicions import beyond_chance
from massline.core.errors import MasslineError
from massline.core.rigid_body import RigidBody


def weighed_against_mesh(chosen: Selection, prove: Prover, result: Diagnosis, nominal: RigidBody | None,
                         transverse: float) -> tuple[Proven, MassLoading | None]:  # fmt: skip
    """The proof with the mass loading the mesh shows: at the drive points undone by identify and proven, at the
    housings among the findings (and returned, to be taken off the body after), its effect out of the registry
    ``unexplained``; ``chosen``'s proof as it is where the body cannot be weighed or shows no loading."""
    after = chosen.proven.after
    loading = weighed_loading(after, result, nominal, transverse) if measures_a_body(after, nominal) else None
    if loading is None:
        return chosen.proven, None
    if not held(loading.finding().effect):
        return outside_the_registry(chosen, prove, loading), None
    if loading.side == "excitation":  # undone by identify, column by column
        proven = prove(chosen.found + [loading.finding()], chosen.set_aside)
        return proven._replace(findings=faults_first(proven.findings)), None
    return chosen.proven._replace(findings=faults_first(chosen.proven.findings + [loading.finding()])), loading


def outside_the_registry(chosen: Selection, prove: Prover, loading: MassLoading) -> Proven:
    """The mesh's excess reported ``unexplained`` where its effect is not in the registry, located before any hit's
    fault that absorbs part of it (those withdrawn, the rest proven again)."""
    proven = chosen.proven
    stand_ins = [f for f in chosen.found if f.kind == "fault" and f.exciter is not None]
    if loading.side == "excitation" and stand_ins:
        proven = prove([f for f in chosen.found if f not in stand_ins], chosen.set_aside)
        proven = proven._replace(withdrawn=proven.withdrawn + stand_ins)
    return proven._replace(left=excess_over_mesh(loading, proven.withdrawn))


def measures_a_body(after: Identification | None, nominal: RigidBody | None) -> bool:
    """Whether identify's body after can be weighed against the mesh's: a mesh was given and the rigid model fits
    the masslines within chance. Beyond it the body is the misfit's (an 8 mm sensor offset left χ² 150× the
    noise and a body 3 % heavy, which the mesh would have called a gauge's mass at the drive points)."""
    return nominal is not None and after is not None and not beyond_chance(after.best.chi2, after.best.dof)


def weighed_loading(after: Identification, result: Diagnosis, nominal: RigidBody, transverse: float):
    """The mass loading θ̂ − θ_mesh shows: at the housings, or (when identify fitted no gauge) at the drive points
    (not when the body with gauges riding there fits no rigid body: the estimate diverged)."""
    excitation = None
    if not after.exciter_mass and len(after.recording.exciters) > 1:
        try:
            pattern = gauge_pattern(after.data, after.sigma, after.planar, transverse, after.best)  # a difference
            excitation = (after.recording.exciters.points, pattern)
        except MasslineError:  # no rigid body fits with gauges riding: the drive points cannot be weighed
            excitation = None
    theta, covariance, planar = weighed(after.best, result.after)
    bare = theta - after.housings.theta(planar)  # the housings the engineer gave are no loading
    return mass_loading(bare, covariance, planar, after.recording.sensors, nominal, excitation)
