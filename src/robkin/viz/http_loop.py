"""The GUI server's connections: one thread reads and writes every socket without blocking; worker
threads see only whole requests.

A thread per connection (or a fixed pool of them reading sockets) lets a few dozen slow clients (half a
request line held open, a body trickling in a byte a second, an answer never read) take every thread
while an honest request waits behind them. Here the sockets are non-blocking and watched by one
selector in :meth:`ConnectionLoop.serve_forever`:

* **Accept** never blocks (the listening socket is non-blocking too). At most ``max_connections``
  are open; a new one beyond that evicts the connection that has been silent longest while half-read
  (or idle between requests), so new clients are always heard.
* **Read**: bytes are buffered until a request is whole: its head (at most ``MAX_HEAD`` bytes), then
  ``Content-Length`` bytes of body. The request policy (``http_policy.check_request``) is applied to
  the head before any body is invited (``Expect: 100-continue``) or waited for; a refused request is
  answered without reading its body.
* **Work**: a whole request goes to a pool of worker threads, which parse and answer it from memory
  (``handle(request_bytes, client_address) -> (response_bytes, close)``) and then send what the
  socket takes at once, never waiting on it.
* **Write**: the rest of the answer is sent by the loop as fast as the client reads it; a client that
  stops reading is cut off like a silent one.

Every connection is closed after ``request_timeout`` seconds without progress, and a request that is
not read and answered within ``max_request_seconds`` of its first byte is cut off however it trickles.
"""

from __future__ import annotations

import io
import selectors
import socket
import sys
import threading
import time
import traceback
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any, Callable

from .http_policy import MAX_BODY, check_request

__all__ = ["ConnectionLoop", "MAX_HEAD", "MAX_CONNECTIONS", "MAX_BUFFERED"]

#: Largest request head (request line and headers), as http.server's line limit: 64 KiB.
MAX_HEAD = 65536
#: Open connections at most (a browser uses up to six; the rest is room for other tabs and tools),
#: far below the usual 1024 file descriptors of a process.
MAX_CONNECTIONS = 256
#: Bytes buffered over all half-read requests: a few maximal bodies at once. A connection whose
#: bytes would pass it is answered 503, so memory stays bounded whatever the clients send.
MAX_BUFFERED = 4 * MAX_BODY

_Handle = Callable[[bytes, Any], "tuple[bytes, bool]"]


@dataclass(eq=False)
class _Conn:
    sock: socket.socket
    address: Any
    last: float                      #: time of the last progress (bytes read or written, accept)
    started: float | None = None     #: time the request under way began (None between requests)
    buf: bytearray = field(default_factory=bytearray)
    need: int | None = None          #: bytes of the request under way (head + body), once its head is read
    out: bytearray = field(default_factory=bytearray)
    state: str = "read"              #: read | work | write
    close_after: bool = False


def _plain(status: int, reason: str) -> bytes:
    body = reason.encode()
    return (f"HTTP/1.1 {status} {reason}\r\nContent-Type: text/plain; charset=utf-8\r\n"
            f"Content-Length: {len(body)}\r\nConnection: close\r\nX-Content-Type-Options: nosniff\r\n\r\n"
            ).encode() + body


class ConnectionLoop:
    """Serve HTTP/1.1 on a listening socket with one selector thread and a pool of workers (see module).

    Parameters
    ----------
    address : (host, port)
        Where to listen; port 0 picks a free port (see ``server_address``).
    handle : callable
        ``handle(request_bytes, client_address) -> (response_bytes, close)``, run in a worker thread
        for each whole request; ``close`` closes the connection after the answer.
    workers : int
        Worker threads.
    inline : callable, optional
        ``inline(request_bytes) -> bool``: requests answered in the loop thread itself, for those that
        take far less time than a hand-over to a worker (each thread hand-over can wait up to a GIL
        switch interval, 5 ms, while other threads compute): small static files, say.
    """

    request_timeout = 10.0
    max_request_seconds = 60.0
    max_connections = MAX_CONNECTIONS
    max_buffered = MAX_BUFFERED

    def __init__(self, address: tuple[str, int], handle: _Handle, workers: int,
                 inline: Callable[[bytes], bool] | None = None) -> None:
        family = socket.AF_INET6 if ":" in address[0] else socket.AF_INET
        self.socket = socket.socket(family, socket.SOCK_STREAM)
        try:
            self.socket.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            self.socket.bind(address)
            self.socket.listen(128)
            self.socket.setblocking(False)
        except OSError:
            self.socket.close()
            raise
        self.server_address = self.socket.getsockname()
        self._handle = handle
        self._inline = inline
        self._pool = ThreadPoolExecutor(workers, thread_name_prefix="robkin-gui-worker")
        self._conns: dict[socket.socket, _Conn] = {}
        self._done: deque[tuple[_Conn, bytes, bool]] = deque()
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._sel = selectors.DefaultSelector()
        self._sel.register(self.socket, selectors.EVENT_READ, "listen")
        self._sel.register(self._wake_r, selectors.EVENT_READ, "wake")
        self._stop = False
        self._running = threading.Event()
        self._stopped = threading.Event()
        self._stopped.set()
        self._buffered = 0

    # ------------------------------------------------------------------------------------ life cycle
    def serve_forever(self, poll_interval: float = 0.5) -> None:
        """Serve until ``shutdown()`` is called from another thread."""
        self._stop = False
        self._stopped.clear()
        self._running.set()
        try:
            while not self._stop:
                for key, mask in self._sel.select(self._next_timeout(poll_interval)):
                    if key.data == "listen":
                        self._accept()
                    elif key.data == "wake":
                        self._drain_wake()
                    else:
                        conn = key.data
                        if mask & selectors.EVENT_READ:
                            self._read(conn)
                        if mask & selectors.EVENT_WRITE and conn.sock in self._conns:
                            self._write(conn)
                self._finish_done()
                self._expire(time.monotonic())
        finally:
            self._running.clear()
            self._stopped.set()

    def shutdown(self) -> None:
        """Stop ``serve_forever`` (running in another thread) and wait until it has returned."""
        self._stop = True
        self._wake()
        if self._running.is_set():
            self._stopped.wait()

    def server_close(self) -> None:
        """Close the listening socket, every connection and the worker pool."""
        for conn in list(self._conns.values()):
            self._close(conn)
        for s in (self.socket, self._wake_r, self._wake_w):
            try:
                self._sel.unregister(s)
            except (KeyError, ValueError):
                pass
            s.close()
        self._sel.close()
        self._pool.shutdown(wait=False, cancel_futures=True)

    @property
    def open_connections(self) -> int:
        """Connections open now (for tests and diagnostics)."""
        return len(self._conns)

    # ------------------------------------------------------------------------------------ events
    def _next_timeout(self, poll_interval: float) -> float:
        now = time.monotonic()
        deadlines = [self._deadline(c) for c in self._conns.values() if c.state != "work"]
        return max(0.0, min([poll_interval, *(d - now for d in deadlines)]))

    def _deadline(self, conn: _Conn) -> float:
        end = conn.last + self.request_timeout
        if conn.started is not None:
            end = min(end, conn.started + self.max_request_seconds)
        return end

    def _expire(self, now: float) -> None:
        for conn in [c for c in self._conns.values() if c.state != "work" and self._deadline(c) <= now]:
            self._close(conn)

    def _accept(self) -> None:
        for _ in range(64):  # a burst of connections at most per wake-up, so reads keep going too
            try:
                sock, address = self.socket.accept()
            except (BlockingIOError, InterruptedError):
                return
            except OSError:  # e.g. out of file descriptors: try again on the next event
                return
            if len(self._conns) >= self.max_connections and not self._evict():
                sock.close()
                continue
            sock.setblocking(False)
            try:
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)  # answers leave at once
            except OSError:
                pass
            conn = _Conn(sock, address, last=time.monotonic())
            self._conns[sock] = conn
            self._sel.register(sock, selectors.EVENT_READ, conn)

    def _evict(self) -> bool:
        """Close the connection silent longest while reading (half-sent or idle); False if none is."""
        reading = [c for c in self._conns.values() if c.state == "read"]
        if not reading:
            return False
        self._close(min(reading, key=lambda c: c.last))
        return True

    def _read(self, conn: _Conn) -> None:
        try:
            data = conn.sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            data = b""
        if not data:
            self._close(conn)
            return
        if self._buffered + len(data) > self.max_buffered:
            self._answer_and_close(conn, _plain(503, "Service Unavailable"))
            return
        now = time.monotonic()
        conn.last = now
        if conn.started is None:
            conn.started = now
        conn.buf += data
        self._buffered += len(data)
        self._advance(conn)

    def _advance(self, conn: _Conn) -> None:
        """Hand the request under way to a worker once it is whole."""
        if conn.need is None:
            end = conn.buf.find(b"\r\n\r\n")
            if end < 0:
                end = conn.buf.find(b"\n\n")  # http.server accepts bare LF line ends too
                end = end + 2 if end >= 0 else -1
            else:
                end += 4
            if end < 0:
                if len(conn.buf) > MAX_HEAD:
                    self._answer_and_close(conn, _plain(431, "Request Header Fields Too Large"))
                return
            conn.need = end + self._body_length(conn, bytes(conn.buf[:end]))
        if len(conn.buf) < conn.need:
            return
        request = bytes(conn.buf[:conn.need])
        del conn.buf[:conn.need]
        self._buffered -= len(request)
        conn.need = None
        conn.state = "work"
        self._sel.unregister(conn.sock)
        if self._inline is not None and self._inline(request):
            self._work(conn, request)  # quick to answer: no hand-over to a worker thread
        else:
            self._pool.submit(self._work, conn, request)

    def _body_length(self, conn: _Conn, head: bytes) -> int:
        """Bytes of body to wait for: Content-Length if the policy lets the request through, else 0."""
        import http.client

        lines = head.split(b"\n", 1)
        method = lines[0].split(b" ", 1)[0].decode("latin-1")
        try:
            headers = http.client.parse_headers(io.BytesIO(lines[1] if len(lines) > 1 else b""))
        except (http.client.HTTPException, ValueError):
            return 0  # the handler answers the malformed head
        if check_request(method, headers, self.server_address[1]) is not None:
            return 0  # refused: the handler answers it without the body
        length = int(headers.get("Content-Length") or 0)  # the policy checked: one plain number
        if length and (headers.get("Expect") or "").strip().lower() == "100-continue":
            try:
                conn.sock.send(b"HTTP/1.1 100 Continue\r\n\r\n")
            except OSError:
                pass
        return length

    def _work(self, conn: _Conn, request: bytes) -> None:
        """In a worker thread: answer the request and send what the socket takes at once (the loop has
        put the connection aside meanwhile); the rest, and what comes next, goes back to the loop.

        Sending here saves the answer a hand-over to the loop thread, which costs up to a GIL switch
        interval (5 ms) when other threads are busy."""
        try:
            out, close = self._handle(request, conn.address)
        except Exception:  # noqa: BLE001 - a bug in a handler must not stop the server
            traceback.print_exc(file=sys.stderr)
            out, close = _plain(500, "Internal Server Error"), True
        try:
            sent = conn.sock.send(out) if out else 0
        except (BlockingIOError, InterruptedError):
            sent = 0
        except OSError:  # the client went away: nothing more to send
            sent, close = len(out), True
        self._done.append((conn, out[sent:], close))
        self._wake()

    def _finish_done(self) -> None:
        while self._done:
            conn, out, close = self._done.popleft()
            if conn.sock not in self._conns:
                continue
            conn.last = time.monotonic()
            if not out:
                if close:
                    self._close(conn)
                else:
                    self._next_request(conn)
                continue
            conn.state, conn.out, conn.close_after = "write", bytearray(out), close
            self._sel.register(conn.sock, selectors.EVENT_WRITE, conn)
            self._write(conn)

    def _next_request(self, conn: _Conn, registered: bool = False) -> None:
        """Back to reading the connection's next request (already under way if pipelined)."""
        conn.state, conn.started = "read", (conn.last if conn.buf else None)
        if registered:
            self._sel.modify(conn.sock, selectors.EVENT_READ, conn)
        else:
            self._sel.register(conn.sock, selectors.EVENT_READ, conn)
        if conn.buf:  # a pipelined request arrived with the previous one
            self._advance(conn)

    def _write(self, conn: _Conn) -> None:
        try:
            sent = conn.sock.send(conn.out)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            self._close(conn)
            return
        del conn.out[:sent]
        conn.last = time.monotonic()
        if conn.out:
            return
        if conn.close_after:
            self._close(conn)
            return
        self._next_request(conn, registered=True)

    def _answer_and_close(self, conn: _Conn, response: bytes) -> None:
        """Answer from the loop (refusals that need no handler) and close after sending."""
        self._buffered -= len(conn.buf)
        conn.buf.clear()
        conn.need = None
        conn.state, conn.out, conn.close_after = "write", bytearray(response), True
        self._sel.modify(conn.sock, selectors.EVENT_WRITE, conn)
        self._write(conn)

    def _close(self, conn: _Conn) -> None:
        if self._conns.pop(conn.sock, None) is None:
            return
        self._buffered -= len(conn.buf)
        conn.buf.clear()
        if conn.state != "work":
            try:
                self._sel.unregister(conn.sock)
            except (KeyError, ValueError):
                pass
        try:
            conn.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        conn.sock.close()

    def _wake(self) -> None:
        try:
            self._wake_w.send(b"x")
        except OSError:  # the wake-up buffer is full (the loop is awake anyway) or closed
            pass

    def _drain_wake(self) -> None:
        try:
            while self._wake_r.recv(4096):
                pass
        except OSError:
            pass
