"""Configurations and multi-start runs evaluated in parallel with dask.distributed.

Each configuration lives in a worker process as a Dask actor holding its own working model,
compiled system and last equilibrium (so warm starts and the symbolic factorisation stay where
they are); a design point sends x and gets back the configuration's residual block and its
Jacobian rows. Multi-start runs are independent tasks. Serial is the default: see
docs/benchmarks.md for where the parallel evaluation starts to pay.
"""

from __future__ import annotations

import functools
from contextlib import contextmanager

import numba
import numpy as np

from ..errors import ModelError, UpdatingError
from .._threads import blas_threads


def single_threaded(function):
    """Run ``function`` with one numba thread and one BLAS thread: the worker processes share the
    machine's cores, and a kernel's threads spin-waiting beside another worker's starve both.

    numba's thread count is thread-local (numba.set_num_threads masks the calling thread's
    parallel regions only), so setting and restoring it here touches no other thread; the BLAS
    limit is the process-wide reference-counted hold of flexgvt.blas_threads."""
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        before = numba.get_num_threads()
        numba.set_num_threads(1)
        try:
            with blas_threads(1):
                return function(*args, **kwargs)
        finally:
            numba.set_num_threads(before)
    return wrapper


class ConfigurationWorker:
    """One configuration's updating problem, kept in a worker process."""

    def __init__(self, model, configuration, measured, variables, objective, n_modes, static_settings,
                 follow_sensors):
        from .problem import UpdatingProblem
        self.name = configuration.name
        self.problem = UpdatingProblem(model, [configuration], [measured], variables, None, objective, n_modes,
                                       static_settings, follow_sensors)

    @single_threaded
    def evaluate(self, x, gradient: bool) -> dict:
        from .problem import DesignPointFailure
        try:
            point = self.problem.evaluate(np.asarray(x, float), gradient=gradient)
        except DesignPointFailure as exc:
            return {"failure": str(exc)}
        out = point.configurations[self.name].to_dict()
        out["solves"] = self.problem.n_solves
        return out


@contextmanager
def client_for(processes: int | None = None, scheduler: str | None = None):
    """A dask.distributed Client: on a scheduler address, or on a local cluster of ``processes``
    single-threaded worker processes (closed on exit); None when neither is given."""
    if processes is None and scheduler is None:
        yield None
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError as exc:  # pragma: no cover - a dependency
        raise ModelError("parallel updating needs dask.distributed: pip install distributed") from exc
    if scheduler is not None:
        client = Client(scheduler)
        try:
            yield client
        finally:
            client.close()
        return
    if processes < 1:
        raise ModelError(f"processes={processes}: give a positive number of worker processes")
    # Dask starts workers with glibc's trim threshold at 64 kB (against memory creep in long-lived
    # workers): every array above it is then a fresh mmap, and the updating's arrays mostly are;
    # a configuration's evaluation took twice as long (ten times the page faults) as in this process.
    import dask
    spawn_env = {k: v for k, v in dask.config.get("distributed.nanny.pre-spawn-environ", {}).items()
                 if k != "MALLOC_TRIM_THRESHOLD_"}
    try:
        with dask.config.set({"distributed.nanny.pre-spawn-environ": spawn_env}):
            cluster = LocalCluster(n_workers=int(processes), threads_per_worker=1, processes=True,
                                   dashboard_address=None)
    except RuntimeError as exc:  # dask's "Nanny failed to start": the spawned workers could not start
        raise UpdatingError(
            f"processes={processes}: the {processes} worker processes could not start ({exc}). In a script, "
            "call the update under `if __name__ == \"__main__\":` (worker processes are spawned, and each "
            "imports the main module again); or leave processes out to run in this process") from exc
    client = Client(cluster)
    try:
        yield client
    finally:
        client.close()
        cluster.close()


def attach_workers(problem, client) -> None:
    """Move the evaluation of each configuration of ``problem`` into a worker-held actor."""
    actors = []
    for cfg in problem.configurations:
        future = client.submit(ConfigurationWorker, problem.model.copy(), cfg, problem.measured[cfg.name],
                               list(problem.par.variables), problem.objective, problem.n_modes,
                               problem.static_settings, problem.follow_sensors, actor=True, pure=False)
        actors.append(future.result())
    problem.workers = actors
