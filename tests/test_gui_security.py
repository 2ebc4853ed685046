"""The GUI server's request policy, timeouts and static files, exercised over real loopback sockets.

Every loopback address the machine lets us bind is tried (127.0.0.1, 127.0.0.2, ::1): requests with a
foreign or malformed Host header and cross-origin POSTs are refused, same-origin ones answered; slow
clients do not block others and are cut off; nothing outside the static folder is served.
"""

from __future__ import annotations

import json
import socket
import time
from pathlib import Path

import pytest

import robkin
from robkin.cli import main
from robkin.viz import gui, http_policy
from robkin.viz.gui import make_server
from robkin.viz.http_policy import is_loopback, parse_host, static_file

RRPR_TEXT = (Path(robkin.__file__).parent / "examples" / "rrpr.yaml").read_text()


def _bindable(host: str) -> bool:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    try:
        with socket.socket(family) as s:
            s.bind((host, 0))
        return True
    except OSError:
        return False


HOSTS = [h for h in ("127.0.0.1", "127.0.0.2", "::1") if _bindable(h)]


@pytest.fixture(params=HOSTS)
def server(request):
    srv = make_server(request.param, 0)
    thread = srv.serve_in_thread()
    yield srv
    srv.shutdown()
    srv.server_close()
    thread.join(5)


def _addr(srv) -> tuple[str, int]:
    return srv.server_address[0], srv.server_address[1]


def _host_header(srv) -> str:
    host, port = _addr(srv)
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


def _connect(srv, timeout: float = 10.0) -> socket.socket:
    return socket.create_connection(_addr(srv), timeout=timeout)


def raw(srv, method: str, path: str, headers: dict[str, str] | list[tuple[str, str]] | None = None,
        body: bytes = b"") -> tuple[int, bytes]:
    """Send one request exactly as given (no header added but Connection: close); (status, body)."""
    items = list(headers.items()) if isinstance(headers, dict) else list(headers or [])
    head = f"{method} {path} HTTP/1.1\r\n" + "".join(f"{k}: {v}\r\n" for k, v in items)
    with _connect(srv) as s:
        s.sendall((head + "Connection: close\r\n\r\n").encode("latin-1") + body)
        data = b""
        while chunk := s.recv(65536):
            data += chunk
    status_line, _, rest = data.partition(b"\r\n")
    return int(status_line.split()[1]), rest.partition(b"\r\n\r\n")[2]


def post(srv, payload: dict, extra: dict[str, str] | None = None, path: str = "/api/describe") -> tuple[int, bytes]:
    body = json.dumps(payload).encode()
    headers = {"Host": _host_header(srv), "Content-Type": "application/json", "Content-Length": str(len(body))}
    return raw(srv, "POST", path, {**headers, **(extra or {})}, body)


# ------------------------------------------------------------------------------------- Host header
def test_same_origin_requests_are_answered(server):
    status, body = raw(server, "GET", "/", {"Host": _host_header(server)})
    assert status == 200 and b"<html" in body.lower()
    origin = "http://" + _host_header(server)
    status, body = post(server, {"text": RRPR_TEXT}, {"Origin": origin, "Sec-Fetch-Site": "same-origin"})
    assert status == 200 and json.loads(body)["ok"] is True


def test_localhost_names_the_server_too(server):
    port = _addr(server)[1]
    for host in (f"localhost:{port}", f"LOCALHOST:{port}", f"127.0.0.1:{port}", f"[::1]:{port}"):
        assert raw(server, "GET", "/api/start", {"Host": host})[0] == 200, host


@pytest.mark.parametrize("host", ["evil.com", "evil.com:{port}", "[::1]evil.com", "[::1]evil.com:{port}",
                                  "localhost:{port}@evil.com", "localhost@evil.com:{port}",
                                  "127.0.0.1:{port}.evil.com", "127.0.0.1.evil.com:{port}", "localhost:{port}/x",
                                  "localhost:1", "localhost", "10.0.0.1:{port}", "0.0.0.0:{port}",
                                  "user@localhost:{port}", " ", "localhost:{port} localhost:{port}"])
def test_foreign_or_malformed_host_headers_are_refused(server, host):
    port = _addr(server)[1]
    status, body = raw(server, "GET", "/api/start", {"Host": host.format(port=port)})
    assert status == 403 and b"forbidden host" in body, (host, status, body)


def test_missing_or_repeated_host_header_is_refused(server):
    assert raw(server, "GET", "/", [])[0] == 400
    good = _host_header(server)
    assert raw(server, "GET", "/", [("Host", good), ("Host", "evil.com")])[0] == 400


# ------------------------------------------------------------------------------------- Origin
@pytest.mark.parametrize("extra", [{"Origin": "http://evil.com"}, {"Origin": "null"},
                                   {"Origin": "https://{host}"}, {"Origin": "http://{host}.evil.com"},
                                   {"Sec-Fetch-Site": "cross-site"}, {"Sec-Fetch-Site": "same-site"},
                                   {"Origin": "http://{host}", "Sec-Fetch-Site": "cross-site"}])
def test_cross_origin_posts_are_refused(server, extra):
    headers = {k: v.format(host=_host_header(server)) for k, v in extra.items()}
    for path in ("/api/describe", "/api/export", "/api/anything-added-later"):
        status, body = post(server, {"text": RRPR_TEXT, "to": "yaml"}, headers, path)
        assert status == 403 and b"refused" in body, (headers, path, status)


def test_cross_origin_post_is_refused_before_the_body_is_invited(server):
    headers = {"Host": _host_header(server), "Origin": "http://evil.com", "Content-Length": "10",
               "Expect": "100-continue"}
    status, body = raw(server, "POST", "/api/describe", headers)
    assert status == 403 and b"100 Continue" not in body


def test_cross_origin_websocket_upgrade_is_refused(server):
    headers = {"Host": _host_header(server), "Upgrade": "websocket", "Connection": "Upgrade",
               "Origin": "http://evil.com", "Sec-WebSocket-Version": "13", "Sec-WebSocket-Key": "x3JJHMbDL1EzLkh9GBhXDw=="}
    assert raw(server, "GET", "/ws", headers)[0] == 403


# ------------------------------------------------------------------------------------- bodies and fields
def test_bodies_need_a_plain_bounded_length(server):
    host = {"Host": _host_header(server)}
    assert raw(server, "POST", "/api/describe", host)[0] == 411
    assert raw(server, "POST", "/api/describe", {**host, "Transfer-Encoding": "chunked"}, b"0\r\n\r\n")[0] == 501
    assert raw(server, "POST", "/api/describe", {**host, "Content-Length": str(http_policy.MAX_BODY + 1)})[0] == 413
    assert raw(server, "POST", "/api/describe", {**host, "Content-Length": "+5"})[0] == 400


@pytest.mark.parametrize("field, value", [("text", ["a list"]), ("fmt", {"a": 1}), ("base_link", ["x"]),
                                          ("tip_link", 3), ("to", ["yaml"])])
def test_api_names_the_field_of_the_wrong_type(server, field, value):
    payload = {"text": RRPR_TEXT, "to": "yaml", field: value}
    for path in ("/api/describe", "/api/export"):
        status, body = post(server, payload, path=path)
        answer = json.loads(body)
        assert status == 200 and answer["ok"] is False, answer
        assert answer["error"].startswith(f"request.{field}: expected a string, got ") and "internal" not in answer["error"]


# ------------------------------------------------------------------------------------- slow clients
def test_half_sent_requests_do_not_block_others(server):
    slow = [_connect(server) for _ in range(4)]
    try:
        for s in slow:  # a request line and half a header, never finished
            s.sendall(f"POST /api/describe HTTP/1.1\r\nHost: {_host_header(server)}\r\nContent-Len".encode())
        status, body = post(server, {"text": RRPR_TEXT})
        assert status == 200 and json.loads(body)["ok"] is True
    finally:
        for s in slow:
            s.close()


def test_silent_and_trickling_clients_are_cut_off(server, monkeypatch):
    monkeypatch.setattr(gui._Handler, "timeout", 0.5)
    monkeypatch.setattr(gui, "MAX_CONNECTION_SECONDS", 1.5)
    with _connect(server) as silent:
        silent.sendall(b"GET / HTTP/1.1\r\n")
        assert silent.recv(100) == b""  # closed by the server (the 10 s client timeout would raise)
    with _connect(server) as trickle:
        closed = False
        for _ in range(40):  # one header byte every 0.25 s: each read is quick, the whole is endless
            try:
                trickle.sendall(b"X")
            except OSError:
                closed = True
                break
            time.sleep(0.25)
        assert closed or trickle.recv(100) == b""


def test_connections_beyond_the_queue_are_answered_503(monkeypatch):
    srv = make_server("127.0.0.1", 0)
    monkeypatch.setattr(srv, "_slots", gui.threading.BoundedSemaphore(1))
    thread = srv.serve_in_thread()
    try:
        with _connect(srv) as held:  # takes the only slot and never finishes its request
            held.sendall(b"GET / HTTP/1.1\r\n")
            time.sleep(0.2)
            assert raw(srv, "GET", "/", {"Host": _host_header(srv)})[0] == 503
    finally:
        srv.shutdown()
        srv.server_close()
        thread.join(5)


# ------------------------------------------------------------------------------------- static files
@pytest.mark.parametrize("path", ["/static/../gui.py", "/static/%2e%2e/gui.py", "/static/..%2fgui.py",
                                  "/static/%2e%2e%2f%2e%2e%2f__init__.py", "/static//etc/passwd",
                                  "/static/%2fetc%2fpasswd", "/static/..\\gui.py", "/../../etc/passwd",
                                  "/static/.hidden", "/static/app.js%00.png", "/gui.py", "/static/"])
def test_nothing_outside_the_static_folder_is_served(server, path):
    status, body = raw(server, "GET", path, {"Host": _host_header(server)})
    assert status == 404 and b"import" not in body and b"root:" not in body, (path, status)


def test_static_file_resolves_links_and_stays_inside(tmp_path):
    root = tmp_path / "static"
    (root / "sub").mkdir(parents=True)
    (root / "sub" / "ok.js").write_text("ok")
    (tmp_path / "secret.txt").write_text("secret")
    (root / "link.js").symlink_to(tmp_path / "secret.txt")
    assert static_file(root, "sub/ok.js") == (root / "sub" / "ok.js").resolve()
    assert static_file(root, "sub%2fok.js") == (root / "sub" / "ok.js").resolve()
    for bad in ("link.js", "../secret.txt", "sub/../../secret.txt", str(tmp_path / "secret.txt"), "", "sub",
                "%2e%2e/secret.txt"):
        assert static_file(root, bad) is None, bad


# ------------------------------------------------------------------------------------- parsing, --host
def test_host_parsing_is_strict():
    assert parse_host("localhost:8765") == ("localhost", 8765)
    assert parse_host("[::1]:80") == ("[::1]", 80)
    assert parse_host("127.0.0.2") == ("127.0.0.2", None)
    for bad in ("[::1]evil.com", "localhost:80@evil.com", "a b", "localhost:", "localhost:123456", "[::1", ""):
        assert parse_host(bad) is None, bad
    assert all(is_loopback(h) for h in ("127.0.0.1", "127.255.0.9", "::1", "[::1]", "localhost"))
    assert not any(is_loopback(h) for h in ("0.0.0.0", "10.0.0.1", "::", "evil.com", "localhost.evil.com", ""))


@pytest.mark.parametrize("host", ["0.0.0.0", "::", "192.168.1.10", "example.com"])
def test_gui_refuses_to_listen_beyond_loopback(host, capsys):
    assert main(["gui", "--host", host, "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"robkin: error: --host '{host}': not a loopback address") and len(err.splitlines()) == 1
