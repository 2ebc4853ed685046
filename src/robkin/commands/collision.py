"""robkin collision: the self-collision model of a robot and its allowed-collision matrix as SRDF."""

from __future__ import annotations

import argparse
import sys

from .support.common import add_input, add_package_path, add_threads, load_input, package_paths, positive_int, seed

EPILOG = """\
Fits a conservative capsule around each link's collision geometry, samples configurations within the
joint limits and writes the link pairs a self-collision check may skip as SRDF (MoveIt's format):
<disable_collisions link1= link2= reason=/>, reason Adjacent (joined by a joint), Default (touching
at the home configuration), Always (touching at every sample) or Never (touching at none). A pair is
judged by its capsules first, then, where they meet, by the meshes themselves (coal, installed with
pinocchio; --no-exact: capsules alone, fewer "Never" pairs). Without -o the SRDF goes to stdout and
the summary to stderr. --compare SRDF says how many link pairs agree with another SRDF (the one a
robot's maintainers ship, say).

examples:
  robkin collision panda.urdf --tip-link panda_hand_tcp --samples 2000 -o panda_acm.srdf
  robkin collision ur5.urdf --tip-link tool0 --samples 2000 --no-exact --json
"""


def register(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    p = sub.add_parser("collision", help="self-collision model: allowed-collision matrix as SRDF",
                       description="The self-collision model of a robot (a capsule per link) and its "
                                   "allowed-collision matrix, written as SRDF <disable_collisions>.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    add_input(p)
    add_package_path(p)
    p.add_argument("-o", "--output", metavar="OUT.srdf", help="write the SRDF here (default: stdout)")
    p.add_argument("--samples", type=positive_int, default=None, metavar="N",
                   help="configurations sampled within the joint limits (default 20000)")
    p.add_argument("--seed", type=seed, default=0, help="random seed of the samples (default 0)")
    p.add_argument("--no-exact", action="store_true",
                   help="judge pairs by their capsules alone (no mesh check with coal)")
    p.add_argument("--compare", metavar="SRDF", help="report agreement with the disabled pairs of this SRDF")
    p.add_argument("--json", action="store_true", help="print the summary as JSON (links, capsules, pairs)")
    add_threads(p)
    return p


def run(args: argparse.Namespace) -> int:
    from ..io.files.atomic import write_text_atomic
    from ..io.srdf import read_srdf, srdf_text
    from ..self_collision.build import DEFAULT_SAMPLES, self_collision_model
    from ..threads import set_threads

    if args.threads is not None:
        set_threads(args.threads)
    robot = load_input(args.input, args)
    compare = read_srdf(args.compare)[1] if args.compare else None
    model = self_collision_model(robot, args.input, package_paths=package_paths(args),
                                 samples=args.samples or DEFAULT_SAMPLES, rng=args.seed,
                                 exact=False if args.no_exact else None)
    text = srdf_text(robot.name, [(d.link1, d.link2, d.reason) for d in model.disabled],
                     comment=f"robkin collision: {model.samples} samples, "
                             f"{'capsules then meshes (coal)' if model.exact is not None else 'capsules only'}")
    summary = _summary(model, compare)
    if args.output:
        write_text_atomic(args.output, text)
    else:
        sys.stdout.write(text)
    if args.json:
        from ..io.files.jsontext import dumps

        print(dumps(summary), file=sys.stderr if not args.output else sys.stdout)
    else:
        out = sys.stderr if not args.output else sys.stdout
        counts = summary["disabled"]
        print(f"{len(summary['links'])} links with collision geometry, {summary['pairs']} pairs: "
              + ", ".join(f"{counts[r]} {r}" for r in counts) + f", {summary['checked']} checked"
              + (f" ({'mesh check: coal' if model.exact is not None else 'capsules only'})"), file=out)
        if compare is not None:
            c = summary["compare"]
            print(f"agreement with {args.compare}: {c['agree']} of {c['pairs']} pairs ({100 * c['fraction']:.1f} %)"
                  + (f"; only here: {', '.join(c['only_here'])}" if c["only_here"] else "")
                  + (f"; only there: {', '.join(c['only_there'])}" if c["only_there"] else ""), file=out)
    return 0


def _summary(model, compare) -> dict:
    from ..self_collision.acm import REASONS

    links = model.links
    every = [frozenset((a, b)) for i, a in enumerate(links) for b in links[i + 1:]]
    out: dict = {
        "links": links,
        "capsules": [{"link": c.link, "body": c.body, "a": c.a.tolist(), "b": c.b.tolist(), "radius": c.radius}
                     for c in model.capsules],
        "pairs": len(every),
        "disabled": {r: sum(1 for d in model.disabled if d.reason == r) for r in REASONS},
        "checked": len(model.pairs),
        "samples": model.samples,
        "exact": model.exact is not None,
    }
    if compare is not None:
        mine = {frozenset((d.link1, d.link2)) for d in model.disabled}
        theirs = {frozenset((p.link1, p.link2)) for p in compare}
        agree = sum((p in mine) == (p in theirs) for p in every)
        out["compare"] = {"pairs": len(every), "agree": agree, "fraction": agree / max(len(every), 1),
                          "only_here": ["/".join(sorted(p)) for p in every if p in mine and p not in theirs],
                          "only_there": ["/".join(sorted(p)) for p in every if p in theirs and p not in mine]}
    return out
