"""The cost of ``robkin convert --collision MODE``: time and triangles per arm and mode.

Arms of example-robot-data (the arms ``tests/test_collision_home.py`` checks), each mode of
``robkin.collision.collision_geometry`` run on the robot read from its URDF, mesh files written into a
temporary folder. Per arm and mode: wall time and CPU time of this process (``time.process_time``: CoACD
runs on one thread, and the machine's other load shows up less than in wall time), the collision
meshes written and their triangles (``source``: the source's collision meshes), the primitives. The
decomposition runs with an empty cache (``XDG_CACHE_HOME`` pointed at a new folder), then again from
the cache. For ``primitives``, the worst volume error and one-sided Hausdorff distance of the arm's links.

Run: ``python benchmarks/bench_collision.py [--modes source,hull,decompose,primitives] [--arms panda,ur5]``.
Needs example-robot-data; ``decompose`` needs CoACD (``pip install 'robkin[collision]'``).
"""

from __future__ import annotations

import argparse
import glob
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

import robkin

ROBOTS = (glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                 "example-robot-data", "robots")) or [""])[0]
ARMS = {
    "panda": ("panda_description/urdf/panda.urdf", None, "panda_hand_tcp"),
    "ur5": ("ur_description/urdf/ur5_robot.urdf", None, "tool0"),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, "ee_link"),
    "kinova": ("kinova_description/robots/kinova.urdf", None, "j2s6s200_end_effector"),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, None),
    "z1": ("z1_description/urdf/z1.urdf", None, "gripperMover"),
    "so100": ("so_arm_description/urdf/so100.urdf", None, None),
}


def _source_faces(robot, path: str) -> tuple[int, int]:
    from robkin.collision.mesh_data import MeshError, read_mesh
    from robkin.io.meshes.files import resolve_meshes

    shapes = [s for s in robot.bodies.shapes if s.role == "collision" and s.geometry.kind == "mesh"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        found = {k: m.path for k, m in resolve_meshes(robot, path).items() if m.path is not None}
    seen, faces = set(), 0
    for s in shapes:
        p = found.get(s.geometry.filename or "")
        if p is None or p in seen:
            continue
        seen.add(p)
        try:
            faces += len(read_mesh(p)[1])
        except MeshError:
            pass
    return len(seen), faces


def run(arm: str, mode: str, rows: list[str]) -> None:
    from robkin.collision import collision_geometry

    rel, base, tip = ARMS[arm]
    path = os.path.join(ROBOTS, rel)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robkin.load(path, base_link=base, tip_link=tip)
    runs = ("cold", "cached") if mode == "decompose" else ("",)
    with tempfile.TemporaryDirectory() as cache:
        os.environ["XDG_CACHE_HOME"] = cache
        for label in runs:
            with tempfile.TemporaryDirectory() as out:
                wall, cpu = time.perf_counter(), time.process_time()
                r = collision_geometry(robot, mode, source=path, out_dir=Path(out))
                wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
            if mode == "source":
                meshes, faces = _source_faces(robot, path)
            else:
                meshes, faces = r.meshes_out, r.faces_out
            fit = ""
            if r.fits:
                worst_v = max(f.volume_error for f in r.fits if f.volume_error != float("inf"))
                worst_h = max(f.hausdorff for f in r.fits)
                fit = f"worst volume error {100 * worst_v:+.0f} %, worst Hausdorff {1000 * worst_h:.1f} mm"
            rows.append(f"| {arm} | {mode}{' ' + label if label else ''} | {wall:.1f} | {cpu:.1f} | {meshes} | "
                        f"{faces} | {r.primitives_out} | {fit} |")
            print(rows[-1], flush=True)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--modes", default="source,hull,primitives,decompose")
    p.add_argument("--arms", default=",".join(ARMS))
    args = p.parse_args()
    if not ROBOTS:
        print("example-robot-data is not installed: nothing to measure")
        return 0
    rows = ["| arm | mode | wall s | CPU s | meshes | triangles | primitives | fit |", "|---|---|---|---|---|---|---|---|"]
    print("\n".join(rows), flush=True)
    for arm in args.arms.split(","):
        for mode in args.modes.split(","):
            run(arm, mode, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
