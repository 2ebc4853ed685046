"""Synthesis benchmark: do the estimates (types A-D) make a better start than random values?

The estimation paper ends by proposing to feed its estimates to an optimiser "to observe if the
convergence is faster". This script does that: for generated tasks it runs ``robkin.synthesis.
synthesize`` from each estimate type and from several random starts, and reports per start type

- reach rate: phase 1 (least squares on the reach residual alone) reached every task pose;
- converged rate: the optimise phase met its tolerance and the final design reaches every pose;
- median evaluations of phase 1 and of all phases, mean wall time per run;
- median final cost (sum of squared link lengths / R^2 for cost 'length') and eq.-48 length (units of
  the task positions), over converged runs;
- best on: the fraction of tasks on which this start found the lowest converged cost (within 0.1 %).

Rows 'best of A-D' and 'best of k random' compare equal budgets (4 runs each).

Tasks (lengths in units of the task size, positions 0.5-1.5 from the base, uniform orientations):
  single   one pose, n = 4
  path3    3 poses 0.3 apart and turned 0.5 rad each, n = 6
  path4    4 poses 0.3 apart and turned 0.5 rad each, n = 4 (nearly as many constraints as unknowns)

Runs go to local processes by default, or to a Dask cluster with --scheduler tcp://host:8786.

usage:
  python benchmarks/bench_synthesis.py                       # 30 tasks per scenario, all cores
  python benchmarks/bench_synthesis.py --tasks 5 --workers 2 --scenarios single
  python benchmarks/bench_synthesis.py --scheduler tcp://10.0.0.5:8786 --tasks 500
  python benchmarks/bench_synthesis.py --markdown results.md --json records.json
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

from robkin.synthesis.sweep import make_jobs, random_task_poses, run_sweep, summarize

SCENARIOS = {
    "single": dict(K=1, n=4, step=0.0, turn=0.0, title="one pose, n = 4"),
    "path3": dict(K=3, n=6, step=0.3, turn=0.5, title="path of 3 poses (0.3 apart, 0.5 rad turns), n = 6"),
    "path4": dict(K=4, n=4, step=0.3, turn=0.5, title="path of 4 poses (0.3 apart, 0.5 rad turns), n = 4"),
}


def _fmt(v: float, digits: int = 3) -> str:
    if isinstance(v, float) and math.isnan(v):
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def markdown_table(rows: list[dict]) -> str:
    head = ("| start | runs | reached by phase 1 | converged | phase-1 evals | total evals | s / run "
            "| cost | length (eq. 48) | best on |")
    out = [head, "|" + "---|" * 10]
    for r in rows:
        out.append("| " + " | ".join([
            r["start"], str(r["runs"]), f"{100 * r['reach_rate']:.0f} %", f"{100 * r['converged_rate']:.0f} %",
            _fmt(r["reach_evaluations"]), _fmt(r["evaluations"]), _fmt(r["seconds"], 2), _fmt(r["cost"]),
            _fmt(r["length"]), f"{100 * r['best_rate']:.0f} %"]) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--tasks", type=int, default=30, help="tasks per scenario (default 30)")
    p.add_argument("--scenarios", default="single,path3,path4", help="comma list of " + ", ".join(SCENARIOS))
    p.add_argument("--random-starts", type=int, default=4, help="random starts per task (default 4)")
    p.add_argument("--cost", default="length", choices=("length", "manipulability"))
    p.add_argument("--workers", type=int, default=None, help="local processes (default: all cores)")
    p.add_argument("--scheduler", help="Dask scheduler address; runs on that cluster instead")
    p.add_argument("--seed", type=int, default=2021)
    p.add_argument("--max-iter", type=int, default=1000, help="evaluation limit per phase")
    p.add_argument("--markdown", help="also write the tables to this Markdown file")
    p.add_argument("--json", help="write every run's record to this JSON file")
    p.add_argument("--no-progress", action="store_true")
    args = p.parse_args(argv)

    starts = ["A", "B", "C", "D"] + ["random"] * args.random_starts
    sections, all_records = [], []
    header = (f"robkin synthesis benchmark: {args.tasks} tasks per scenario, starts A-D + "
              f"{args.random_starts} random, cost '{args.cost}', seed {args.seed}; "
              f"{platform.python_implementation()} {platform.python_version()}, "
              f"{'Dask ' + args.scheduler if args.scheduler else f'{args.workers or os.cpu_count()} local processes'}")
    print(header)
    for name in args.scenarios.split(","):
        sc = SCENARIOS[name]
        rng = np.random.default_rng([args.seed, list(SCENARIOS).index(name)])
        tasks = [random_task_poses(rng, sc["K"], sc["step"], sc["turn"]) for _ in range(args.tasks)]
        jobs = make_jobs(tasks, sc["n"], starts, args.cost, args.seed, args.max_iter)
        t0 = time.perf_counter()
        records = run_sweep(jobs, workers=args.workers, scheduler=args.scheduler, progress=not args.no_progress)
        wall = time.perf_counter() - t0
        for r in records:
            r["scenario"] = name
        all_records += records
        table = markdown_table(summarize(records, random_group=args.random_starts))
        text = f"\n### {name}: {sc['title']}\n\n{table}\n\n({len(jobs)} runs in {wall:.0f} s wall)\n"
        print(text)
        sections.append(text)
    if args.markdown:
        with open(args.markdown, "w", encoding="utf-8") as fh:
            fh.write(header + "\n" + "".join(sections))
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(all_records, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
