"""Drag-to-IK rate of the GUI: ``POST /api/ik`` round trips per second for the Panda (7 joints).

Goal (issue 13): the robot follows a dragged tool frame at >= 30 updates per second for a 7-joint arm.
The page sends one request at a time (the next target waits for the answer), so the rate is 1 / the
round-trip time: JSON request, robot text looked up in the parse cache, one IK attempt seeded with the
previous q, the scene at the new q, JSON answer. Measured here over one kept-alive HTTP connection on
loopback, like the browser's fetch, with the tool pulled along a 5 cm circle in small steps (what a
mouse drag asks). The UR5 (closed form, all 8 branches per answer) is measured the same way.

Run: ``.venv/bin/python benchmarks/bench_gui_ik.py [--steps 300]``. Exit status 0 whatever the result
(a benchmark, not a test); the last line says whether the goal is met.
"""

from __future__ import annotations

import argparse
import http.client
import json
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

GOAL = 30.0
ERD = Path(sys.prefix) / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages" / \
    "cmeel.prefix" / "share" / "example-robot-data" / "robots"
ARMS = {  # name: (URDF, base link, tip link, a configuration away from limits and singularities)
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8",
              [0, -math.pi / 4, 0, -3 * math.pi / 4, 0, math.pi / 2, math.pi / 4]),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "", "tool0", [0.3, -1.2, 1.4, -0.8, 1.1, 0.5]),
}


def drag(name: str, steps: int) -> tuple[list[float], int]:
    """Round-trip times (s) of ``steps`` IK requests along a circle, and how many reached the target."""
    from robkin.viz.gui import make_server
    from robkin.viz.gui_api import describe

    path, base, tip, q = ARMS[name]
    text = (ERD / path).read_text()
    server = make_server(port=0, text=text, fmt="urdf", base_link=base or None, tip_link=tip)
    server.serve_in_thread()
    try:
        home = np.array(describe(text, "urdf", q, base or None, tip)["T"])
        conn = http.client.HTTPConnection(*server.server_address[:2])
        times, reached = [], 0
        for k in range(steps):
            t = 2 * math.pi * k / steps
            T = home.copy()
            T[:3, 3] += 0.05 * np.array([math.cos(t) - 1, math.sin(t), 0.0])
            body = json.dumps({"text": text, "fmt": "urdf", "base_link": base, "tip_link": tip,
                               "target": T.tolist(), "q0": q})
            t0 = time.perf_counter()
            conn.request("POST", "/api/ik", body, {"Content-Type": "application/json"})
            res = json.loads(conn.getresponse().read())
            times.append(time.perf_counter() - t0)
            q = res["q"]
            reached += bool(res["success"])
        conn.close()
        return times, reached
    finally:
        server.shutdown()
        server.server_close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=300)
    args = ap.parse_args()
    if not ERD.is_dir():
        sys.exit("example-robot-data is not installed (pip install 'robkin[test]')")
    rates = {}
    for name in ARMS:
        times, reached = drag(name, args.steps)
        med = statistics.median(times)
        p95 = sorted(times)[int(0.95 * len(times))]
        rates[name] = 1 / med
        print(f"{name:6s} {args.steps} targets: round trip median {med * 1e3:.1f} ms, 95th percentile "
              f"{p95 * 1e3:.1f} ms -> {1 / med:.0f} updates/s; {reached}/{args.steps} reached")
    ok = rates["panda"] >= GOAL
    print(f"goal >= {GOAL:.0f} updates/s for the 7-joint Panda: {'met' if ok else 'NOT met'} ({rates['panda']:.0f}/s)")


if __name__ == "__main__":
    main()
