"""``robkin gui``: a small local web app to load a robot, look at it in 3D and convert it.

A standard-library HTTP server (no web framework, nothing fetched from the internet) serves one page
(``static/index.html``, ``app.js``, ``viewer.js``, ``style.css``: a three.js 3D view with a draggable
tool frame, joint sliders, tables of every representation, downloads), the three.js modules of
``static/vendor/`` (see :mod:`robkin.viz.assets`), and a JSON API over :mod:`robkin.viz.gui_api`:

``GET /api/start``
    The robots given on the command line (if any), their visuals, and the bundled examples.
``GET /api/mesh/<id>``
    A mesh file of the command-line robot, by the id ``/api/start`` gave it (see ``meshes.py``).
``POST /api/describe`` ``{text, fmt, q, strict_q, overlay, base_link, tip_link, tool_row, other}``
    ``{"ok": true, ...describe()}`` or ``{"ok": false, "error": "one line"}``.
``POST /api/ik`` ``{text, fmt, base_link, tip_link, tool_row, target, q0}``
    ``{"ok": true, ...solve_ik()}`` or ``{"ok": false, "error"}``.
``POST /api/export`` ``{text, fmt, to, base_link, tip_link, tool_row}``
    ``{"ok": true, "filename", "mime", "content"}`` or ``{"ok": false, "error"}``.

Bad input is answered with ``ok: false`` and a message the page shows; an unexpected exception is
logged and answered the same way, so no request can stop the server. The server binds 127.0.0.1 by
default and, when bound to a loopback address, refuses requests whose Host header names another host
(a guard against DNS rebinding by web pages open in the same browser).
"""

from __future__ import annotations

import base64
import hashlib
import json
import re
import sys
import threading
import traceback
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

from ..errors import InputError
from .assets import STATIC_DIR, VENDOR, VENDOR_DIR
from .meshes import MeshRegistry

__all__ = ["GuiServer", "make_server", "STATIC_DIR"]

_STATIC_TYPES = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
                 ".css": "text/css; charset=utf-8", ".svg": "image/svg+xml", ".png": "image/png"}
_API = ("/api/describe", "/api/ik", "/api/export")

_LOOPBACK = ("127.0.0.1", "localhost", "::1", "[::1]")
#: Largest request body: the robot text limit plus room for the JSON wrapper and escaping.
_MAX_BODY = 10 * 1024 * 1024


def _inline_script_hashes() -> str:
    """CSP sources allowing index.html's inline import map (and nothing else inline)."""
    html = (STATIC_DIR / "index.html").read_text(encoding="utf-8")
    found = re.findall(r'<script type="importmap">(.*?)</script>', html, flags=re.S)
    return " ".join("'sha256-" + base64.b64encode(hashlib.sha256(t.encode()).digest()).decode() + "'"
                    for t in found)


class GuiServer(ThreadingHTTPServer):
    """The GUI's HTTP server; ``start`` holds the robot text to show first (may be empty)."""

    daemon_threads = True

    def __init__(self, address: tuple[str, int], start: dict[str, Any], quiet: bool = True,
                 meshes: MeshRegistry | None = None) -> None:
        super().__init__(address, _Handler)
        self.start_payload = start
        self.meshes = meshes or MeshRegistry()
        self.quiet = quiet
        self.script_src = f"'self' {_inline_script_hashes()}"

    @property
    def url(self) -> str:
        host, port = self.server_address[:2]
        host = f"[{host}]" if ":" in str(host) else host
        return f"http://{host}:{port}/"

    def serve_in_thread(self) -> threading.Thread:
        """Serve in a daemon thread (for tests and notebooks); stop with ``shutdown()``."""
        # poll every 50 ms (default 0.5 s) so that shutdown() returns quickly
        t = threading.Thread(target=self.serve_forever, kwargs={"poll_interval": 0.05}, name="robkin-gui",
                             daemon=True)
        t.start()
        return t


def make_server(host: str = "127.0.0.1", port: int = 8765, text: str = "", fmt: str = "auto",
                base_link: str | None = None, tip_link: str | None = None, source: str = "",
                quiet: bool = True, other: dict[str, str] | None = None) -> GuiServer:
    """A GUI server bound to (host, port); port 0 picks a free port (see ``server.url``).

    ``text`` is the robot shown when the page opens (with its ``fmt`` and URDF chain selectors);
    ``other`` ({text, fmt, source}) a second robot to compare it with (``robkin gui A B``).
    ``source`` is the file ``text`` was read from: only then are the meshes it references served.
    Raises InputError when the three.js modules are not installed (see ``robkin.viz.assets``).
    """
    from ..commands._common import EXAMPLES_DIR
    from .assets import require_assets
    from .gui_api import parse_robot

    require_assets()
    examples = {p.stem: p.read_text(encoding="utf-8") for p in sorted(EXAMPLES_DIR.glob("*.yaml"))}
    meshes = MeshRegistry()
    if text and source:
        meshes = MeshRegistry.of(parse_robot(text, fmt, base_link, tip_link, source=source)[0], Path(source))
    start = {"text": text, "fmt": fmt, "base_link": base_link or "", "tip_link": tip_link or "",
             "source": source, "examples": examples, "default_example": "rrpr", "other": other,
             "visuals": meshes.visuals, "missing_meshes": meshes.missing}
    try:
        return GuiServer((host, port), start, quiet=quiet, meshes=meshes)
    except OSError as exc:
        raise InputError(f"--port {port}: cannot listen on {host}:{port} ({exc.strerror or exc}); "
                         f"try another port or --port 0") from None


class _Handler(BaseHTTPRequestHandler):
    server: GuiServer
    server_version = "robkin-gui"
    protocol_version = "HTTP/1.1"
    # Headers and body go out as separate writes; with Nagle's algorithm the body then waits for the
    # client's delayed ACK (~40 ms on Linux), which would cap dragging to IK at ~20 updates/s.
    disable_nagle_algorithm = True

    # ----------------------------------------------------------------- plumbing
    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - signature of the base class
        if not self.server.quiet:
            super().log_message(format, *args)

    def _host_ok(self) -> bool:
        bound = self.server.server_address[0]
        if bound not in _LOOPBACK:
            return True  # the user chose to listen on a network address
        host = (self.headers.get("Host") or "").strip().lower()
        name = host.rsplit(":", 1)[0] if not host.startswith("[") else host.split("]")[0] + "]"
        return name in _LOOPBACK

    def _send(self, status: int, body: bytes, ctype: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.send_header("Content-Security-Policy",
                         f"default-src 'self'; script-src {self.server.script_src}; img-src 'self' data: blob:; "
                         "style-src 'self'; object-src 'none'")
        self.end_headers()
        if self.command != "HEAD":
            self.wfile.write(body)

    def _json(self, payload: dict[str, Any], status: int = 200) -> None:
        try:
            body = json.dumps(payload, allow_nan=False).encode()
        except ValueError:  # NaN/inf slipped into an answer: say so rather than send invalid JSON
            body = json.dumps({"ok": False, "error": "internal error (non-finite number in the answer)"}).encode()
        self._send(status, body, "application/json")

    # ----------------------------------------------------------------- routes
    def do_GET(self) -> None:  # noqa: N802 - http.server naming
        if not self._host_ok():
            return self._send(HTTPStatus.FORBIDDEN, b"forbidden host", "text/plain")
        path = self.path.split("?", 1)[0]
        if path == "/api/start":
            return self._json(self.server.start_payload)
        if path.startswith("/api/mesh/"):
            found = self.server.meshes.read(path.removeprefix("/api/mesh/"))  # an id, never a path
            if found is None:
                return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
            return self._send(HTTPStatus.OK, *found)
        name = "index.html" if path in ("/", "/index.html") else path.removeprefix("/static/")
        f = STATIC_DIR / name
        if name.startswith("vendor/") and name.removeprefix("vendor/") in VENDOR:
            f = VENDOR_DIR / name.removeprefix("vendor/")  # a name from the fixed list, never a request path
        # Else only plain files directly in static/ (no '/', no '..'): nothing else on disk is reachable.
        elif "/" in name or name.startswith("."):
            return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
        if f.suffix not in _STATIC_TYPES or not f.is_file():
            return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
        self._send(HTTPStatus.OK, f.read_bytes(), _STATIC_TYPES[f.suffix])

    do_HEAD = do_GET

    def do_POST(self) -> None:  # noqa: N802
        if not self._host_ok():
            return self._send(HTTPStatus.FORBIDDEN, b"forbidden host", "text/plain")
        path = self.path.split("?", 1)[0]
        if path not in _API:
            return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
        try:
            length = int(self.headers.get("Content-Length") or 0)
        except ValueError:
            length = -1
        if not 0 < length <= _MAX_BODY:
            self.close_connection = True
            return self._json({"ok": False, "error": f"request: body must be 1..{_MAX_BODY} bytes"}, 413)
        try:
            req = json.loads(self.rfile.read(length).decode("utf-8"))
            if not isinstance(req, dict):
                raise ValueError("not an object")
        except (ValueError, UnicodeDecodeError):
            return self._json({"ok": False, "error": "request: expected a JSON object"}, 400)
        self._json(self._answer(path, req))

    def _answer(self, path: str, req: dict[str, Any]) -> dict[str, Any]:
        from . import gui_api

        args = {"text": req.get("text", ""), "fmt": req.get("fmt") or "auto",
                "base_link": req.get("base_link") or None, "tip_link": req.get("tip_link") or None,
                "tool_row": req.get("tool_row") is True}
        try:
            if path == "/api/describe":
                return {"ok": True, **gui_api.describe(q=req.get("q"), strict_q=req.get("strict_q") is not False,
                                                       overlay=req.get("overlay"), other=req.get("other"), **args)}
            if path == "/api/ik":
                return {"ok": True, **gui_api.solve_ik(target=req.get("target"), q0=req.get("q0"), **args)}
            filename, mime, content = gui_api.export(to=str(req.get("to", "")), **args)
            return {"ok": True, "filename": filename, "mime": mime, "content": content}
        except InputError as exc:
            return {"ok": False, "error": str(exc)}
        except Exception as exc:  # a bug: keep serving, show it, log the traceback
            traceback.print_exc(file=sys.stderr)
            return {"ok": False, "error": f"internal error ({type(exc).__name__}: {exc}); please report it"}
