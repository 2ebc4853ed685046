"""Which HTTP requests the GUI server answers: one policy, applied to every request before routing.

The GUI serves this machine only, and only its own page. A web page on another site, open in the same
browser, can still send requests to ``http://127.0.0.1:PORT`` (a cross-site form POST, a ``fetch``) or
rebind a domain name of its own to 127.0.0.1 (DNS rebinding). ``check_request`` refuses both:

* **Host**: exactly one ``Host`` header, parsed strictly (``name[:port]`` or ``[ipv6][:port]``, nothing
  else: no userinfo, no path, no trailing garbage such as ``[::1]evil.com`` or ``localhost:PORT@evil.com``),
  naming a loopback address (127.0.0.0/8, ::1) or ``localhost``, with the server's port. A rebound
  domain name never passes, so a foreign page cannot read answers.
* **Origin**: on every request that can change something or carry data (any method but GET, HEAD and
  OPTIONS) and on any ``Upgrade`` (websocket) request, an ``Origin`` header, when present, must be this
  very server (``http://`` + the Host header); ``Origin: null`` (sandboxed frames, files) is refused.
  ``Sec-Fetch-Site``, when present, must be ``same-origin`` or ``none`` (typed by the user). Browsers
  send ``Origin`` with every cross-origin POST, so a request without it comes from a program on this
  machine (curl, a test), which could read the files directly anyway.
* **Body**: no ``Transfer-Encoding`` (chunked bodies are not needed), ``Content-Length`` a plain number
  of at most ``MAX_BODY`` bytes, and required for POST.

The server (``robkin.viz.gui``) calls ``check_request`` from its handler's ``parse_request``, i.e. for
every request of every method before any ``do_GET``/``do_POST`` runs. **A new route is therefore
protected without doing anything**: add it to ``do_GET`` (read-only answers) or ``do_POST`` (anything
that takes input), never to a route that changes state on GET. Static files are looked up only with
``static_file`` (resolved, then checked to lie inside the static folder). The connection loop
(``robkin.viz.http_loop``) also applies ``check_request`` to each request head before it reads or invites
the body. Timeouts and the worker count (``REQUEST_TIMEOUT``, ``MAX_CONNECTION_SECONDS``, ``MAX_WORKERS``)
are defined here and used by the server.
"""

from __future__ import annotations

import ipaddress
import re
from pathlib import Path
from typing import TYPE_CHECKING, NamedTuple

if TYPE_CHECKING:  # pragma: no cover
    from email.message import Message

__all__ = ["Refusal", "check_request", "is_loopback", "parse_host", "static_file", "MAX_BODY",
           "REQUEST_TIMEOUT", "MAX_CONNECTION_SECONDS", "MAX_WORKERS"]

#: Largest request body: the GUI's robot text limit (4 MB) plus room for the JSON wrapper and escaping.
MAX_BODY = 10 * 1024 * 1024
#: Seconds a connection may stay silent (per read or write) before it is closed: far more than any
#: loopback client needs between two packets, short enough that idle keep-alive connections and
#: half-sent requests give their worker back soon.
REQUEST_TIMEOUT = 10.0
#: Longest time one request may take to arrive and its answer to leave (seconds), however it trickles
#: its bytes: a slow client that sends one byte every few seconds is cut off here. Far above the slowest honest request (a large URDF
#: with every representation takes about a second).
MAX_CONNECTION_SECONDS = 60.0
#: Worker threads answering whole requests (the connection loop reads and writes the sockets, so an
#: idle or slow connection never holds one); more requests wait in the pool's queue.
MAX_WORKERS = 8
#: METHODS that only read: no Origin check (navigations and ``<script>`` loads carry foreign Origins).
_SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
#: ``host[:port]``: a bracketed IPv6 literal or a plain name / IPv4 address, then an optional port.
_HOST_RE = re.compile(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9.-]+)(?::([0-9]{1,5}))?")


class Refusal(NamedTuple):
    """Why a request is refused: HTTP status and a one-line reason (sent as the plain-text body)."""

    status: int
    reason: str


def is_loopback(host: str) -> bool:
    """True for ``localhost`` and every loopback address (127.0.0.0/8, ::1), brackets allowed."""
    name = host.strip().lower().removeprefix("[").removesuffix("]")
    if name in ("localhost", "localhost."):
        return True
    try:
        return ipaddress.ip_address(name).is_loopback
    except ValueError:
        return False


def parse_host(value: str) -> tuple[str, int | None] | None:
    """(host, port or None) of a Host header value, or None if it is not exactly ``host[:port]``."""
    m = _HOST_RE.fullmatch(value.strip())
    if m is None:
        return None
    return m.group(1).lower(), None if m.group(2) is None else int(m.group(2))


def _host_refusal(headers: Message, server_port: int) -> Refusal | None:
    values = headers.get_all("Host") or []
    if len(values) != 1:
        return Refusal(400, "exactly one Host header is needed")
    parsed = parse_host(values[0])
    if parsed is None or not is_loopback(parsed[0]):
        return Refusal(403, "forbidden host: this server answers requests for a loopback address only")
    port = 80 if parsed[1] is None else parsed[1]
    if port != server_port:
        return Refusal(403, f"forbidden host: wrong port (this server listens on {server_port})")
    return None


def _origin_refusal(headers: Message) -> Refusal | None:
    site = headers.get("Sec-Fetch-Site")
    if site is not None and site.strip().lower() not in ("same-origin", "none"):
        return Refusal(403, "cross-site request refused: only this page may send requests")
    origin = headers.get_all("Origin") or []
    if not origin:
        return None
    expected = "http://" + (headers.get("Host") or "").strip().lower()
    if len(origin) != 1 or origin[0].strip().lower() != expected:
        return Refusal(403, "cross-origin request refused: only this page may send requests")
    return None


def _body_refusal(method: str, headers: Message) -> Refusal | None:
    if headers.get("Transfer-Encoding") is not None:
        return Refusal(501, "Transfer-Encoding is not supported; send a Content-Length")
    lengths = headers.get_all("Content-Length") or []
    if not lengths:
        return Refusal(411, "POST needs a Content-Length") if method == "POST" else None
    if len(lengths) != 1 or not lengths[0].strip().isdigit() or not lengths[0].isascii():
        return Refusal(400, "Content-Length must be one plain number")
    if int(lengths[0]) > MAX_BODY:
        return Refusal(413, f"request body larger than {MAX_BODY} bytes")
    return None


def check_request(method: str, headers: Message, server_port: int) -> Refusal | None:
    """None if the request may be routed; else the status and reason to answer it with (see module)."""
    refusal = _host_refusal(headers, server_port)
    if refusal is None and (method not in _SAFE_METHODS or headers.get("Upgrade") is not None):
        refusal = _origin_refusal(headers)
    if refusal is None:
        refusal = _body_refusal(method, headers)
    return refusal


def static_file(root: Path, relative: str) -> Path | None:
    """The file ``relative`` (URL-decoded, '/'-separated) inside the folder ``root``, or None.

    None unless the resolved path (symbolic links followed) is a regular file inside the resolved
    ``root`` and no part of it is hidden (starts with '.'): ``..``, absolute paths, encoded slashes
    and links pointing out of the folder all end here.
    """
    from urllib.parse import unquote

    name = unquote(relative)
    if not name or "\x00" in name or "\\" in name:
        return None
    base = root.resolve()
    try:
        path = (base / name).resolve()
        inside = path.relative_to(base)
    except (ValueError, OSError, RuntimeError):  # outside the folder, or a symlink loop
        return None
    if any(part.startswith(".") for part in inside.parts) or not path.is_file():
        return None
    return path
