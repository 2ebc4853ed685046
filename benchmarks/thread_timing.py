"""Timing of robkin's threads against what the machine gives at the same moment (bench_threads, bench_ik_threads).

A batch call is timed with ``threads=1``, with ``threads=k`` and as the **machine's ceiling**: the same
work done as k independent one-thread calls on k contiguous parts of the batch, run at the same time
(the calling thread takes the first part, persistent worker threads the others, released together; the
kernels release the GIL). The ceiling is what k threads can give on this machine at that moment with no
threading machinery of robkin's at all: on a shared virtual machine the vCPUs do not run at equal
speeds (measured here: the same one-thread call pinned to cpu0 and cpu1 at the same time took 401 and
598 us), and a speed drifts within a minute, so two threads reach (speed0 + speed1) / speed of the
calling thread's vCPU, not 2x. Equal parts reach less: the slower vCPU's part ends last, and the
ceiling of equal parts is k x (slowest speed) / (calling thread's speed). Each part's own time is
measured too, and the **balanced ceiling** is the same run had the parts been sized to those speeds:
the (speed0 + speed1) bound, which a dynamic split such as robkin's guided schedule can approach. Both
ceilings take the parts' own times, from call to return: starting and joining the Python threads
(tens of microseconds, the measuring tool's cost) is left out, robkin's own start and join is not.
A fresh result larger than glibc's 32 MB reuse limit is not comparable: the parts' smaller arrays are
served from freed memory, the whole one pays the system's page faults (docs/compiled.md), and the
ceiling then exceeds k; such rows are named apart in the goal line. robkin's share (its speed-up over
the higher of the two ceilings, all from the same rounds) separates robkin's threading from the
machine's state. A share above 100 % is possible: the ceilings' parts are Python calls, each with its
own argument checks and result, and robkin's guided schedule can beat equal parts.

Each round pauses (``SETTLE``: libgomp's worker spins ~5-10 ms after a parallel region, and a
ceiling run meanwhile would share a vCPU with it), runs the one-thread call once untimed, then times
the one-thread call and the ceiling (which goes first alternates), each k-thread call and each k-thread
call again right after. The first k-thread call, like the ceiling, starts with its worker threads
asleep (as a call after a pause does); the second finds libgomp's workers still spinning (as in a
loop of calls): robkin's share of the ceiling compares the first, the plain goal takes the second.
A speed-up is the median over the rounds of the ratio within a round (a round's calls see nearly the
same machine, so the drift between rounds cancels). The number of rounds comes from a time budget
per row, between a floor and a cap.
"""

from __future__ import annotations

import os
import threading
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from robkin.threads import available_cores


def others_share(run: Callable[[], Any]) -> tuple[Any, float | None]:
    """run() and the share (0..1) of all CPUs that other processes used meanwhile (None off Linux)."""
    def busy() -> int:
        with open("/proc/stat") as f:
            v = [int(x) for x in f.readline().split()[1:]]
        return sum(v) - v[3] - v[4]   # all but idle and iowait, in clock ticks
    try:
        b0, s0, t0 = busy(), os.times(), time.perf_counter()
    except OSError:
        return run(), None
    result = run()
    s1, hz = os.times(), os.sysconf("SC_CLK_TCK")
    own = (s1.user + s1.system - s0.user - s0.system) * hz
    return result, max(0.0, (busy() - b0 - own) / hz / (time.perf_counter() - t0) / available_cores())


def parts_of(n: int, k: int) -> list[slice]:
    """k contiguous slices covering range(n), sizes differing by at most one (the larger first)."""
    bounds = np.cumsum([0] + [n // k + (i < n % k) for i in range(k)])
    return [slice(int(a), int(b)) for a, b in zip(bounds[:-1], bounds[1:])]


class Concurrent:
    """Runs k jobs at the same time: the calling thread the first, k - 1 persistent worker threads the rest.

    The workers wait at a barrier between runs (no thread is created per run), worker i pinned to the
    i-th CPU this process may use (where the system allows it): with k = 2 the other vCPU, where
    robkin's OpenMP worker runs too, even when another process keeps it busy (unpinned, the scheduler
    would put the worker next to the caller instead). Use as a context manager.
    """

    def __init__(self, k: int):
        self.k = k
        self._jobs: list = [None] * k
        self._results: list = [None] * k
        self._errors: list = [None] * k
        self._start = threading.Barrier(k)
        self._done = threading.Barrier(k)
        cpus = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
        self._workers = [threading.Thread(target=self._serve, args=(i, cpus[i % len(cpus)] if cpus else None),
                                          daemon=True) for i in range(1, k)]
        for w in self._workers:
            w.start()

    def _serve(self, i: int, cpu: int | None) -> None:
        if cpu is not None:
            os.sched_setaffinity(0, {cpu})   # this thread only (Linux)
        while True:
            self._start.wait()
            job = self._jobs[i]
            if job is None:
                return
            try:
                self._results[i] = job()
            except BaseException as e:   # noqa: BLE001 - handed to the caller, which re-raises it
                self._errors[i] = e
            self._done.wait()

    def run(self, jobs: list[Callable[[], Any]]) -> list:
        """Each job's result, the k jobs started together."""
        self._jobs[:] = jobs
        self._start.wait()
        try:
            self._results[0] = jobs[0]()
        finally:
            self._done.wait()
        for e in self._errors:
            if e is not None:
                self._errors[:] = [None] * self.k
                raise e
        return list(self._results)

    def close(self) -> None:
        self._jobs[:] = [None] * self.k
        self._start.wait()
        for w in self._workers:
            w.join()

    def __enter__(self) -> Concurrent:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


SETTLE = 0.015
"""Seconds of pause before each round: longer than libgomp's spin (~5-10 ms of a worker spinning on a
vCPU after each parallel region, OMP_WAIT_POLICY unset), which would otherwise compete with the
ceiling's worker; every round then starts with robkin's and the ceiling's workers asleep alike."""


def timed_rounds(fns: dict, rounds: int, settle: float = SETTLE) -> dict:
    """Wall seconds of each function in each of ``rounds`` rounds (arrays).

    ``fns``: the one-thread call (key 1), the ceiling (key "ceiling") and the k-thread calls (int keys
    > 1). A round: a pause of ``settle`` seconds, the one-thread call once untimed (the caches and this
    thread's vCPU warm again after the pause), the one-thread call and the ceiling (which goes first
    alternates), then each k-thread call twice (keys k and ("again", k)): no k-thread call comes just
    before the ceiling.
    """
    many = [k for k in fns if k not in (1, "ceiling")]
    times: dict = {k: np.empty(rounds) for k in [1, "ceiling", *many, *(("again", k) for k in many)]}
    for r in range(rounds):
        time.sleep(settle)
        fns[1]()
        for key in ([1, "ceiling"] if r % 2 else ["ceiling", 1]) + [x for k in many for x in (k, ("again", k))]:
            fn = fns[key[1] if isinstance(key, tuple) else key]
            t0 = time.perf_counter()
            fn()
            times[key][r] = time.perf_counter() - t0
    return times


@dataclass
class Budget:
    """Rounds per row: as many as ``seconds`` hold (from one timed round), at least ``least``, at most ``most``."""

    seconds: float
    least: int
    most: int

    def rounds(self, fns: dict) -> int:
        t0 = time.perf_counter()
        timed_rounds(fns, 1)
        return int(min(self.most, max(self.least, self.seconds // max(time.perf_counter() - t0, 1e-9))))


@dataclass
class Row:
    """One kernel at one batch size: one-thread median seconds, speed-ups of k threads (workers asleep
    before the call, and again right after it) and of the ceiling (medians over the rounds of the
    ratios within a round)."""

    t1: float
    speedup: dict                   # {k: speed-up}, the k-thread call after the pause
    again: dict                     # {k: speed-up}, the same call right after it
    ceiling: float                  # k one-thread calls on k equal parts at once
    balanced: float                 # the same, were the parts sized to the threads' measured speeds
    rounds: int
    bits: bool                      # every k-thread result the one-thread bits
    ceiling_bits: bool              # the parts' results the one-thread bits (where comparable)

    def share(self) -> float:
        """robkin's speed-up on the most threads (workers asleep, as the ceiling's) over the higher of
        the two ceilings (the balanced one, unless the equal parts happened to do better)."""
        return self.speedup[max(self.speedup)] / max(self.ceiling, self.balanced)


def arrays_equal(a: Any, b: Any) -> bool:
    """Same shape and bits (NaN where NaN)."""
    return bool(np.array_equal(a, b, equal_nan=True))


def arrays_joined_equal(one: Any, results: list, parts: list[slice]) -> bool:
    """The parts' arrays, joined, are the one-thread array's bits."""
    return arrays_equal(np.concatenate(results), one)


def measure(call: Callable[[int, slice], Any], n: int, counts: list[int], pool: Concurrent, budget: Budget,
            same: Callable[[Any, Any], bool] = arrays_equal,
            parts_agree: Callable[[Any, list, list[slice]], bool] = arrays_joined_equal) -> Row:
    """Time ``call(threads, rows)`` (rows: a slice of a batch of n) on one thread, on each of ``counts``
    threads and as the ceiling (``pool.k`` one-thread calls on contiguous parts at once); check the bits.

    A result that is a reused ``out=`` array is copied before the next call overwrites it.
    """
    def kept(r: Any) -> Any:
        return r.copy() if isinstance(r, np.ndarray) else r

    def part(s: slice) -> float:
        t0 = time.perf_counter()
        call(1, s)
        return time.perf_counter() - t0

    parts = parts_of(n, pool.k)
    sizes = np.array([s.stop - s.start for s in parts], float)
    everything = slice(0, n)
    one = kept(call(1, everything))
    bits = all(same(call(k, everything), one) for k in counts)
    ceiling_bits = parts_agree(one, [kept(r) for r in pool.run([lambda s=s: call(1, s) for s in parts])], parts)
    spans: list = []     # each ceiling run's parts' own seconds
    fns: dict = {1: lambda: call(1, everything),
                 "ceiling": lambda: spans.append(pool.run([lambda s=s: part(s) for s in parts]))}
    fns.update({k: (lambda k=k: call(k, everything)) for k in counts})
    rounds = budget.rounds(fns)
    t = timed_rounds(fns, rounds)
    # each part's own time, from its call to its return: the Python threads' start and join (the tool's
    # cost, tens of microseconds, not the machine's) left out
    d = np.array(spans[-rounds:])                   # (rounds, k)
    balanced = n / (sizes / d).sum(axis=1)          # every vCPU busy to the end at its measured speed
    return Row(float(np.median(t[1])), {k: float(np.median(t[1] / t[k])) for k in counts},
               {k: float(np.median(t[1] / t["again", k])) for k in counts},
               float(np.median(t[1] / d.max(axis=1))), float(np.median(t[1] / balanced)), rounds, bits,
               ceiling_bits)


def header_cells(counts: list[int]) -> str:
    """The column titles of ``row_cells``."""
    return "".join(f"{f'{k} threads':>12}{'again':>8}" for k in counts) + \
        f"{'halves':>9}{'balanced':>10}{'share':>8}{'rounds':>8}"


def row_cells(r: Row) -> str:
    """A Row's speed-ups, ceilings, share and rounds as table cells."""
    return "".join(f"{r.speedup[k]:>11.2f}x{r.again[k]:>7.2f}x" for k in r.speedup) + \
        f"{r.ceiling:>8.2f}x{r.balanced:>9.2f}x{100 * r.share():>7.0f}%{r.rounds:>8}"


def legend(best: int, what: str) -> str:
    """What the columns of a table of Rows mean."""
    return (f"{best} threads: after the round's pause (workers asleep); again: right after it (libgomp's workers "
            f"still spinning); halves: {best} one-thread calls on {best} equal parts of {what} at the same time "
            f"(the machine's {best} vCPUs at this moment, no robkin threading; the parts' own times); balanced: "
            f"the same, parts sized to the speeds measured; share: the {best}-thread speed-up over the higher "
            f"ceiling")


def goal_lines(rows: list, best: int, share: float = 0.95) -> list[str]:
    """The plain goal (>= 0.9 x best cores, calls back to back) and the goal against the ceiling; rows
    are (label, Row). A row whose ceiling exceeds ``best`` (a fresh array the parts get without page
    faults) is not compared with it, only named."""
    missed = [label for label, r in rows if r.again[best] < 0.9 * best]
    apart = [label for label, r in rows if min(r.ceiling, r.balanced) > best]
    below = [f"{label} ({100 * r.share():.0f} %)" for label, r in rows if label not in apart and r.share() < share]
    compared = len(rows) - len(apart)
    return [f"goal >= {0.9 * best:.1f}x on {best} cores at N >= 1e4 (calls back to back): "
            + ("met" if not missed else f"MISSED by {len(missed)} of {len(rows)}: " + ", ".join(missed)),
            f"robkin's {best}-thread speed-up >= {100 * share:.0f} % of the machine's ceiling measured in the "
            f"same rounds: " + ("met" if not below else f"MISSED by {len(below)} of {compared}: " + ", ".join(below))
            + ("" if not apart else f"; not compared (ceiling above {best}x, fresh arrays): " + ", ".join(apart))]


IK_FIELDS = ("q", "success", "iterations", "attempts", "position_error", "orientation_error")


def ik_same_bits(a: Any, b: Any) -> bool:
    """Every per-target field of two batch IK results bit for bit (NaN where NaN)."""
    return all(arrays_equal(getattr(a, f), getattr(b, f)) for f in IK_FIELDS)


def ik_parts_agree(one: Any, results: list, parts: list[slice]) -> bool:
    """The parts' batch IK results against the whole batch's, on the rows where they must agree.

    A numeric restart's random stream depends on the row's index in its batch (``compiled.ik.lm``): the
    first part's rows have the same indices, every row solved by its first attempt (no random numbers)
    is the same anywhere; a later part's restarted rows may differ, and are not compared.
    """
    for s, r in zip(parts, results):
        rows = np.ones(s.stop - s.start, bool) if s.start == 0 else one.attempts[s] == 1
        if not all(arrays_equal(getattr(r, f)[rows], getattr(one, f)[s][rows]) for f in IK_FIELDS):
            return False
    return True
