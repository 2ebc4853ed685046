"""Smoke test of an installed robkin (CI runs it in a fresh venv holding only the wheel, outside the
source tree): the compiled core loads, convert, fk/ik, the HTML viewer and the GUI serving its page
and three.js all work. Exit status 0, or 1 with the first failure.

Usage: python smoke_installed.py SOURCE_TREE   (to check that robkin is not imported from it)
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import urllib.request
from pathlib import Path


def run(*args: str) -> str:
    done = subprocess.run([sys.executable, "-m", "robkin.cli", *args], capture_output=True, text=True, timeout=120)
    if done.returncode != 0:
        raise SystemExit(f"smoke: robkin {' '.join(args)}: exit {done.returncode}: {done.stderr.strip()}")
    return done.stdout


def main(source_tree: str) -> int:
    import robkin
    from robkin.compiled.chain import dh_chain  # noqa: F401  (the compiled core, from the wheel)

    where = Path(robkin.__file__).resolve()
    if Path(source_tree).resolve() in where.parents:
        raise SystemExit(f"smoke: robkin imported from the source tree ({where}), not from the install")
    print(f"smoke: robkin {robkin.__version__} from {where.parent}")
    example = where.parent / "examples" / "rrpr.yaml"
    with tempfile.TemporaryDirectory() as tmp:
        run("convert", str(example), "--to", "urdf", "-o", f"{tmp}/rrpr.urdf")
        T = json.loads(run("fk", f"{tmp}/rrpr.urdf", "--q", "0.3,-0.4,0.05,0.2", "--json"))["T"]
        pose = ",".join(repr(v) for row in T for v in row)
        q = json.loads(run("ik", str(example), "--pose", pose, "--json"))["solutions"][0]["q"]
        back = json.loads(run("fk", str(example), "--q", ",".join(map(repr, q)), "--json"))["T"]
        # 1e-9 m/rad: IK converges to rounding; a wrong installation misses by far more
        if max(abs(a - b) for ra, rb in zip(T, back) for a, b in zip(ra, rb)) > 1e-9:
            raise SystemExit("smoke: ik does not reproduce the pose fk gave")
        run("plot", str(example), "-o", f"{tmp}/rrpr.html")
        if "three" not in Path(f"{tmp}/rrpr.html").read_text(encoding="utf-8").lower():
            raise SystemExit("smoke: plot -o .html wrote a page without the three.js viewer")
    print("smoke: convert, fk, ik and plot -o .html work")

    from robkin.viz.gui import make_server

    server = make_server(port=0, text=example.read_text(), fmt="yaml")
    server.serve_in_thread()
    try:
        host = f"127.0.0.1:{server.server_address[1]}"
        for path in ("/", "/static/vendor/three.module.js", "/api/start"):
            req = urllib.request.Request(f"http://{host}{path}", headers={"Host": host})
            with urllib.request.urlopen(req, timeout=30) as answer:
                if answer.status != 200 or not answer.read():
                    raise SystemExit(f"smoke: GUI {path}: status {answer.status}")
    finally:
        server.shutdown()
        server.server_close()
    print("smoke: the GUI serves its page, three.js and the robot")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
