"""Check a release (``make dist``): the wheel and the sdist carry the GUI's three.js modules and the
version of pyproject.toml, and the wheel the GUI's own page and scripts; the wheel stays within its
budget (under 8 MB, none of the C that Cython generates nor other build byproducts in its compiled core:
the compiled modules are stripped of debug symbols) and the sdist carries the Cython sources it builds
from; exit status 1 with one line per problem otherwise.

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


# The wheel's budget: the 27 stripped modules (about 4 MB), three.js (2.4 MB) and the Python; the 22 MB
# of generated .c or 19 MB of debug symbols would each break it.
WHEEL_BUDGET = 8_000_000
# Build byproducts the wheel's compiled core must not carry: Cython's C and annotation pages, object files.
BYPRODUCTS = (".c", ".html", ".o", ".obj")
# The sources of the compiled core an sdist must carry (it is built from them).
CORE_SOURCES = (".pyx", ".pxd", ".pxi", ".h", ".pyi")


def core_sources() -> set[str]:
    """The compiled core's source files in this checkout, relative to src/."""
    compiled = ROOT / "src" / "robkin" / "compiled"
    return {str(p.relative_to(ROOT / "src")) for p in compiled.rglob("*")
            if p.suffix in CORE_SOURCES and p.is_file()}


def main(folder: str) -> int:
    version = re.search(r'^version = "([^"]+)"', (ROOT / "pyproject.toml").read_text(), re.M).group(1)
    dist = Path(folder)
    wheels = sorted(dist.glob(f"robkin-{version}-*.whl"))
    sdists = sorted(dist.glob(f"robkin-{version}.tar.gz"))
    problems = [] if wheels and sdists else [f"{dist}: expected robkin-{version}-*.whl and robkin-{version}.tar.gz"]
    wanted = [f"robkin/viz/static/vendor/{name}" for name in VENDOR]
    # the GUI's own page, scripts and style (index.html: the .html byproducts are refused in
    # robkin/compiled/ only)
    wanted += [f"robkin/viz/static/{p.name}" for p in sorted((ROOT / "src/robkin/viz/static").iterdir())
               if p.is_file()]
    for wheel in wheels:
        names = set(zipfile.ZipFile(wheel).namelist())
        problems += [f"{wheel.name}: {n} missing" for n in wanted if n not in names]
        if not any(n.startswith("robkin/compiled/") and n.endswith((".so", ".pyd")) for n in names):
            problems.append(f"{wheel.name}: no compiled core (robkin/compiled/*/*.so)")
        problems += [f"{wheel.name}: carries the build byproduct {n}" for n in sorted(names)
                     if n.startswith("robkin/compiled/") and n.endswith(BYPRODUCTS)]
        size = wheel.stat().st_size
        if size >= WHEEL_BUDGET:
            problems.append(f"{wheel.name}: {size / 1e6:.1f} MB, over the budget of {WHEEL_BUDGET / 1e6:.0f} MB")
    sources = core_sources()
    for sdist in sdists:
        names = {n.split("/", 1)[1] for n in tarfile.open(sdist).getnames() if "/" in n}
        problems += [f"{sdist.name}: src/{n} missing" for n in wanted if f"src/{n}" not in names]
        problems += [f"{sdist.name}: src/{n} missing" for n in sorted(sources) if f"src/{n}" not in names]
    for p in problems:
        print(f"check_dist: {p}", file=sys.stderr)
    if not problems:
        print(f"check_dist: {', '.join(p.name for p in wheels + sdists)} carry the GUI's "
              f"{len(VENDOR)} three.js files and version {version}; the wheel "
              f"{', '.join(f'{w.stat().st_size / 1e6:.1f} MB' for w in wheels)} (budget "
              f"{WHEEL_BUDGET / 1e6:.0f} MB) without build byproducts; the sdist with the core's "
              f"{len(sources)} Cython sources")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "dist"))
