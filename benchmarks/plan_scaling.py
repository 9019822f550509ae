"""Planner scaling: time, memory and certified gap at 1e3, 1e4 and 1e5 candidate lines.

    python benchmarks/plan_scaling.py [--sizes 1000 10000 100000] [--cvxpy-seconds 300] [--certify-steps 2500]
    python benchmarks/plan_scaling.py --certificate [--repeat 3]   (1e5 lines, minimal budget)

For each size, candidate lines are sampled on the bundled 3-D structure (surface
normals) and the minimal layout (6 sensors × 3 exciters) is planned end to end:
working-set search, exchanges on every candidate, full-set relaxation, certificate.
The baseline is cvxpy's generic conic solve (`log_det` through SCS, the one conic solver that did not fail
at scale in our notes) of the same relaxation — the sensor selection at the
planned exciters — beside our first-order solve of it, with the ratio of times and
both certified bounds (re-evaluated at the returned weights, so both are valid).
SCS is stopped after --cvxpy-seconds; a stopped run prints its time with '>'.
Memory is the tracemalloc peak of a second, untimed run.

--certificate prints, for 1e5 lines and the minimal budget (6 sensors × 3 exciters,
the paper's 18 masslines), the certified D-efficiency and the wall time of the whole
plan (search + certificate) for several certificate budgets (relaxation steps: a budget of work, so the
efficiency is the same on any machine; only the seconds are this machine's), against the baseline in
the same run: the relaxation's bound alone (0 steps, no branch and bound).
The efficiency is certified against every layout changing the sensors alone or the
exciters alone (placement/certification.py). Best of --repeat runs (shared machines
are noisy), with the process CPU time beside the wall time.
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np
import trimesh

from massline.meshes import BUNDLED
from massline.core import Lines
from massline.meshes.loader import load_body
from massline.core.model import RigidModel
from massline.placement.planner import Budget, CandidateLines, Planner, plan_on_candidates
from massline.placement.relaxation import relax_cvxpy, relax_first_order


def measured(fn):
    """Result, seconds and peak MiB of ``fn()``: timed on its own, then run again under tracemalloc
    (which slows allocation-heavy code) for the memory."""
    start = time.perf_counter()
    out = fn()
    seconds = time.perf_counter() - start
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return out, seconds, peak


def certificate_table(model, repeat: int, budgets: list) -> None:
    """Certified D-efficiency and seconds at 1e5 lines, minimal budget: relaxation alone vs branch and bound."""
    body_mesh = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density).mesh
    points, faces = trimesh.sample.sample_surface(body_mesh, 100_000, seed=1)
    side = CandidateLines.single(Lines(points, body_mesh.face_normals[faces]))
    print(f"{'steps':>9} | {'plan s (best)':>13} {'cpu s':>6} {'× baseline':>10} {'D-eff ≥':>8} {'log det':>8}")
    baseline = None
    for steps in [0, *budgets]:
        runs = []
        for _ in range(repeat):
            start, cpu = time.perf_counter(), time.process_time()
            plan = plan_on_candidates(model, side, side, Budget(6, 3), certify_steps=steps)
            wall, cpu = time.perf_counter() - start, time.process_time() - cpu
            runs.append((wall, cpu, plan.d_efficiency_lower_bound, plan.log_det))
        t, cpu, eff, value = min(runs)
        baseline = baseline or t
        label = "baseline" if steps == 0 else f"{steps}"
        print(f"{label:>9} | {t:13.2f} {cpu:6.2f} {t / baseline:10.2f} {eff:8.2%} {value:8.3f}", flush=True)
    print(f"best of {repeat}; goal: D-eff ≥ 95 % in < 5 s end to end on 2 cores")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--cvxpy-seconds", type=float, default=300.0, help="time limit of the cvxpy/SCS baseline")
    parser.add_argument("--certify-steps", type=int, default=2500, help="the certificate's relaxation steps")
    parser.add_argument("--certificate", action="store_true", help="the certificate table at 1e5 lines only")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--certificate-steps", type=int, nargs="+", default=[2500, 5000, 7500, 15000])
    args = parser.parse_args()
    body = load_body(BUNDLED["structure"].path, "m", BUNDLED["structure"].density)
    model = RigidModel(body.nominal)
    if args.certificate:
        certificate_table(model, args.repeat, args.certificate_steps)
        return
    print(
        f"{'lines':>7} | {'plan s':>7} {'MiB':>6} {'gap nats':>8} {'D-eff ≥':>7} | {'relax: ours s':>13} {'U ours':>9}"
        f" | {'cvxpy s':>8} {'MiB':>6} {'U cvxpy':>9} | {'time ratio':>10}"
    )
    for n in args.sizes:
        points, faces = trimesh.sample.sample_surface(body.mesh, n, seed=1)
        side = CandidateLines.single(Lines(points, body.mesh.face_normals[faces]))
        plan, t_plan, m_plan = measured(
            lambda: plan_on_candidates(model, side, side, Budget(6, 3), certify_steps=args.certify_steps)
        )
        gap = max(plan.bounds.values()) - plan.log_det
        planner = Planner(model, side, side, Budget(6, 3), plan.noise)
        exciters = [int(np.flatnonzero(np.all(side.lines.points == p, axis=1))[0]) for p in plan.exciters.points]
        sensors = [int(np.flatnonzero(np.all(side.lines.points == p, axis=1))[0]) for p in plan.sensors.points]
        problem = planner.sensor_problem(planner.exciter_rows(exciters))
        start = time.perf_counter()
        _, U_ours = relax_first_order(problem, sensors, tol=1e-4)
        t_ours = time.perf_counter() - start
        try:
            tracemalloc.start()
            start = time.perf_counter()
            _, U_cvx = relax_cvxpy(problem, "SCS", time_limit_secs=args.cvxpy_seconds)
            t_cvx = time.perf_counter() - start  # one run only: too slow to repeat; tracemalloc slows it a little
            m_cvx = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
        except Exception as err:  # the generic solvers do fail at scale; say so
            U_cvx, t_cvx, m_cvx = float("nan"), float("nan"), float("nan")
            print(f"  cvxpy failed at {n}: {type(err).__name__}: {str(err)[:80]}")
        stopped = ">" if t_cvx >= args.cvxpy_seconds else " "
        print(
            f"{n:>7} | {t_plan:7.2f} {m_plan:6.0f} {gap:8.3f} {plan.d_efficiency_lower_bound:7.1%} | {t_ours:13.3f}"
            f" {U_ours:9.3f} | {stopped}{t_cvx:7.1f} {m_cvx:6.0f} {U_cvx:9.3f} | {stopped}{t_cvx / t_ours:9.0f}",
            flush=True,
        )
    print("gap: largest certified bound minus log det of the plan (both sides); D-eff ≥ exp(−gap / 10).")
    print("U: bound on the sensor relaxation at the planned exciters (lower is tighter; both are valid).")


if __name__ == "__main__":
    main()
