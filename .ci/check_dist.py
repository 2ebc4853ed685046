"""Check a release (``make dist``): the wheel and the sdist carry the GUI's three.js modules and the
version of pyproject.toml; exit status 1 with one line per problem otherwise.

Usage: python .ci/check_dist.py DIST_FOLDER
"""

from __future__ import annotations

import re
import sys
import tarfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "src"))
from robkin.viz.assets import VENDOR  # noqa: E402  (the list of files the GUI serves)


def main(folder: str) -> int:
    version = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M).group(1)
    dist = Path(folder)
    wheels = sorted(dist.glob(f"robkin-{version}-*.whl"))
    sdists = sorted(dist.glob(f"robkin-{version}.tar.gz"))
    problems = [] if wheels and sdists else [f"{dist}: expected robkin-{version}-*.whl and robkin-{version}.tar.gz"]
    wanted = [f"robkin/viz/static/vendor/{name}" for name in VENDOR]
    for wheel in wheels:
        names = set(zipfile.ZipFile(wheel).namelist())
        problems += [f"{wheel.name}: {n} missing" for n in wanted if n not in names]
        if not any(n.startswith("robkin/compiled/") and n.endswith((".so", ".pyd")) for n in names):
            problems.append(f"{wheel.name}: no compiled core (robkin/compiled/*/*.so)")
    for sdist in sdists:
        names = {n.split("/", 1)[1] for n in tarfile.open(sdist).getnames() if "/" in n}
        problems += [f"{sdist.name}: src/{n} missing" for n in wanted if f"src/{n}" not in names]
    for p in problems:
        print(f"check_dist: {p}", file=sys.stderr)
    if not problems:
        print(f"check_dist: {', '.join(p.name for p in wheels + sdists)} carry the GUI's "
              f"{len(VENDOR)} three.js files and version {version}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "dist"))
