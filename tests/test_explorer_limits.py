"""The explorer's server under a careless or hostile client: foreign Host and Origin headers,
half-open sockets, too many connections, clients that go away, many distinct vase requests,
values that the ground truth would round out of range."""

from __future__ import annotations

import http.client
import io
import json
import math
import socket
import time
import urllib.parse

import pytest

from roughdiffuse.explorer import backend, make_server, serve_in_thread
from roughdiffuse.explorer.server import ExplorerHandler, ExplorerServer


@pytest.fixture
def server():
    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    yield srv
    srv.shutdown()
    srv.server_close()


def request(srv, path: str, headers: dict[str, str] | None = None) -> tuple[int, bytes]:
    host, port = srv.server_address[:2]
    conn = http.client.HTTPConnection(host, port, timeout=120)
    conn.putrequest("GET", path, skip_host=headers is not None and "Host" in headers)
    for k, v in (headers or {}).items():
        conn.putheader(k, v)
    conn.endheaders()
    r = conn.getresponse()
    body = r.read()
    conn.close()
    return r.status, body


def test_requests_addressed_to_the_server_are_served(server):
    port = server.server_address[1]
    assert request(server, "/")[0] == 200  # Host: 127.0.0.1:PORT, as printed
    assert request(server, "/", {"Host": f"localhost:{port}"})[0] == 200
    origin = {"Origin": f"http://127.0.0.1:{port}"}
    assert request(server, "/api/info.json", origin)[0] == 200


@pytest.mark.parametrize(
    "host",
    ["evil.example:{port}", "127.0.0.1:1", "rebind.attacker.test:{port}", "", "127.0.0.1"],
)
def test_a_foreign_host_header_is_refused(server, host):
    port = server.server_address[1]
    status, _ = request(server, "/api/info.json", {"Host": host.format(port=port)})
    assert status == 421


@pytest.mark.parametrize("origin", ["http://evil.example", "null", "https://127.0.0.1:{port}"])
def test_a_foreign_origin_is_refused(server, origin):
    port = server.server_address[1]
    status, _ = request(server, "/api/info.json", {"Origin": origin.format(port=port)})
    assert status == 403


def test_host_check_of_a_server_on_all_interfaces():
    srv = ExplorerServer.__new__(ExplorerServer)  # the check only, no socket
    srv.bound_host, srv.bound_port = "0.0.0.0", 8765
    assert srv.allowed_host("192.168.1.20:8765") and srv.allowed_host("[::1]:8765")
    assert not srv.allowed_host("attacker.test:8765") and not srv.allowed_host("10.0.0.1:80")


def test_a_half_open_socket_is_closed_after_the_idle_timeout(monkeypatch, server):
    monkeypatch.setattr(ExplorerHandler, "timeout", 0.5)
    s = socket.create_connection(server.server_address[:2], timeout=10)
    s.sendall(b"GET / HTTP/1.1\r\nHost: 127.0.0.1")  # never finished
    # b"": closed by the server; had it kept the socket, recv would raise at our own 10 s
    assert s.recv(1024) == b""
    s.close()


def test_connections_beyond_the_thread_bound_get_503():
    class Small(ExplorerServer):
        max_threads = 2

    srv = Small(("127.0.0.1", 0))
    serve_in_thread(srv)
    try:
        held = [socket.create_connection(srv.server_address[:2], timeout=10) for _ in range(2)]
        for s in held:
            s.sendall(b"GET / HTTP/1.1\r\n")  # half-open: each holds a thread
        time.sleep(0.3)
        extra = socket.create_connection(srv.server_address[:2], timeout=10)
        assert extra.recv(1024).startswith(b"HTTP/1.1 503")
        extra.close()
        for s in held:
            s.close()
    finally:
        srv.shutdown()
        srv.server_close()


def test_ctrl_c_while_a_handler_thread_starts_stops_the_server(monkeypatch):
    """CI's hang, replayed deterministically: a Ctrl-C lands in ``process_request`` after its
    handler thread has already run and released the slot. The interrupt must reach
    ``serve_forever``'s caller, not turn into "semaphore released too many times" (an
    ordinary exception that socketserver prints and then serves on), and the slot count must
    be whole again."""
    import socketserver
    import threading

    def start_then_interrupt(self, request, client_address):
        t = threading.Thread(target=self.process_request_thread, args=(request, client_address))
        t.start()
        t.join()  # the handler has finished and released its slot
        raise KeyboardInterrupt

    monkeypatch.setattr(socketserver.ThreadingMixIn, "process_request", start_then_interrupt)

    class Small(ExplorerServer):
        max_threads = 2

    srv = Small(("127.0.0.1", 0))
    client = socket.create_connection(srv.server_address[:2], timeout=10)
    client.sendall(b"GET / HTTP/1.0\r\nHost: %s:%d\r\n\r\n" % (b"127.0.0.1", srv.bound_port))
    try:
        with pytest.raises(KeyboardInterrupt):
            srv.handle_request()
        assert client.recv(12) == b"HTTP/1.0 200"
        # both slots are free again, and neither is freed twice
        assert srv._slots.acquire(blocking=False) and srv._slots.acquire(blocking=False)
        assert not srv._slots.acquire(blocking=False)
    finally:
        client.close()
        srv.server_close()


def test_a_client_that_goes_away_is_one_quiet_line(server, capsys):
    try:
        raise BrokenPipeError(32, "Broken pipe")
    except BrokenPipeError:
        server.handle_error(None, ("127.0.0.1", 5555))
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "went away" in err and "Traceback" not in err


def test_compiled_vase_variants_stay_bounded():
    clears = []
    variants = backend.CompiledVariants(maxsize=8, clear=lambda: clears.append(1))
    for i in range(50):  # 50 distinct (model, size) keys
        variants.use(("model", i))
        assert len(variants) <= 8
    assert len(clears) == 6  # emptied at the 9th, 17th, ..., 49th new key
    variants.use(("model", 49))  # in use: no new compile counted
    assert len(clears) == 6 and len(variants) == 2


def test_vase_sizes_are_a_fixed_set(server):
    status, body = request(server, "/api/vase.png?model=lambert&size=300")
    assert status == 400 and b"size must be one of" in body


def _rss_bytes() -> int:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmRSS")


def test_fifty_distinct_vase_requests_keep_memory_bounded(server):
    pytest.importorskip("PIL")
    try:
        _rss_bytes()
    except (OSError, RuntimeError):
        pytest.skip("needs /proc/self/status (Linux) to read the resident memory")
    q = "/api/vase.png?model=lambert&size=64&albedo={a},{a},{a}&light_theta={t}"
    assert request(server, q.format(a=0.5, t=10))[0] == 200  # compiles once
    before = _rss_bytes()
    for i in range(50):
        status, body = request(server, q.format(a=0.3 + 0.01 * i, t=i))
        assert status == 200 and body.startswith(b"\x89PNG")
    grown = _rss_bytes() - before
    # one compiled variant serves them all; 50 PNGs of 64x64 are a few kB each
    assert len(backend.VASE_VARIANTS) <= backend.VASE_COMPILED
    assert grown < 50e6, f"RSS grew by {grown / 1e6:.0f} MB over 50 requests"


def test_vase_with_a_non_finite_image_is_refused(server):
    status, body = request(server, "/api/vase.png?model=torrance-sparrow&eta=1e308&size=64")
    assert status == 400 and b"eta" in body


@pytest.mark.parametrize(
    ("query", "used"),
    [
        ({"sigma": "1.5707963", "theta_i": "30"}, {"sigma": math.pi / 2, "theta_i": 30.0}),
        ({"sigma": "0.3", "theta_i": "89.96"}, {"sigma": 0.3, "theta_i": 89.9}),
        ({"sigma": "0.00004", "theta_i": "10"}, {"sigma": 1e-4, "theta_i": 10.0}),
    ],
)
def test_ground_truth_validates_the_values_it_uses(monkeypatch, query, used):
    calls = []

    def fake(sigma, theta_i, albedo, bounces):
        calls.append((sigma, theta_i, albedo))
        return tuple(0.1 for _ in backend.THETA_R_DEG)

    monkeypatch.setattr(backend, "_plane_of_incidence", fake)
    monkeypatch.setattr(backend, "_solver", lambda: object())
    out = backend.ground_truth(query)
    ((sigma, theta_i, _),) = calls
    assert 0 < sigma <= math.pi / 2 and 0 <= theta_i < 90  # the solver's ranges
    assert sigma == pytest.approx(used["sigma"], abs=1e-12)
    assert theta_i == pytest.approx(used["theta_i"], abs=1e-12)
    assert (out["sigma"], out["theta_i"]) == (sigma, theta_i)  # reported as used


def test_ground_truth_still_refuses_out_of_range_values():
    for q in (
        {"sigma": "1.5708"},
        {"sigma": "0"},
        {"theta_i": "90"},
        {"albedo": "1.01"},
        {"bounces": "3"},
    ):
        with pytest.raises(ValueError, match=next(iter(q))):
            backend.ground_truth({**{"sigma": "0.3"}, **q})


def test_query_helper_quotes(server):
    # the page's own query (static/js/main.js queryFor) still passes the Host check
    port = server.server_address[1]
    q = urllib.parse.urlencode({"model": "lambert", "albedo": "1,1,1", "size": "64"})
    status, body = request(server, f"/api/vase.png?{q}", {"Host": f"127.0.0.1:{port}"})
    assert status == 200 and io.BytesIO(body).read(4) == b"\x89PNG"
    assert json.loads(request(server, "/api/info.json")[1])["vase"] is True
