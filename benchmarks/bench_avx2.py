"""Batch FK and Jacobian: robkin's portable and AVX2 kernel builds against a hand-written AVX2 kernel.

The Franka Panda of example-robot-data (7 revolute joints, tool ``panda_hand_tcp``), N random
configurations (N = 1e3, 1e4, 1e5), one thread. Three contenders per kernel (FK, geometric Jacobian), each writing into a
buffer allocated beforehand (robkin: ``out=``):
- robkin with ``robkin.compiled.chain.kernels.use("portable")`` (x86-64 baseline, SSE2: 2 doubles a vector),
- robkin with ``use("avx2")`` (the same source built with -mavx2, chosen at import on an AVX2 CPU),
- the floor: ``avx2_floor.c`` next to this file, FK and the geometric Jacobian written by hand with AVX2
  intrinsics (4 configurations a vector, a group's poses in registers), compiled here with the machine's
  C compiler (``cc -O3 -mavx2 -ffp-contract=off``, no FMA, as robkin) into a temporary folder and called
  through ctypes. It is not part of robkin.

Then the dynamics blocks (inverse dynamics ``rnea``, mass matrix ``crba``), portable against AVX2 only.

Interleaved rounds, medians of **CPU time of this thread** (``time.thread_time``: the machine's other
load shows up less than in wall time). The two robkin builds are checked to give identical bits, and
the floor to agree with them to 1e-12 (its sine/cosine skips robkin's exact reduction).

Goal (issue 24): robkin's AVX2 build within 1.3x of the floor.

Run: ``python benchmarks/bench_avx2.py [--quick]``. Exit status 0 whatever the timings, 1 if the bits
differ or the floor disagrees; 0 with a message when the CPU, the build or the compiler lacks AVX2.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread: the instruction set is measured, not the cores

import argparse  # noqa: E402
import ctypes  # noqa: E402
import glob  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import sysconfig  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

import robkin  # noqa: E402
from robkin.compiled.chain import kernels  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def robots_dir() -> str:
    found = glob.glob(os.path.join(sys.prefix, "lib", "python*", "site-packages", "cmeel.prefix", "share",
                                   "example-robot-data", "robots"))
    return found[0] if found else ""


def build_floor(folder: str) -> ctypes.CDLL | None:
    """Compile avx2_floor.c into a shared library in ``folder``; None without a C compiler."""
    cc = os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc"
    cc = cc.split()[0]
    if shutil.which(cc) is None:
        return None
    lib = os.path.join(folder, "avx2_floor.so")
    subprocess.run([cc, "-O3", "-mavx2", "-ffp-contract=off", "-fPIC", "-shared",
                    os.path.join(HERE, "avx2_floor.c"), "-o", lib], check=True)
    floor = ctypes.CDLL(lib)
    for fn in (floor.floor_fk, floor.floor_jacobian):
        fn.argtypes = [DOUBLE_P, ctypes.c_char_p, ctypes.c_int, DOUBLE_P, ctypes.c_long, DOUBLE_P]
        fn.restype = None
    return floor


def interleaved(fns: dict, rounds: int, repeat: int) -> dict:
    """Median CPU seconds of this thread per call of each function over ``rounds`` interleaved rounds
    (each round times ``repeat`` calls)."""
    times: dict = {k: [] for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            t0 = time.thread_time()
            for _ in range(repeat):
                fn()
            times[k].append((time.thread_time() - t0) / repeat)
    return {k: float(np.median(v)) for k, v in times.items()}


def robkin_call(robot: robkin.Robot, build: str, method: str, Q: np.ndarray, out: np.ndarray):
    def run():
        kernels.use(build)
        getattr(robot, method)(Q, threads=1, out=out)
    return run


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds")
    args = parser.parse_args(argv)
    path = os.path.join(robots_dir(), "panda_description/urdf/panda.urdf")
    if not os.path.isfile(path):
        print("example-robot-data's Panda is not installed: nothing to measure")
        return 0
    if not (kernels.cpu_has_avx2() and kernels.avx2_built()):
        print("this CPU or this build of robkin has no AVX2 kernels: nothing to compare")
        return 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robkin.load(path, tip_link="panda_hand_tcp")
    n = robot.n
    L = np.ascontiguousarray(robot._local, dtype=np.float64)
    rev = np.ascontiguousarray(robot.revolute, dtype=np.uint8).tobytes()
    rounds = 5 if args.quick else 15
    rng = np.random.default_rng(0)
    status = 0
    before = kernels.active()
    with tempfile.TemporaryDirectory() as tmp:
        floor = build_floor(tmp)
        if floor is None:
            print("no C compiler: no floor to compare with")
            return 0
        print(f"Panda, n = {n}, one thread, CPU time (time.thread_time), median of {rounds} interleaved rounds")
        print(f"{'kernel':<10}{'N':>8}{'portable us':>13}{'AVX2 us':>10}{'floor us':>10}{'AVX2/floor':>12}"
              f"{'portable/AVX2':>15}")
        for N in (1_000, 10_000, 100_000):
            Q = np.ascontiguousarray(robot.random_q(N, rng))
            for method, shape, fn in (("fk", (N, 4, 4), floor.floor_fk),
                                      ("jacobian", (N, 6, n), floor.floor_jacobian)):
                outs = {k: np.empty(shape) for k in ("portable", "avx2", "floor")}
                Fo = outs["floor"]
                fns = {"portable": robkin_call(robot, "portable", method, Q, outs["portable"]),
                       "avx2": robkin_call(robot, "avx2", method, Q, outs["avx2"]),
                       "floor": lambda fn=fn, Fo=Fo: fn(L.ctypes.data_as(DOUBLE_P), rev, n,
                                                          Q.ctypes.data_as(DOUBLE_P), N,
                                                          Fo.ctypes.data_as(DOUBLE_P))}
                repeat = max(1, 20_000 // N)
                t = interleaved(fns, rounds, repeat)
                if not np.array_equal(outs["portable"], outs["avx2"]):
                    print(f"{method} N={N}: the portable and AVX2 builds differ")
                    status = 1
                if not np.allclose(outs["floor"], outs["avx2"], rtol=0, atol=1e-12):
                    print(f"{method} N={N}: the floor disagrees with robkin")
                    status = 1
                print(f"{method:<10}{N:>8}{t['portable'] * 1e6:>13.1f}{t['avx2'] * 1e6:>10.1f}"
                      f"{t['floor'] * 1e6:>10.1f}{t['avx2'] / t['floor']:>12.2f}"
                      f"{t['portable'] / t['avx2']:>15.2f}")
        for N in (1_000, 10_000, 100_000):      # and the dynamics blocks (no floor written for them)
            Q, QD, QDD = (np.ascontiguousarray(robot.random_q(N, rng)) for _ in range(3))
            for method, args_ in (("rnea", (Q, QD, QDD)), ("crba", (Q,))):
                call = robot.inverse_dynamics if method == "rnea" else robot.mass_matrix
                got: dict = {}

                def run(build, call=call, args_=args_, got=got):
                    kernels.use(build)
                    got[build] = call(*args_, threads=1)
                t = interleaved({b: (lambda b=b: run(b)) for b in ("portable", "avx2")}, rounds,
                                max(1, 20_000 // N))
                if not np.array_equal(got["portable"], got["avx2"]):
                    print(f"{method} N={N}: the portable and AVX2 builds differ")
                    status = 1
                print(f"{method:<10}{N:>8}{t['portable'] * 1e6:>13.1f}{t['avx2'] * 1e6:>10.1f}{'-':>10}{'-':>12}"
                      f"{t['portable'] / t['avx2']:>15.2f}")
    kernels.use(before)
    return status


if __name__ == "__main__":
    sys.exit(main())
