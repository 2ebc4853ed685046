"""``robkin plot -o robot.html``: the GUI's 3D viewer as one self-contained HTML file.

The page holds everything: the scene data (JSON), the robot file's meshes (base64, drawn as the GUI
draws them; the ones not found named in the page), the three.js modules and robkin's viewer. A file
opened from disk has no folder for ES modules to import from, so the modules are embedded as text
and a short loader turns each into a blob URL and maps its bare name to it (an import map, see
:func:`robkin.viz.assets.module_sources`). Nothing is fetched; the page works offline.
"""

from __future__ import annotations

import html
import json
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ..robot import Robot

__all__ = ["viewer_data", "viewer_page"]

#: robkin's own modules in the page (static/ file -> bare specifier); the first one is the entry point.
_APP_MODULES = {"standalone.js": "robkin/standalone.js", "viewer.js": "robkin/viewer.js",
                "meshes.js": "robkin/meshes.js"}

_LOADER = """\
const imports = {};
for (const s of document.querySelectorAll("script[type='text/x-robkin-module']")) {
  imports[s.dataset.name] = URL.createObjectURL(new Blob([s.textContent], {type: "text/javascript"}));
}
const map = document.createElement("script");
map.type = "importmap";
map.textContent = JSON.stringify({imports});
document.head.append(map);
const main = document.createElement("script");
main.type = "module";
main.textContent = 'import "robkin/standalone.js";';
document.head.append(main);
"""

_STYLE = """\
body { margin: 0; font: 14px/1.4 system-ui, sans-serif; color: #222; }
header { padding: 0.5em 1em; display: flex; gap: 0.4em; align-items: center; flex-wrap: wrap; }
h1 { font-size: 1.1em; margin: 0 1em 0 0; }
#view { position: relative; height: 72vh; border-top: 1px solid #ddd; border-bottom: 1px solid #ddd; }
#view canvas { display: block; width: 100%; height: 100%; }
.label3d { position: absolute; transform: translate(3px, -100%); font-size: 11px; white-space: nowrap; }
.label3d.axis { color: #1f4fe0; } .label3d.base { color: #000; } .label3d.differs { color: #e02020; font-weight: 700; }
.legend { padding: 0.3em 1em; display: flex; gap: 1em; flex-wrap: wrap; font-size: 0.85em; }
.k::before { content: ""; display: inline-block; width: 1.4em; height: 3px; margin-right: 0.3em; vertical-align: middle; }
.link::before { background: #3a3a3a; } .axis::before { background: #1f4fe0; }
.tool::before { background: #ff3fa4; } .base::before { background: #000; }
#overlays { display: contents; }
pre { margin: 0.5em 1em; font-size: 12px; }
#missing-meshes { margin: 0.3em 1em; color: #8a4b00; font-size: 0.9em; }
"""


def viewer_data(robots: Sequence[Robot], q: np.ndarray | None, overlay: Sequence[str], labels: Sequence[str],
                frames: bool = False, view: Sequence[float] | None = None,
                exaggerate: float | None = None, source: str | Path | None = None,
                package_paths: Mapping[str, Path] | None = None) -> dict[str, Any]:
    """What the page draws: the first robot's scene, and as dashed overlays its representations
    (``overlay``) or the other robots (each at the same q), like ``robkin plot``'s pictures.
    ``exaggerate`` (several robots): the others' differences from the first multiplied by it, and
    ``arrows`` (``robkin.viz.difference``) from the first robot's axes to theirs.

    ``source``: the file the first robot was read from; its visuals are drawn with the mesh files they
    name (found as :func:`robkin.io.meshes.files.resolve_meshes` finds them, with ``package_paths``), and
    ``missing_line`` says which were not found. Warns (one line) when some were not.
    """
    from .scene import build_scene, overlay_scenes

    robot = robots[0]
    Q = np.zeros(robot.n) if q is None else np.asarray(q, dtype=float)
    scene = build_scene(robot, Q, label=labels[0])
    arrows: list[dict[str, Any]] = []
    if len(robots) > 1:
        overlays = [build_scene(r, Q, label=label) for r, label in zip(robots[1:], labels[1:])]
        if exaggerate is not None:
            from .difference import difference_arrows
            from .difference import exaggerate as exaggerated

            arrows = [a.to_json() for s in overlays for a in difference_arrows(scene, s, exaggerate)]
            overlays = [exaggerated(scene, s, exaggerate) for s in overlays]
    else:
        overlays = overlay_scenes(robot, Q, [r for r in overlay if r != "gjd"])
    data = {"scene": scene.to_json(), "overlays": [s.to_json() for s in overlays],
            "scale": max(r.scale for r in robots), "show_frames": bool(frames),
            "view": list(view) if view is not None else None, "arrows": arrows,
            "visuals": [], "meshes": {}, "motions": None, "missing_line": None}
    if source is not None:
        data.update(_visuals(robot, Q, Path(source), package_paths))
    return data


def _visuals(robot: Robot, Q: np.ndarray, source: Path, package_paths: Mapping[str, Path] | None) -> dict[str, Any]:
    import warnings

    from ..bodies import body_motions  # type: ignore[import-not-found, unused-ignore]
    from .meshes import MAX_PAGE_MESH_BYTES, MeshRegistry

    reg = MeshRegistry.of(robot, source, package_paths)
    meshes, left = reg.embedded()
    line = reg.missing_line
    if left:
        names = [reg.files[i].name for i in left]
        note = (f"{len(left)} mesh file(s) left out, more than {MAX_PAGE_MESH_BYTES // 2 ** 20} MB in all: "
                f"{', '.join(names[:3])}{' ...' if len(names) > 3 else ''}")
        line = f"{line}; {note}" if line else f"{source}: {note}"
    if line:
        warnings.warn(line, UserWarning, stacklevel=3)
    visuals = [v for v in reg.visuals if v.get("mesh") is None or v["mesh"] in meshes]
    return {"visuals": visuals, "meshes": meshes, "missing_line": line,
            "motions": body_motions(robot, Q).tolist() if visuals else None}


def _embed(text: str) -> str:
    # A script element ends at the first "</script"; "<\/" means the same inside JS strings and
    # regular expressions, and JSON parses "\/" as "/".
    return text.replace("</", "<\\/")


#: JSON text inside a <script> element: '<' (so neither "</script" nor "<!--", which starts the HTML
#: parser's "script data escaped" state, where a following "<script" hides the element's end), and
#: '>' and '&' as well, written as JSON escapes; json.loads / JSON.parse give back the same strings.
_JSON_IN_HTML = {ord("<"): "\\u003c", ord(">"): "\\u003e", ord("&"): "\\u0026"}


def _embed_json(data: Any) -> str:
    """``data`` as JSON text safe inside a ``<script>`` element (names come from untrusted files)."""
    return json.dumps(data, allow_nan=False).translate(_JSON_IN_HTML)


def viewer_page(data: dict[str, Any], title: str, caption: str = "") -> str:
    """The HTML text of the self-contained viewer page for ``data`` (see :func:`viewer_data`)."""
    from .assets import module_sources

    modules = "\n".join(f'<script type="text/x-robkin-module" data-name="{html.escape(name)}">{_embed(src)}</script>'
                        for name, src in module_sources(_APP_MODULES).items())
    buttons = "".join(f'<button type="button" data-view="{v}">{v if v != "iso" else "reset"}</button>'
                      for v in ("fit", "iso", "front", "side", "top"))
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<style>
{_STYLE}</style>
</head>
<body data-state="loading">
<header><h1>{html.escape(title)}</h1>{buttons}</header>
<div id="view" aria-label="robot in 3D: left drag turns, right drag pans, wheel zooms"></div>
<div class="legend"><span class="k link">links</span><span class="k axis">joint axes (+ end longer)</span>
<span class="k tool">tool frame</span><span class="k base">base frame</span><span id="overlays"></span>
<span id="grid-unit"></span></div>
{f'<p id="missing-meshes">{html.escape(data["missing_line"])}</p>' if data.get("missing_line") else ""}
<pre>{html.escape(caption)}</pre>
<script type="application/json" id="robkin-data">{_embed_json(data)}</script>
{modules}
<script>
{_LOADER}</script>
</body>
</html>
"""
