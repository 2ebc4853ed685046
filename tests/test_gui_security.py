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
@pytest.fixture
def one_server():
    """A server on 127.0.0.1 only, for the tests that change its limits."""
    srv = make_server("127.0.0.1", 0)
    thread = srv.serve_in_thread()
    yield srv
    srv.shutdown()
    srv.server_close()
    thread.join(5)


def _half_sent(srv, count: int, kind: str) -> list[socket.socket]:
    """``count`` connections that start a request and stall: in its head, its body, or never reading."""
    held = []
    for _ in range(count):
        s = _connect(srv)
        if kind == "head":  # a request line and half a header, never finished
            s.sendall(f"POST /api/describe HTTP/1.1\r\nHost: {_host_header(srv)}\r\nContent-Len".encode())
        elif kind == "body":  # a whole head announcing 1000 bytes, then 10 of them
            s.sendall(f"POST /api/describe HTTP/1.1\r\nHost: {_host_header(srv)}\r\nContent-Length: 1000\r\n"
                      f"\r\n{{\"text\": \"".encode())
        held.append(s)
    return held


def test_half_sent_requests_do_not_block_others(server):
    slow = _half_sent(server, 4, "head")
    try:
        status, body = post(server, {"text": RRPR_TEXT})
        assert status == 200 and json.loads(body)["ok"] is True
    finally:
        for s in slow:
            s.close()


def test_sixty_held_open_requests_do_not_starve_the_server(one_server):
    # The security check's case: 60 half-sent requests (7x the worker threads), in the head and in the
    # body, then normal requests: each must be answered (the client's 10 s timeout would raise).
    slow = _half_sent(one_server, 30, "head") + _half_sent(one_server, 30, "body")
    try:
        for _ in range(3):
            status, body = post(one_server, {"text": RRPR_TEXT})
            assert status == 200 and json.loads(body)["ok"] is True
        assert raw(one_server, "GET", "/", {"Host": _host_header(one_server)})[0] == 200
        assert one_server.open_connections >= 60  # they are all still held, not dropped to make room
    finally:
        for s in slow:
            s.close()


def test_a_client_that_never_reads_its_answers_blocks_no_one(one_server):
    # Pipelined requests for the page whose answers are never read fill the socket buffers; the loop
    # stops writing to that client and goes on serving the others.
    greedy = _connect(one_server)
    try:
        greedy.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
        request = f"GET /static/app.js HTTP/1.1\r\nHost: {_host_header(one_server)}\r\n\r\n".encode()
        greedy.sendall(request * 50)
        status, body = post(one_server, {"text": RRPR_TEXT})
        assert status == 200 and json.loads(body)["ok"] is True
    finally:
        greedy.close()


def test_silent_and_trickling_clients_are_cut_off(one_server):
    one_server.request_timeout = 0.5
    one_server.max_request_seconds = 1.5
    with _connect(one_server) as silent:
        silent.sendall(b"GET / HTTP/1.1\r\n")
        assert silent.recv(100) == b""  # closed by the server (the 10 s client timeout would raise)
    with _connect(one_server) as trickle:
        closed = False
        for _ in range(40):  # one header byte every 0.25 s: each read is quick, the whole is endless
            try:
                trickle.sendall(b"X")
            except OSError:
                closed = True
                break
            time.sleep(0.25)
        assert closed or trickle.recv(100) == b""


def test_beyond_the_connection_limit_the_longest_silent_connection_makes_room(one_server):
    one_server.max_connections = 4
    held = _half_sent(one_server, 4, "head")
    try:
        time.sleep(0.2)  # the loop has accepted all four
        assert raw(one_server, "GET", "/", {"Host": _host_header(one_server)})[0] == 200
        assert held[0].recv(100) == b""  # the first (silent longest) was closed to make room
    finally:
        for s in held:
            s.close()


def test_buffered_bytes_are_bounded(one_server):
    one_server.max_buffered = 4096
    with _connect(one_server) as big:
        head = f"POST /api/describe HTTP/1.1\r\nHost: {_host_header(one_server)}\r\nContent-Length: 100000\r\n\r\n"
        try:
            big.sendall(head.encode() + b"x" * 100000)
        except OSError:  # the server may close before all is sent
            pass
        assert big.recv(100).startswith(b"HTTP/1.1 503")
    assert post(one_server, {"text": "x"})[0] == 200  # the others are served on


def test_expect_100_continue_is_answered_then_the_body_read(server):
    body = json.dumps({"text": RRPR_TEXT}).encode()
    head = (f"POST /api/describe HTTP/1.1\r\nHost: {_host_header(server)}\r\nContent-Length: {len(body)}\r\n"
            "Expect: 100-continue\r\nConnection: close\r\n\r\n")
    with _connect(server) as s:
        s.sendall(head.encode())
        assert s.recv(100).startswith(b"HTTP/1.1 100 Continue")
        s.sendall(body)
        data = b""
        while chunk := s.recv(65536):
            data += chunk
    assert data.startswith(b"HTTP/1.1 200") and b'"ok": true' in data


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


# ------------------------------------------------------------------------------------- hostile values
def test_a_400_digit_q_is_one_line_naming_q(server):
    status, body = post(server, {"text": RRPR_TEXT, "q": [10 ** 400, 0, 0, 0]})
    answer = json.loads(body)
    assert status == 200 and answer["ok"] is False
    assert answer["error"].startswith("q[0]: must be a finite number") and "internal" not in answer["error"]
    assert len(answer["error"]) < 200 and "\n" not in answer["error"]


@pytest.mark.parametrize("field", ["q0", "target"])
def test_huge_numbers_in_ik_requests_name_their_field(server, field):
    request = {"text": RRPR_TEXT, "q0": [0, 0, 0, 0], "target": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
    request[field] = [[10 ** 400] * 4] * 4 if field == "target" else [10 ** 400, 0, 0, 0]
    answer = json.loads(post(server, request, path="/api/ik")[1])
    assert answer["ok"] is False and answer["error"].startswith(f"{field}[0]") and "internal" not in answer["error"]


_URDF = ('<robot name="r"><link name="a"/><link name="b"/><joint name="j1" type="revolute"><parent link="a"/>'
         '<child link="b"/><origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>'
         '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')
_BIG = "x" * (3 * 1024 * 1024)  # a 3 MB attribute (the request limit is 4 MB of text)


@pytest.mark.parametrize("old, new, field", [
    ('xyz="0 0 0.1"', f'xyz="{_BIG}"', "origin xyz"),
    ('axis xyz="0 0 1"', f'axis xyz="{_BIG}"', "axis xyz"),
    ('type="revolute"', f'type="{_BIG}"', "unknown type"),
    ('parent link="a"', f'parent link="{_BIG}"', "parent link"),
    ('lower="-1"', f'lower="{_BIG}"', "limit lower"),
    ('xyz="0 0 0.1"', f'xyz="0 0 1{"0" * 3_000_000}"', "origin xyz"),
])
def test_a_huge_attribute_gives_one_short_line_naming_it(one_server, old, new, field):
    answer = json.loads(post(one_server, {"text": _URDF.replace(old, new)})[1])
    error = answer["error"]
    assert answer["ok"] is False and field in error and "joint 'j1'" in error
    assert len(error) < 200 and "\n" not in error, len(error)


def test_every_input_error_is_bounded():
    from robkin.errors import MAX_MESSAGE, InputError

    error = str(InputError("joint '" + _BIG + "': unknown type"))
    assert len(error) <= MAX_MESSAGE <= 400 and error.endswith("unknown type")
