"""The map's chunks on a Dask cluster (``reachability_map(..., dask=ADDRESS)``, ``robkin workspace
--dask ADDRESS``): the same chunks, seeds and folding as in one process (``sampling``), so the same map.

The chunks are split into contiguous ranges, one Dask task each; a task returns its range's partial map
and the client folds them in range order. Dask (``dask[distributed]``) is imported only here.
"""

from __future__ import annotations

from typing import Any

from ..errors import InputError
from .sampling import Partial, Plan, chunks, run_chunks, split

__all__ = ["run_on_dask"]

#: Tasks per worker thread: a few, so that a slow worker does not hold up the end, while each task's
#: result (a dense partial map of the whole box) is sent only a few times per worker.
TASKS_PER_THREAD = 4


def run_on_dask(plan: Plan, scheduler: Any, tasks: int | None = None) -> Partial:
    """The plan's partial map, its chunk ranges run on the Dask cluster ``scheduler``.

    Parameters
    ----------
    plan : Plan
    scheduler : str or dask.distributed.Client
        A scheduler address ('tcp://10.0.0.5:8786') or a connected client (kept open).
    tasks : int, optional
        Number of tasks (default: ``TASKS_PER_THREAD`` per worker thread of the cluster).
    """
    try:
        from dask.distributed import Client
    except ImportError:
        raise InputError("dask: Dask is not installed; pip install 'dask[distributed]' (or 'robkin[synthesis]') "
                         "to build a map on a Dask cluster") from None
    own = not isinstance(scheduler, Client)
    if own and not isinstance(scheduler, str):
        raise InputError(f"dask: expected a scheduler address or a dask.distributed.Client, got {scheduler!r}")
    try:
        # (dask.distributed's Client has no type hints)
        client = Client(scheduler, timeout="10s") if own else scheduler  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"dask: cannot connect to the Dask scheduler {scheduler!r} ({exc})") from None
    try:
        if tasks is None:
            threads = sum(client.nthreads().values()) or 1
            tasks = TASKS_PER_THREAD * threads
        elif isinstance(tasks, bool) or not isinstance(tasks, int) or tasks < 1:
            raise InputError(f"tasks: expected a whole number >= 1, got {tasks!r}")
        # a fresh robot: the one given may hold its compiled chain, which does not pickle
        shipped = Plan(**{**plan.__dict__, "robot": plan.robot.replace()})
        ranges = split(chunks(plan.samples), tasks)
        futures = client.map(_task, [shipped] * len(ranges), [a for a, _ in ranges], [b for _, b in ranges],
                             pure=False)
        parts = client.gather(futures)
    finally:
        if own:
            client.close()
    out = parts[0]
    for part in parts[1:]:
        out.fold(part)
    return out


def _task(plan: Plan, start: int, stop: int) -> Partial:
    """One Dask task: chunks start .. stop - 1 (the kernels on the worker's one thread, see robkin.threads)."""
    return run_chunks(plan, start, stop, 1)
