"""Many synthesis runs at once: generated tasks x start types, on local processes or a Dask cluster.

``run_sweep(jobs)`` evaluates ``Job`` records in parallel and returns one plain-dict record per job:

- default: a local process pool (``concurrent.futures``), ``workers`` processes (default: CPU count);
- ``workers=1``: in this process (no pickling; handy for tests and debugging);
- ``scheduler="tcp://host:8786"`` (or a ``dask.distributed.Client``): on that Dask cluster, for users
  who outgrow one machine (``pip install robkin[synthesis]``; dask is imported only then).

Long sweeps show a progress bar (tqdm if installed, else a one-line counter on stderr).
``summarize(records)`` turns the records into per-start statistics for the benchmark table.
"""

from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass
from typing import Any, Iterable, Sequence

import numpy as np

from .. import se3
from ..errors import InputError

__all__ = ["Job", "random_task_poses", "make_jobs", "run_job", "run_sweep", "summarize", "progress_bar"]


@dataclass(frozen=True)
class Job:
    """One synthesis run: task poses (K, 4, 4) in the robot base frame, n, start, cost, seed."""

    task_id: int
    poses: np.ndarray
    n: int
    start: str
    cost: str = "length"
    seed: int = 0
    max_iter: int = 1000
    reach: str = "pose"


def random_task_poses(rng: np.random.Generator, count: int = 3, step: float = 0.3,
                      turn: float = 0.5, radius: tuple[float, float] = (0.5, 1.5)) -> np.ndarray:
    """A random path of ``count`` poses (count, 4, 4): the first at a uniform direction and a distance
    in ``radius`` from the base with a uniform orientation, each next one moved by a random step of
    length ``step`` and turned by ``turn`` rad about a random axis (lengths in the radius' units)."""
    from scipy.spatial.transform import Rotation

    d = rng.normal(size=3)
    p = d / np.linalg.norm(d) * rng.uniform(*radius)
    T = se3.homogeneous(Rotation.random(random_state=int(rng.integers(2**31))).as_matrix(), p)
    out = [T]
    for _ in range(count - 1):
        axis = rng.normal(size=3)
        axis /= np.linalg.norm(axis)
        move = rng.normal(size=3)
        move *= step / np.linalg.norm(move)
        T = se3.homogeneous(Rotation.from_rotvec(axis * turn).as_matrix() @ T[:3, :3], T[:3, 3] + move)
        out.append(T)
    return np.stack(out)


def make_jobs(tasks: Sequence[np.ndarray], n: int, starts: Sequence[str], cost: str = "length",
              seed: int = 0, max_iter: int = 1000, reach: str = "pose") -> list[Job]:
    """Every (task, start) pair; random starts get distinct seeds derived from ``seed``."""
    jobs = []
    for t, poses in enumerate(tasks):
        for j, s in enumerate(starts):
            jobs.append(Job(t, np.asarray(poses, dtype=float), n, s, cost, seed * 1_000_003 + t * 1009 + j,
                            max_iter, reach))
    return jobs


def run_job(job: Job) -> dict[str, Any]:
    """Run one job; returns its ``SynthesisResult.summary()`` plus task_id, n, cost name."""
    from .optimize import make_task, synthesize

    task = make_task(job.poses, reach=job.reach)
    res = synthesize(task, job.n, job.start, job.cost, rng=job.seed, max_iter=job.max_iter)
    rec = res.summary()
    rec.update(task_id=job.task_id, n=job.n, cost_name=job.cost, K=int(job.poses.shape[0]))
    return rec


class _Counter:
    """Minimal progress display when tqdm is not installed: 'desc: k/N' rewritten on stderr."""

    def __init__(self, total: int, desc: str, enabled: bool) -> None:
        self.total, self.desc, self.k = total, desc, 0
        self.enabled = enabled and sys.stderr.isatty()

    def update(self, k: int = 1) -> None:
        self.k += k
        if self.enabled:
            print(f"\r{self.desc}: {self.k}/{self.total}", end="", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self.enabled:
            print(file=sys.stderr)


def progress_bar(total: int, desc: str = "synthesis", enabled: bool = True):
    """A tqdm bar (if tqdm is installed) or a plain counter; both have update() and close()."""
    if enabled:
        try:
            from tqdm import tqdm

            return tqdm(total=total, desc=desc, file=sys.stderr)
        except ImportError:
            pass
    return _Counter(total, desc, enabled)


def run_sweep(jobs: Iterable[Job], workers: int | None = None, scheduler: Any = None,
              progress: bool = True) -> list[dict[str, Any]]:
    """Run jobs in parallel; records come back in job order.

    Parameters
    ----------
    jobs : iterable of Job
    workers : int, optional
        Local processes (default: os.cpu_count()); 1 runs in this process. Ignored with ``scheduler``.
    scheduler : str or dask.distributed.Client, optional
        Address of a Dask scheduler (e.g. 'tcp://10.0.0.5:8786') or a connected Client.
    progress : bool
        Show a progress bar.
    """
    jobs = list(jobs)
    bar = progress_bar(len(jobs), enabled=progress)
    try:
        if scheduler is not None:
            return _run_dask(jobs, scheduler, bar)
        workers = (os.cpu_count() or 1) if workers is None else int(workers)
        if workers < 1:
            raise InputError(f"workers: need at least 1, got {workers}")
        if workers == 1 or len(jobs) <= 1:
            out = []
            for job in jobs:
                out.append(run_job(job))
                bar.update(1)
            return out
        return _run_processes(jobs, workers, bar)
    finally:
        bar.close()


def _run_processes(jobs: list[Job], workers: int, bar) -> list[dict[str, Any]]:
    from concurrent.futures import ProcessPoolExecutor, as_completed

    out: list[dict[str, Any] | None] = [None] * len(jobs)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(run_job, job): i for i, job in enumerate(jobs)}
        for fut in as_completed(futures):
            out[futures[fut]] = fut.result()
            bar.update(1)
    return out  # type: ignore[return-value]


def _run_dask(jobs: list[Job], scheduler: Any, bar) -> list[dict[str, Any]]:
    try:
        from dask.distributed import Client, as_completed
    except ImportError:
        raise InputError("scheduler: Dask is not installed; pip install 'robkin[synthesis]' "
                         "(or dask[distributed]) to run on a Dask cluster") from None
    own = not isinstance(scheduler, Client)
    try:
        client = Client(scheduler) if own else scheduler
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"scheduler: cannot connect to Dask scheduler {scheduler!r} ({exc})") from None
    try:
        futures = client.map(run_job, jobs, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        out: list[dict[str, Any] | None] = [None] * len(jobs)
        for fut in as_completed(futures):
            out[index[fut.key]] = fut.result()
            bar.update(1)
        return out  # type: ignore[return-value]
    finally:
        if own:
            client.close()


def summarize(records: Sequence[dict[str, Any]], random_group: int | None = None) -> list[dict[str, Any]]:
    """Per-start statistics (one row per start label, in first-seen order).

    Columns: runs; reach_rate (phase 1 alone reached every pose); converged_rate; median
    reach_evaluations and total evaluations; median final cost and eq.-48 length over converged runs;
    best_rate: fraction of tasks on which this start's converged cost is within 1e-3 relative of the
    best converged cost of any start. With ``random_group`` = k, one more row 'best of k random'
    takes, per task, the best of the first k random starts (same budget comparison as "best of A-D").
    """
    by_task: dict[int, list[dict[str, Any]]] = {}
    for r in records:
        by_task.setdefault(r["task_id"], []).append(r)
    best = {t: min((r["cost"] for r in rs if r["converged"]), default=math.inf) for t, rs in by_task.items()}
    labels: list[str] = []
    for r in records:
        if r["start"] not in labels:
            labels.append(r["start"])
    rows = [_row(label, [r for r in records if r["start"] == label], best) for label in labels]
    groups = {"best of A-D": lambda rs: [r for r in rs if r["start"] in "ABCD"]}
    if random_group:
        groups[f"best of {random_group} random"] = lambda rs: [r for r in rs if r["start"] == "random"][:random_group]
    for name, pick in groups.items():
        picked = []
        for t, rs in by_task.items():
            cand = pick(rs)
            if not cand:
                continue
            ok = [r for r in cand if r["converged"]]
            chosen = dict(min(ok, key=lambda r: r["cost"]) if ok else cand[0])
            chosen["evaluations"] = sum(r["evaluations"] for r in cand)
            chosen["reach_evaluations"] = sum(r["reach_evaluations"] for r in cand)
            chosen["seconds"] = sum(r["seconds"] for r in cand)
            chosen["reached_first"] = any(r["reached_first"] for r in cand)
            picked.append(chosen)
        if picked:
            rows.append(_row(name, picked, best))
    return rows


def _row(label: str, rs: list[dict[str, Any]], best: dict[int, float]) -> dict[str, Any]:
    conv = [r for r in rs if r["converged"]]

    def med(key: str, src: list[dict[str, Any]]) -> float:
        return float(np.median([r[key] for r in src])) if src else math.nan

    wins = len({r["task_id"] for r in conv if r["cost"] <= best[r["task_id"]] * (1 + 1e-3)})
    return {"start": label, "runs": len(rs),
            "reach_rate": sum(r["reached_first"] for r in rs) / len(rs),
            "converged_rate": len(conv) / len(rs),
            "reach_evaluations": med("reach_evaluations", rs), "evaluations": med("evaluations", rs),
            "seconds": float(np.mean([r["seconds"] for r in rs])),
            "cost": med("cost", conv), "length": med("length", conv),
            "best_rate": wins / len({r["task_id"] for r in rs})}
