"""The explorer's local web server (standard library only).

It serves the static page in ``static/`` and small JSON/PNG endpoints under ``/api/``:

* ``/api/info.json``: what this server can do (``vase``: the Python renderer is importable;
  ``groundtruth``: the V-cavity solver is importable).
* ``/api/models``: every model of :mod:`roughdiffuse.registry`, the same JSON as
  ``roughdiffuse models --json`` plus each model's printed shader (``shader``) and the
  page's keys of its parameters (``state_keys``); the page builds its menus and sliders from
  it. ``/glsl/models.glsl`` is the models' GLSL, printed from their code
  (:mod:`roughdiffuse.explorer.shaders`), and ``/api/shader?p=<JSON record>`` the GLSL and
  uniform values of a model traced on the server for one parameter set (the coat).
* ``/api/vase.png?model=…&albedo=…``: the vase preset, rendered by :mod:`roughdiffuse.render`.
* ``/api/groundtruth.json?sigma=…&theta_i=…&albedo=…&bounces=1|all``: V-cavity radiance in
  the plane of incidence, one bounce or all, computed by :mod:`roughdiffuse.simulate` on
  request.
* ``/api/layeredtruth.json?model=coated&…&absorption=…&theta_i=…`` (the vase's parameters):
  the layered walk's radiance of that coat in the plane of incidence (:mod:`.layered_truth`).

and, for measured data (:mod:`roughdiffuse.explorer.datasets`; JSON answers, errors as
``{"error": message}`` with a 4xx status):

* ``POST /api/data?format=merl|csv&name=…``: the body is a MERL ``.binary`` file or a CSV of
  BRDF samples (at most :data:`~roughdiffuse.explorer.datasets.MAX_MERL_BYTES` or
  :data:`~roughdiffuse.explorer.datasets.MAX_CSV_BYTES` bytes: larger gets 413 unread, no
  ``Content-Length`` 411, a malformed file 400 naming what is wrong). It is parsed by
  :mod:`roughdiffuse.fit` and kept in memory (the last
  :data:`~roughdiffuse.explorer.datasets.DATASETS_KEPT` datasets); the answer is its summary
  (``id``, ``theta_i`` angles, sample counts, the models a fit may use).
* ``GET /api/data/slice?id=…&theta_i=…&delta_phi=…``: a MERL dataset's BRDF (RGB) along
  θr = −89°…89° at azimuth Δφ (θr > 0) and Δφ + 180° (θr < 0) from the light (the old
  name ``dphi=`` is read too).
* ``POST /api/fit`` with ``{"dataset": id, "model": registry id, "choices": {name: value}}``
  (``choices`` optional: the slot's menus, e.g. Coated's base): the fit of that model
  (values, standard errors, RMS, BIC) on at most
  :data:`~roughdiffuse.explorer.datasets.FIT_SAMPLES` samples.
* ``POST /api/rank`` with ``{"dataset": id, "models": [ids]}``: those models (at most
  :data:`~roughdiffuse.explorer.datasets.RANK_MODELS_AT_ONCE`) fitted and ranked by BIC.

One fit runs at a time (another gets 503 at once); at most :data:`UPLOADS_AT_ONCE` uploads
are read at once (more get 503), each within :data:`UPLOAD_SECONDS`. A POST carries the same
``Host`` and ``Origin`` checks as a GET, so another web page cannot post to the server
(its browser sends its own ``Origin``: 403).

It serves only its own files: a path with a ``..`` or ``.`` segment, an empty segment (``//``),
a backslash, a NUL, or anything that resolves outside ``static/`` gets 404; so does every
path that is not a regular file there (no directory listings). It binds to 127.0.0.1 unless
told otherwise.

It answers only requests addressed to it: the ``Host`` header must name the address it
printed (or ``localhost``, or a loopback address) with its port, else 421; an ``Origin``
header, when sent, must be ``http://`` and such a host, else 403. So neither another web page
nor a DNS-rebinding name can make the user's browser talk to it. A connection idle for
:data:`IDLE_TIMEOUT` seconds is closed, so is one whose request line and headers take more
than :data:`HEADER_SECONDS` in all (one byte every few seconds), at most :data:`MAX_THREADS`
requests are served at once (more get 503), every 4xx body is clipped
(:func:`~roughdiffuse.io.reading.clip_echo`), the layered truth refuses a coat beyond its cost
budget before any walk (:func:`~roughdiffuse.explorer.layered_truth.check_cost`), and a
client that goes away is one quiet line, not a traceback.
"""

from __future__ import annotations

import io
import ipaddress
import json
import mimetypes
import posixpath
import socket
import sys
import threading
import time
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, unquote, urlsplit

from .._validate import ParameterError
from .._version import version
from ..io.jsonfile import dumps
from ..io.reading import clip_echo, loads_json
from . import backend, datasets

__all__ = [
    "IDLE_TIMEOUT",
    "HEADER_SECONDS",
    "MAX_THREADS",
    "UPLOADS_AT_ONCE",
    "UPLOAD_SECONDS",
    "UPLOAD_SLOTS",
    "STATIC_DIR",
    "ExplorerHandler",
    "ExplorerServer",
    "make_server",
    "resolve_static",
]

IDLE_TIMEOUT = 15.0
"""Seconds a connection may stay silent (while sending its request) before it is closed."""

MAX_THREADS = 32
"""Requests served at once; a connection beyond them gets 503 and is closed."""

HEADER_SECONDS = 30.0
"""Seconds a client may take to send a request line and its headers, in all: a client that
sends one byte every few seconds (never silent for :data:`IDLE_TIMEOUT`) is cut off."""

UPLOADS_AT_ONCE = 2
"""Upload bodies read at once (each up to 36 MB in memory); more get 503."""

UPLOAD_SECONDS = 120.0
"""Seconds an upload may take to arrive in full (a trickling client is cut off: 408)."""

JSON_BODY_BYTES = 10_000
"""Largest JSON body of ``/api/fit`` and ``/api/rank``."""

UPLOAD_SLOTS = threading.BoundedSemaphore(UPLOADS_AT_ONCE)
"""Taken while an upload is read and parsed."""

STATIC_DIR = Path(__file__).resolve().parent / "static"
"""The page's files (shipped as package data)."""

CONTENT_TYPES = {
    ".html": "text/html; charset=utf-8",
    ".js": "text/javascript; charset=utf-8",
    ".css": "text/css; charset=utf-8",
    ".glsl": "text/plain; charset=utf-8",
    ".vert": "text/plain; charset=utf-8",
    ".frag": "text/plain; charset=utf-8",
    ".json": "application/json",
    ".png": "image/png",
    ".svg": "image/svg+xml",
}


def resolve_static(url_path: str, root: Path = STATIC_DIR) -> Path | None:
    """The file under ``root`` that ``url_path`` names, or ``None`` (-> 404).

    ``url_path`` is the path part of a request URL (percent-encoded). ``/`` is ``index.html``.
    Anything that could reach outside ``root`` is refused rather than normalised.
    """
    if not url_path.startswith("/"):
        return None  # absolute-form or garbage request targets
    path = unquote(url_path, errors="strict") if "%" in url_path else url_path
    if "\\" in path or "\0" in path:
        return None
    if path == "/":
        path = "/index.html"
    parts = path[1:].split("/")
    if any(p in ("", ".", "..") for p in parts):
        return None
    if posixpath.isabs(path[1:]):
        return None
    candidate = (root / Path(*parts)).resolve()
    try:
        candidate.relative_to(root.resolve())
    except ValueError:
        return None
    return candidate if candidate.is_file() else None


class ExplorerHandler(BaseHTTPRequestHandler):
    """GET and HEAD for the static page and the ``/api/`` endpoints, POST for the measured
    data endpoints; nothing else."""

    server_version = f"roughdiffuse-explorer/{version()}"
    quiet = True
    timeout = IDLE_TIMEOUT  # socket timeout: a half-open connection does not hold a thread

    _header_deadline: float | None = None

    def setup(self) -> None:
        super().setup()
        self.rfile = io.BufferedReader(_HeaderDeadline(self))

    def handle_one_request(self) -> None:
        # the request line and the headers must arrive within HEADER_SECONDS in all
        self._header_deadline = time.monotonic() + HEADER_SECONDS
        try:
            super().handle_one_request()
        finally:
            self._header_deadline = None

    def parse_request(self) -> bool:
        ok = super().parse_request()  # reads the headers
        self._header_deadline = None  # a body has its own deadline (UPLOAD_SECONDS)
        self.connection.settimeout(self.timeout)
        return ok

    def _client_connected(self) -> bool:
        """Whether the client is still there (a closed connection reads as end of file), for
        long work to stop when it has left."""
        try:
            self.connection.setblocking(False)
            return self.connection.recv(1, socket.MSG_PEEK) != b""
        except BlockingIOError:  # nothing to read: still connected, waiting
            return True
        except OSError:
            return False
        finally:
            self.connection.settimeout(self.timeout)

    def log_message(self, format: str, *args: Any) -> None:  # noqa: A002 - stdlib signature
        if not self.quiet:
            super().log_message(format, *args)

    def _send(self, status: int, body: bytes, ctype: str, head: bool = False) -> None:
        self.send_response(status)
        self.send_header("Content-Type", ctype)
        self.send_header("Content-Length", str(len(body)))
        self.send_header("Cache-Control", "no-store")
        self.send_header("X-Content-Type-Options", "nosniff")
        self.end_headers()
        if not head:
            self.wfile.write(body)

    def _json(self, status: int, obj: Any, head: bool = False) -> None:
        if status >= 400 and isinstance(obj, dict) and isinstance(obj.get("error"), str):
            obj = {**obj, "error": clip_echo(obj["error"])}  # never echo a flood back
        self._send(status, dumps(obj).encode(), "application/json", head)

    def _not_found(self, head: bool = False) -> None:
        self._send(HTTPStatus.NOT_FOUND, b"404 not found\n", "text/plain; charset=utf-8", head)

    def do_HEAD(self) -> None:  # noqa: N802 - stdlib name
        self._get(head=True)

    def do_GET(self) -> None:  # noqa: N802 - stdlib name
        self._get(head=False)

    def _error(self, status: int, message: str) -> None:
        """A JSON error; the connection is closed (an unread body must not be parsed as the
        next request)."""
        self.close_connection = True
        self._json(status, {"error": message})

    def do_POST(self) -> None:  # noqa: N802 - stdlib name
        if self._refused(False):
            self.close_connection = True
            return
        try:
            url = urlsplit(self.path)
        except ValueError:
            self._error(HTTPStatus.NOT_FOUND, "no such endpoint")
            return
        q = {k: v[-1] for k, v in parse_qs(url.query).items()}
        if url.path == "/api/data":
            self._upload(q)
        elif url.path in ("/api/fit", "/api/rank"):
            self._fit(url.path)
        else:
            self._error(HTTPStatus.NOT_FOUND, "no such endpoint")

    def _length(self, limit: int, what: str) -> int | None:
        """The body's announced length, or None after answering 411/413."""
        if self.headers.get("Transfer-Encoding"):
            self._error(HTTPStatus.LENGTH_REQUIRED, "send the body with a Content-Length")
            return None
        text = self.headers.get("Content-Length")
        try:
            n = int(text) if text is not None else -1
        except ValueError:
            n = -1
        if n < 0:
            self._error(HTTPStatus.LENGTH_REQUIRED, "a Content-Length header is required")
            return None
        if n > limit:
            self._error(
                HTTPStatus.REQUEST_ENTITY_TOO_LARGE,
                f"{what} is too large: {n} bytes, at most {limit} are accepted",
            )
            return None
        return n

    def _body(self, n: int) -> bytes | None:
        """Read ``n`` bytes within :data:`UPLOAD_SECONDS`, or answer 408/400 and None."""
        import time

        deadline = time.monotonic() + UPLOAD_SECONDS
        chunks: list[bytes] = []
        got = 0
        stalled = False
        try:
            while got < n:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise TimeoutError
                stalled = IDLE_TIMEOUT < left  # a timeout now is silence, not the deadline
                self.connection.settimeout(min(IDLE_TIMEOUT, left))
                chunk = self.rfile.read1(min(n - got, 1 << 20))
                if not chunk:
                    self._error(HTTPStatus.BAD_REQUEST, f"the body ended after {got} of {n} bytes")
                    return None
                chunks.append(chunk)
                got += len(chunk)
        except TimeoutError:
            # say which limit was enforced: silence for IDLE_TIMEOUT s, or the whole deadline
            why = (
                f"nothing arrived for {IDLE_TIMEOUT:g} s"
                if stalled
                else f"the body did not arrive within {UPLOAD_SECONDS:g} s"
            )
            self._error(HTTPStatus.REQUEST_TIMEOUT, f"{why} ({got} of {n} bytes)")
            return None
        finally:
            self.connection.settimeout(IDLE_TIMEOUT)
        return b"".join(chunks)

    def _upload(self, q: dict[str, str]) -> None:
        kind = q.get("format", "")
        limits = {"merl": datasets.MAX_MERL_BYTES, "csv": datasets.MAX_CSV_BYTES}
        if kind not in limits:
            self._error(HTTPStatus.BAD_REQUEST, f"format must be 'merl' or 'csv' (got {kind!r})")
            return
        name = q.get("name", "") or f"data.{'binary' if kind == 'merl' else 'csv'}"
        what = "a MERL file" if kind == "merl" else "a CSV file"
        n = self._length(limits[kind], f"{name} ({what})")
        if n is None:
            return
        if not UPLOAD_SLOTS.acquire(blocking=False):
            self._error(HTTPStatus.SERVICE_UNAVAILABLE, "other uploads are being read; try again")
            return
        try:
            body = self._body(n)
            if body is None:
                return
            try:
                ds = datasets.parse_upload(kind, name, body)
            except ValueError as exc:
                self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)})
                return
            del body
        finally:
            UPLOAD_SLOTS.release()
        self._json(HTTPStatus.OK, ds.summary())

    def _fit(self, path: str) -> None:
        n = self._length(JSON_BODY_BYTES, "the request")
        if n is None:
            return
        body = self._body(n)
        if body is None:
            return
        try:
            req = loads_json(body.decode("utf-8"), "the body")
            if not isinstance(req, dict):
                raise ParameterError("the body must be a JSON object")
        except UnicodeDecodeError:
            self._json(HTTPStatus.BAD_REQUEST, {"error": "the body is not UTF-8 text"})
            return
        except ValueError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)})
            return
        try:
            ds = datasets.STORE.get(str(req.get("dataset")))
        except KeyError:
            self._json(
                HTTPStatus.NOT_FOUND,
                {
                    "error": "no such dataset here (the server keeps "
                    f"the last {datasets.DATASETS_KEPT}): load the file again"
                },
            )
            return
        try:
            if path == "/api/fit":
                out = datasets.fit_model(ds, req.get("model"), req.get("choices"))
            else:
                out = datasets.rank_models(ds, req.get("models"))
        except datasets.Busy as exc:
            self._json(HTTPStatus.SERVICE_UNAVAILABLE, {"error": str(exc)})
            return
        except ValueError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)})
            return
        self._json(HTTPStatus.OK, out)

    def _refused(self, head: bool) -> bool:
        """Answer 421 (foreign Host) or 403 (foreign Origin) and return True, or False."""
        server = self.server
        allowed = server.allowed_host if isinstance(server, ExplorerServer) else None
        if allowed is None:
            return False
        if not allowed(self.headers.get("Host")):
            self._send(
                HTTPStatus.MISDIRECTED_REQUEST,
                b"421 this server answers only requests addressed to it\n",
                "text/plain; charset=utf-8",
                head,
            )
            return True
        origin = self.headers.get("Origin")
        if origin is not None and not (
            origin.startswith("http://") and allowed(origin[len("http://") :])
        ):
            self._send(
                HTTPStatus.FORBIDDEN,
                b"403 requests from other web pages are refused\n",
                "text/plain; charset=utf-8",
                head,
            )
            return True
        return False

    def _get(self, head: bool) -> None:
        if self._refused(head):
            return
        try:
            url = urlsplit(self.path)
        except ValueError:
            self._not_found(head)
            return
        if self.path.startswith("/api/"):
            self._api(url.path, parse_qs(url.query), head)
            return
        if url.path == "/glsl/models.glsl":  # printed from the models' code, not a file
            from .shaders import models_glsl

            self._send(HTTPStatus.OK, models_glsl().encode(), CONTENT_TYPES[".glsl"], head)
            return
        try:
            file = resolve_static(url.path if self.path.startswith("/") else self.path)
        except UnicodeDecodeError:
            file = None
        if file is None:
            self._not_found(head)
            return
        ctype = CONTENT_TYPES.get(file.suffix) or mimetypes.guess_type(file.name)[0]
        self._send(HTTPStatus.OK, file.read_bytes(), ctype or "application/octet-stream", head)

    def _api(self, path: str, query: dict[str, list[str]], head: bool) -> None:
        q = {k: v[-1] for k, v in query.items()}
        try:
            if path == "/api/info.json":
                self._json(HTTPStatus.OK, backend.info(), head)
            elif path == "/api/models":
                self._json(HTTPStatus.OK, models_json(), head)
            elif path == "/api/shader":
                from .shaders import server_shader

                self._json(HTTPStatus.OK, server_shader(_json_query(q, "p")), head)
            elif path == "/api/vase.png":
                self._send(HTTPStatus.OK, backend.vase_png(q), "image/png", head)
            elif path == "/api/groundtruth.json":
                self._json(HTTPStatus.OK, backend.ground_truth(q), head)
            elif path == "/api/layeredtruth.json":
                from .layered_truth import layered_truth

                self._json(HTTPStatus.OK, layered_truth(q, self._client_connected), head)
            elif path == "/api/data/slice":
                try:
                    ds = datasets.STORE.get(q.get("id", ""))
                except KeyError:
                    raise backend.Unavailable("no such dataset here: load the file again") from None
                key = "delta_phi" if "delta_phi" in q or "dphi" not in q else "dphi"
                out = datasets.slice_points(
                    ds, backend.number(q, "theta_i", 0.0), backend.number(q, key, 0.0)
                )
                self._json(HTTPStatus.OK, out, head)
            else:
                self._not_found(head)
        except backend.Unavailable as exc:
            self._json(HTTPStatus.NOT_FOUND, {"error": str(exc)}, head)
        except ValueError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)}, head)


def models_json() -> list[dict[str, Any]]:
    """``/api/models``: the registry's records (``roughdiffuse models --json``), each with its
    printed shader (``shader``, :func:`.shaders.shader_records`) and the page's keys of the
    parameters whose key differs from their name (``state_keys``)."""
    from .. import registry
    from .params import state_keys
    from .shaders import shader_records, with_glsl_fields

    shaders = shader_records()
    out = []
    for record in with_glsl_fields(registry.to_json()):
        keys = state_keys(registry.get(record["id"]))
        out.append({**record, "shader": shaders.get(record["id"]), "state_keys": keys})
    return out


def _json_query(q: dict[str, str], key: str) -> dict[str, Any]:
    """The JSON object in query value ``key`` (a ValueError, 400, if it is not one)."""
    try:
        value = json.loads(q.get(key, ""))
    except json.JSONDecodeError:
        raise ParameterError(f"{key} must be a JSON object") from None
    if not isinstance(value, dict):
        raise ParameterError(f"{key} must be a JSON object")
    return value


def _split_host(value: str) -> tuple[str, str] | None:
    """("host", "port") of a Host header value (``[v6]:port`` or ``name:port``), or None."""
    if value.startswith("["):
        end = value.find("]")
        if end < 0 or value[end + 1 : end + 2] != ":":
            return None
        return value[1:end].lower(), value[end + 2 :]
    host, sep, port = value.rpartition(":")
    return (host.lower(), port) if sep else None


def _is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _is_ip(host: str) -> bool:
    try:
        ipaddress.ip_address(host)
    except ValueError:
        return False
    return True


class _HeaderDeadline(io.RawIOBase):
    """The handler's connection as a raw stream whose reads stop at the handler's header
    deadline (each read waits at most the time left), so headers trickled in byte by byte
    cannot hold a thread for ever."""

    def __init__(self, handler: ExplorerHandler) -> None:
        self.handler = handler
        self.sock = handler.connection

    def readable(self) -> bool:
        return True

    def readinto(self, buffer: Any) -> int:
        deadline = self.handler._header_deadline
        if deadline is not None:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"request headers not complete within {HEADER_SECONDS:g} s")
            self.sock.settimeout(min(self.handler.timeout or IDLE_TIMEOUT, left))
        return self.sock.recv_into(buffer)


class ExplorerServer(ThreadingHTTPServer):
    """The explorer's HTTP server: one thread per request, at most :data:`MAX_THREADS`, and
    a check of the ``Host`` header (:meth:`allowed_host`)."""

    daemon_threads = True
    max_threads = MAX_THREADS

    def __init__(self, address: tuple[str, int], handler: type = ExplorerHandler) -> None:
        super().__init__(address, handler)
        self._slots = threading.BoundedSemaphore(self.max_threads)
        self._claims_lock = threading.Lock()
        self._unclaimed: set[Any] = set()
        self.bound_host = str(self.server_address[0]).lower()
        self.bound_port = int(self.server_address[1])

    def allowed_host(self, value: str | None) -> bool:
        """Whether a ``Host`` header ``value`` addresses this server: its port, and its bound
        address, ``localhost`` or a loopback address; any IP address (never a name, which a
        DNS-rebinding page controls) when bound to all interfaces."""
        parts = _split_host(value or "")
        if parts is None or parts[1] != str(self.bound_port):
            return False
        host = parts[0]
        if host == self.bound_host or _is_loopback(host):
            return True
        wildcard = self.bound_host in ("0.0.0.0", "::")
        return wildcard and _is_ip(host)

    def process_request(self, request: Any, client_address: Any) -> None:
        if not self._slots.acquire(blocking=False):
            try:
                request.settimeout(1.0)
                request.sendall(
                    b"HTTP/1.1 503 Service Unavailable\r\nContent-Length: 0\r\n"
                    b"Connection: close\r\n\r\n"
                )
            except OSError:
                pass
            self.shutdown_request(request)
            return
        with self._claims_lock:
            self._unclaimed.add(request)
        try:
            super().process_request(request, client_address)
        except BaseException:
            # The handler thread may already have started, finished and released the slot
            # (a Ctrl-C can land while ``Thread.start`` waits); whoever claims the request
            # first releases its slot, so it is released once and the interrupt is not
            # replaced by a "released too many times" error that serve_forever would swallow.
            if self._claim(request):
                self._slots.release()
            raise

    def process_request_thread(self, request: Any, client_address: Any) -> None:
        owns_slot = self._claim(request)
        try:
            super().process_request_thread(request, client_address)
        finally:
            if owns_slot:
                self._slots.release()

    def _claim(self, request: Any) -> bool:
        """Take the release of ``request``'s slot: True for the first caller only."""
        with self._claims_lock:
            try:
                self._unclaimed.remove(request)
            except KeyError:
                return False
            return True

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A client that went away (or stalled) is one line on stderr; anything else is a
        traceback, as in the standard library."""
        exc = sys.exc_info()[1]
        if isinstance(exc, ConnectionError | TimeoutError):
            host, port = client_address[:2]
            print(
                f"roughdiffuse explorer: client {host}:{port} went away ({type(exc).__name__})",
                file=sys.stderr,
                flush=True,
            )
            return
        super().handle_error(request, client_address)


class _ExplorerServerV6(ExplorerServer):
    address_family = socket.AF_INET6


def make_server(
    host: str = "127.0.0.1", port: int | None = None, *, expose_to_network: bool = False
) -> ExplorerServer:
    """A server bound to ``host``:``port`` (a free port when ``port`` is None or 0).

    Call ``serve_forever()`` on it (or :func:`serve_in_thread`); ``server_address`` holds the
    port actually bound.

    Raises
    ------
    ValueError
        If ``host`` is not a loopback address or ``localhost`` -- an empty host or a wildcard
        (``0.0.0.0``, ``::``) binds every interface -- unless ``expose_to_network`` is True
        (``roughdiffuse explore --expose-to-network``).
    """
    if port is not None and not 0 <= port <= 65535:
        raise ParameterError(f"port must be in [0, 65535] (got {port})")
    if not expose_to_network and not (host.strip() and _is_loopback(host.strip().lower())):
        from ..io.reading import short

        raise ParameterError(
            f"host {short(host)} is not this machine only (an empty host or a wildcard binds "
            "every network interface); use a loopback address such as 127.0.0.1, or add "
            "--expose-to-network to let other machines reach the explorer"
        )
    cls = _ExplorerServerV6 if ":" in host else ExplorerServer
    return cls((host, port or 0), ExplorerHandler)


def serve_in_thread(server: ThreadingHTTPServer) -> threading.Thread:
    """Run ``server`` in a daemon thread (for tests and notebooks); stop with shutdown()."""
    t = threading.Thread(target=server.serve_forever, name="roughdiffuse-explorer", daemon=True)
    t.start()
    return t


def url_of(server: ThreadingHTTPServer) -> str:
    """The page's URL."""
    host, port = server.server_address[:2]
    host = f"[{host}]" if ":" in str(host) else host
    return f"http://{host}:{port}/"
