"""``robkin gui``: a small local web app to load a robot, look at it in 3D and convert it.

A standard-library HTTP server (no web framework, nothing fetched from the internet) serves one page
(``static/index.html``, ``style.css``, ``app.js``, ``tables.js``, ``check.js``, ``dom.js``,
``viewer.js``, ``meshes.js``: a three.js 3D view with a draggable tool frame, joint sliders, tables of
every representation, downloads, the check against a second robot), the three.js modules of
``static/vendor/`` (see :mod:`robkin.viz.assets`), and a JSON API over :mod:`robkin.viz.gui_api`:

``GET /api/start``
    The robots given on the command line (if any), their visuals, and the bundled examples.
``GET /api/representations``
    The registered representations as the page shows them: its tables, overlay checkboxes and
    download buttons (see ``representations_api.py``).
``GET /api/mesh/<id>``
    A mesh file of the command-line robot, by the id ``/api/start`` gave it (see ``meshes.py``).
``POST /api/describe`` ``{text, fmt, q, strict_q, overlay, base_link, tip_link, tool_row, other, collision}``
    ``{"ok": true, ...describe()}`` or ``{"ok": false, "error": "one line"}``.
``POST /api/ik`` ``{text, fmt, base_link, tip_link, tool_row, target, q0[, arm_angle, collision]}``
    ``{"ok": true, ...solve_ik()}`` or ``{"ok": false, "error"}``.
``POST /api/collision`` ``{text, fmt, base_link, tip_link, tool_row, q}``
    ``{"ok": true, "q", "collision"}``: only the self-collision answer at q (``gui_api.collision_at``),
    which the page asks again for the q it shows while the robot's model is being built.
``POST /api/export`` ``{text, fmt, to, base_link, tip_link, tool_row}``
    ``{"ok": true, "filename", "mime", "content"}`` or ``{"ok": false, "error"}``.
``POST /api/workspace`` ``{text, fmt, base_link, tip_link, tool_row[, voxel, samples]}``
    ``{"ok": true, ...workspace_overlay()}``: the reachable voxels to draw (``workspace_api.py``).

``describe`` and ``ik`` with ``"collision": true`` also answer which links collide with each other at
the q shown (``collision_api.py``; the model of the command-line robot is built from its file's
collision meshes, registered here).

Bad input is answered with ``ok: false`` and a message the page shows; an unexpected exception is
logged and answered the same way, so no request can stop the server. The server binds loopback
addresses only (127.0.0.0/8, ::1, localhost) and answers only requests that pass
:func:`robkin.viz.http_policy.check_request` (a loopback Host header with this port; same-origin for
anything but GET/HEAD), checked on the request head before its body is read and again in
``parse_request`` before any route runs, so every route, present or future, is covered. Connections
are read and written by one non-blocking loop (:mod:`robkin.viz.http_loop`) and only whole requests
reach the worker threads, so slow clients cannot pin the server.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import re
import sys
import threading
import traceback
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler
from pathlib import Path
from typing import Any, Mapping

from ..errors import InputError, quote
from .http_loop import ConnectionLoop
from .http_policy import (MAX_BODY, MAX_CONNECTION_SECONDS, MAX_WORKERS, REQUEST_TIMEOUT, check_request,
                          is_loopback, static_file)
from .assets import STATIC_DIR, VENDOR
from .meshes import MeshRegistry

__all__ = ["GuiServer", "make_server", "STATIC_DIR"]

_STATIC_TYPES = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8",
                 ".css": "text/css; charset=utf-8", ".svg": "image/svg+xml", ".png": "image/png"}
#: Request fields that must be strings (or absent / null) when given.
_STRING_FIELDS = ("text", "fmt", "to", "base_link", "tip_link")
_API = ("/api/describe", "/api/ik", "/api/collision", "/api/export", "/api/workspace")


def _inline_script_hashes() -> str:
    """CSP sources allowing index.html's inline import map (and nothing else inline)."""
    html = (STATIC_DIR / "index.html").read_text(encoding="utf-8")
    found = re.findall(r'<script type="importmap">(.*?)</script>', html, flags=re.S)
    return " ".join("'sha256-" + base64.b64encode(hashlib.sha256(t.encode()).digest()).decode() + "'"
                    for t in found)


def _answered_inline(request: bytes) -> bool:
    """GET/HEAD of the page, its static files, /api/start and /api/representations: answered by the connection loop itself
    (a file read or a prepared answer, well under a millisecond); meshes (up to 64 MB) and the API's
    POSTs, which compute, go to the worker threads."""
    line = request[:request.find(b"\n")]
    return line.startswith((b"GET ", b"HEAD ")) and b" /api/mesh/" not in line


class GuiServer(ConnectionLoop):
    """The GUI's HTTP server; ``start_payload`` holds the robot text to show first (may be empty).

    One thread reads and writes every connection without blocking, and ``MAX_WORKERS`` threads
    answer whole requests (see :mod:`robkin.viz.http_loop`), so slow or stalled clients cost a buffer,
    never a thread. A connection is closed after ``request_timeout`` seconds without progress, and a
    request that takes longer than ``max_request_seconds`` to arrive and leave is cut off.
    """

    request_timeout = REQUEST_TIMEOUT
    max_request_seconds = MAX_CONNECTION_SECONDS

    def __init__(self, address: tuple[str, int], start: dict[str, Any], quiet: bool = True,
                 meshes: MeshRegistry | None = None) -> None:
        super().__init__(address, self._respond, MAX_WORKERS, inline=_answered_inline)
        self.start_payload = start
        self.meshes = meshes or MeshRegistry()
        self.quiet = quiet
        self.script_src = f"'self' {_inline_script_hashes()}"

    def _respond(self, request: bytes, client_address: Any) -> tuple[bytes, bool]:
        """Answer one whole request (in a worker thread): (response bytes, close the connection)."""
        handler = _Handler(request, client_address, self)
        return handler.wfile.getvalue(), bool(handler.close_connection)

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
                quiet: bool = True, other: dict[str, str] | None = None,
                package_paths: Mapping[str, Path] | None = None) -> GuiServer:
    """A GUI server bound to (host, port); port 0 picks a free port (see ``server.url``).

    ``text`` is the robot shown when the page opens (with its ``fmt`` and URDF chain selectors);
    ``other`` ({text, fmt, source}) a second robot to compare it with (``robkin gui A B``).
    ``source`` is the file ``text`` was read from: only then are the meshes it references served
    (``package_paths``: NAME -> folder of packages they name, as ``--package-path``).
    Raises InputError when the three.js modules are not installed (see ``robkin.viz.assets``).

    ``base_link``, ``tip_link``: the chain of a URDF, SDF or MJCF ``text``; ``quiet``: False logs each request
    to stderr.
    """
    from ..examples import EXAMPLES_DIR
    from .assets import require_assets
    from .gui_api import parse_robot

    if not is_loopback(host):
        raise InputError(f"host={host!r}: not a loopback address; the GUI serves this machine only "
                         f"(127.0.0.1, another 127.x.y.z, ::1 or localhost)")
    require_assets()
    examples = {p.stem: p.read_text(encoding="utf-8") for p in sorted(EXAMPLES_DIR.glob("*.yaml"))}
    meshes = MeshRegistry()
    if text and source:
        from .collision_api import register_source

        register_source(text, source, package_paths)
        meshes = MeshRegistry.of(parse_robot(text, fmt, base_link, tip_link, source=source)[0], Path(source),
                                 package_paths)
    start = {"text": text, "fmt": fmt, "base_link": base_link or "", "tip_link": tip_link or "",
             "source": source, "examples": examples, "default_example": "rrpr", "other": other,
             "visuals": meshes.visuals, "missing_meshes": meshes.missing,
             "missing_line": meshes.missing_line}
    try:
        return GuiServer((host, port), start, quiet=quiet, meshes=meshes)
    except OSError as exc:
        raise InputError(f"port={port}: cannot listen on {host}:{port} ({exc.strerror or exc}); "
                         f"try another port or port=0") from None


class _Handler(BaseHTTPRequestHandler):
    """One whole request, answered from memory: ``request`` is its bytes, the answer collects in ``wfile``.

    The connection loop (``http_loop``) has read the request and sends the answer; the handler never
    touches a socket, so it never waits for a client.
    """

    server: GuiServer
    server_version = "robkin-gui"
    protocol_version = "HTTP/1.1"

    # ----------------------------------------------------------------- plumbing
    def setup(self) -> None:
        self.rfile = io.BytesIO(self.request)
        self.wfile = io.BytesIO()

    def handle(self) -> None:
        self.close_connection = True  # unless the request asks to keep it open (handle_one_request)
        self.handle_one_request()

    def finish(self) -> None:
        """Nothing to flush or close: the loop sends ``wfile``'s bytes."""

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - signature of the base class
        if not self.server.quiet:
            super().log_message(format, *args)

    def parse_request(self) -> bool:
        """Parse the request line and headers, then apply the request policy before any route runs."""
        return super().parse_request() and self._allowed()

    def handle_expect_100(self) -> bool:
        """``Expect: 100-continue``: the loop has invited the body (after the same policy); just check."""
        return self._allowed()

    def _allowed(self) -> bool:
        """True if the request passes ``check_request``; else answer the refusal and close."""
        refusal = check_request(self.command, self.headers, self.server.server_address[1])
        if refusal is None:
            return True
        self.close_connection = True
        self._send(refusal.status, refusal.reason.encode(), "text/plain; charset=utf-8")
        return False

    def _send(self, status: int, body: bytes, ctype: str) -> None:
        self.send_response(status)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        if self.close_connection:  # e.g. a refused request whose body was not read
            self.send_header("Connection", "close")
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
        path = self.path.split("?", 1)[0].split("#", 1)[0]
        if path == "/api/start":
            return self._json(self.server.start_payload)
        if path == "/api/representations":
            from .representations_api import gui_representations

            return self._json(gui_representations())
        if path.startswith("/api/mesh/"):
            found = self.server.meshes.read(path.removeprefix("/api/mesh/"))  # an id, never a path
            if found is None:
                return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
            return self._send(HTTPStatus.OK, *found)
        f = None
        if path in ("/", "/index.html"):
            f = static_file(STATIC_DIR, "index.html")
        elif path.startswith("/static/"):
            name = path.removeprefix("/static/")
            # vendor/: only the fixed list of three.js modules; elsewhere nothing outside static/ is reachable
            if not name.startswith("vendor/") or name.removeprefix("vendor/") in VENDOR:
                f = static_file(STATIC_DIR, name)
        if f is None or f.suffix not in _STATIC_TYPES:
            return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
        self._send(HTTPStatus.OK, f.read_bytes(), _STATIC_TYPES[f.suffix])

    do_HEAD = do_GET

    def do_POST(self) -> None:  # noqa: N802
        path = self.path.split("?", 1)[0]
        if path not in _API:
            self.close_connection = True  # the body is not read
            return self._send(HTTPStatus.NOT_FOUND, b"not found", "text/plain")
        length = int(self.headers["Content-Length"])  # the request policy checked it (1 number <= MAX_BODY)
        if length == 0:
            return self._json({"ok": False, "error": f"request: body must be 1..{MAX_BODY} bytes"}, 400)
        try:
            req = json.loads(self.rfile.read(length).decode("utf-8"))
            if not isinstance(req, dict):
                raise ValueError("not an object")
        except (ValueError, UnicodeDecodeError, RecursionError):
            return self._json({"ok": False, "error": "request: expected a JSON object"}, 400)
        self._json(self._answer(path, req))

    def _answer(self, path: str, req: dict[str, Any]) -> dict[str, Any]:
        from . import gui_api

        for key in _STRING_FIELDS:
            if req.get(key) is not None and not isinstance(req[key], str):
                return {"ok": False, "error": f"request.{key}: expected a string, got {type(req[key]).__name__}"}
        args = {"text": req.get("text", ""), "fmt": req.get("fmt") or "auto",
                "base_link": req.get("base_link") or None, "tip_link": req.get("tip_link") or None,
                "tool_row": req.get("tool_row") is True}
        try:
            if path == "/api/describe":
                return {"ok": True, **gui_api.describe(q=req.get("q"), strict_q=req.get("strict_q") is not False,
                                                       overlay=req.get("overlay"), other=req.get("other"),
                                                       collision=req.get("collision") is True, **args)}
            if path == "/api/ik":
                return {"ok": True, **gui_api.solve_ik(target=req.get("target"), q0=req.get("q0"),
                                                       arm_angle=req.get("arm_angle"),
                                                       collision=req.get("collision") is True, **args)}
            if path == "/api/collision":
                return {"ok": True, **gui_api.collision_at(q=req.get("q"), **args)}
            if path == "/api/workspace":
                from .workspace_api import workspace_overlay

                return {"ok": True, **workspace_overlay(voxel=req.get("voxel"), samples=req.get("samples"), **args)}
            filename, mime, content = gui_api.export(to=str(req.get("to", "")), **args)
            return {"ok": True, "filename": filename, "mime": mime, "content": content}
        except InputError as exc:
            return {"ok": False, "error": str(exc)}
        except Exception as exc:  # a bug: keep serving, show it, log the traceback
            traceback.print_exc(file=sys.stderr)
            return {"ok": False, "error": f"internal error ({type(exc).__name__}: {quote(str(exc), 200)}); "
                                          f"please report it"}
