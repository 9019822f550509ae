"""The plan's FE model solved in a second process, while the layout is searched in the first.

The FE model a plan predicts its band on (:func:`massline.virtual.planned_test.plan_fe_model`) does not depend on
the layout, and the layout search does not need it: on two cores the two overlap, so a plan takes the longer of
the two instead of their sum (a 64-facet cylinder's 27 000-DOF solve is about 25 s). The process is started by
``spawn`` (a fresh interpreter: no thread of this one is forked), gets the body, and sends the modes back as the
arrays the cache keeps (:func:`massline.virtual.fe_cache.as_arrays`), or the error it met, which is raised here.
It is a daemon, terminated when it is no longer wanted (``close``) and when this process exits.
"""

from __future__ import annotations

import multiprocessing

from massline.meshes.loader import BodyMesh
from massline.virtual.fe_cache import as_arrays, from_arrays
from massline.virtual.planned_test import FEModel, plan_fe_model

POLL = 0.25  # s between looks at the pipe while waiting (so that Ctrl-C is taken at once)


def _solve(body: BodyMesh, mesh_name: str | None, pipe) -> None:
    """In the second process: each stage of the solve as ("stage", name, done, total), then the plan's FE model
    as ("modes", arrays, material, kept, assumed), or ("error", the exception met)."""
    try:
        fe = plan_fe_model(body, mesh_name, lambda *stage: pipe.send(("stage", *stage)))
        pipe.send(("modes", as_arrays(fe.modes), fe.material, fe.kept, fe.assumed))
    except BaseException as error:  # noqa: BLE001 — handed to the first process, which raises it
        try:
            pipe.send(("error", error))
        except Exception:  # noqa: BLE001 — an error that cannot be pickled goes as its words
            pipe.send(("error", RuntimeError(f"the FE solve failed: {type(error).__name__}: {error}")))
    finally:
        pipe.close()


class FEInProcess:
    """The plan's FE model of ``body`` being solved in a second process (module docstring)."""

    def __init__(self, body: BodyMesh, mesh_name: str | None):
        context = multiprocessing.get_context("spawn")
        self._pipe, sending = context.Pipe(duplex=False)
        self._process = context.Process(target=_solve, args=(body, mesh_name, sending), daemon=True)
        self._process.start()
        sending.close()
        self._stages: list[tuple] = []  # stages read by ``check`` and not yet shown
        self._last: tuple | None = None  # ("modes", …) or ("error", …), once read

    def _read(self, wait: float) -> bool:
        """Read one message if one comes within ``wait`` s; whether the last one (modes or error) has come."""
        if self._last is None and self._pipe.poll(wait):
            try:
                kind, *got = self._pipe.recv()
            except EOFError:  # its end closed without a last message: the process was killed
                raise self._ended() from None
            if kind == "stage":
                self._stages.append(tuple(got))
            else:
                self._last = (kind, *got)
        elif self._last is None and not self._process.is_alive() and not self._pipe.poll():
            raise self._ended()
        return self._last is not None

    def _ended(self) -> RuntimeError:
        """The error of a process that ended without a result (killed: out of memory, a signal), kept as its last
        message (a later look raises it again) once the process is closed."""
        self.close()
        error = RuntimeError(f"the FE process ended with exit code {self._process.exitcode}, without a result")
        self._last = ("error", error)
        return error

    def check(self) -> None:
        """Raise, at once, the error the solve met if it has already failed, or a RuntimeError if its process has
        ended without a result (without waiting for it)."""
        while self._last is None and self._pipe.poll():
            self._read(0.0)
        if self._last is None:
            self._read(0.0)  # a process that ended without a word (killed: out of memory) is raised now
        if self._last is not None and self._last[0] == "error":
            self.close()
            raise self._last[1]

    def result(self, progress=None) -> FEModel:
        """The FE model, once solved; each stage of the solve, as it is read, to ``progress(stage, done, total)``
        (the stages the search outlasted at once, then the one under way)."""
        try:
            while True:
                done = self._read(POLL)
                while self._stages:
                    stage = self._stages.pop(0)
                    if progress is not None:
                        progress(*stage)
                if done:
                    break
        finally:
            self.close()
        kind, *got = self._last
        if kind == "error":
            raise got[0]
        arrays, material, kept, assumed = got
        return FEModel(from_arrays(arrays, material), material, kept, assumed)

    def close(self) -> None:
        """Stop the process, if it still runs, and release the pipe (again: nothing)."""
        if self._process.is_alive():
            self._process.terminate()
        self._process.join()
        if not self._pipe.closed:
            self._pipe.close()
