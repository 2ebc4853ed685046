"""The GUI server under load: a few thousand requests from a handful of concurrent loopback clients.

Starts ``robkin gui``'s server in this process on 127.0.0.1 (a free port), then ``--clients`` threads
each send ``--requests`` requests over their own keep-alive connection, a mix of what the page does:
static files, ``/api/start``, ``POST /api/describe`` of the bundled RRPR robot at a random q (the
slider case) and a few refused cross-origin POSTs. While that runs, ``--slow`` extra clients hold
half-sent requests open, to show that they do not stall the others. Reported: requests per second and
the latency median, p99 and maximum per kind; every answer is checked (status and body), and any
failure is counted.

Run: ``.venv/bin/python benchmarks/bench_gui_load.py [--clients 6] [--requests 500] [--slow 3]``.
Loopback only, a bounded loop; exit status 0 unless a request failed.
"""

from __future__ import annotations

import argparse
import http.client
import json
import random
import socket
import statistics
import sys
import threading
import time
from collections import defaultdict
from pathlib import Path

import robkin
from robkin.viz.gui import make_server

RRPR = (Path(robkin.__file__).parent / "examples" / "rrpr.yaml").read_text()


def _client(port: int, n: int, seed: int, lat: dict[str, list[float]], failures: list[str]) -> None:
    rng = random.Random(seed)
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    origin = f"http://127.0.0.1:{port}"
    for _ in range(n):
        kind = rng.choices(["static", "start", "describe", "cross-origin"], weights=[3, 1, 5, 1])[0]
        headers = {"Host": f"127.0.0.1:{port}"}
        if kind == "static":
            method, path, body = "GET", rng.choice(["/", "/static/app.js", "/static/style.css"]), None
        elif kind == "start":
            method, path, body = "GET", "/api/start", None
        else:
            q = [rng.uniform(-1, 1) for _ in range(4)]
            body = json.dumps({"text": RRPR, "q": q}).encode()
            method, path = "POST", "/api/describe"
            headers.update({"Content-Type": "application/json",
                            "Origin": origin if kind == "describe" else "http://evil.example"})
        t0 = time.perf_counter()
        try:
            conn.request(method, path, body=body, headers=headers)
            resp = conn.getresponse()
            data = resp.read()
        except (OSError, http.client.HTTPException) as exc:
            failures.append(f"{kind}: {exc!r}")
            conn.close()
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
            continue
        lat[kind].append(time.perf_counter() - t0)
        expected = 403 if kind == "cross-origin" else 200
        if resp.status != expected or (kind == "describe" and not json.loads(data)["ok"]):
            failures.append(f"{kind}: status {resp.status}")
        if resp.getheader("Connection", "").lower() == "close":
            conn.close()
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    conn.close()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--clients", type=int, default=6)
    ap.add_argument("--requests", type=int, default=500, help="requests per client")
    ap.add_argument("--slow", type=int, default=3, help="clients that hold a half-sent request open")
    args = ap.parse_args()

    srv = make_server("127.0.0.1", 0)
    srv.serve_in_thread()
    port = srv.server_address[1]
    slow = [socket.create_connection(("127.0.0.1", port)) for _ in range(args.slow)]
    for s in slow:
        s.sendall(f"POST /api/describe HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Le".encode())
    lat: dict[str, list[float]] = defaultdict(list)
    failures: list[str] = []
    threads = [threading.Thread(target=_client, args=(port, args.requests, i, lat, failures))
               for i in range(args.clients)]
    t0 = time.perf_counter()
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    wall = time.perf_counter() - t0
    for s in slow:
        s.close()
    srv.shutdown()
    srv.server_close()

    every = sorted(x for v in lat.values() for x in v)
    print(f"{len(every)} requests from {args.clients} clients (+{args.slow} half-sent) in {wall:.1f} s: "
          f"{len(every) / wall:.0f} requests/s")
    print(f"{'kind':<13} {'count':>6} {'median ms':>10} {'p99 ms':>8} {'max ms':>8}")
    for kind, v in sorted(lat.items()) + [("all", every)]:
        v = sorted(v)
        p99 = v[min(len(v) - 1, int(0.99 * len(v)))]
        print(f"{kind:<13} {len(v):>6} {1e3 * statistics.median(v):>10.1f} {1e3 * p99:>8.1f} {1e3 * v[-1]:>8.1f}")
    print(f"failures: {len(failures)}" + (f" (first: {failures[0]})" if failures else ""))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
