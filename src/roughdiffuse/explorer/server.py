"""The explorer's local web server (standard library only).

It serves the static page in ``static/`` and four small JSON/PNG endpoints under ``/api/``:

* ``/api/info.json``: what this server can do (``vase``: the Python renderer is importable;
  ``groundtruth``: the V-cavity solver is importable).
* ``/api/models``: every model of :mod:`roughdiffuse.registry`, the same JSON as
  ``roughdiffuse models --json``; the page builds its menus and sliders from it.
* ``/api/vase.png?model=…&albedo=…``: the vase preset, rendered by :mod:`roughdiffuse.render`.
* ``/api/groundtruth.json?sigma=…&theta_i=…&albedo=…``: V-cavity radiance in the plane of
  incidence, computed by :mod:`roughdiffuse.simulate` on request.

It serves only its own files: a path with a ``..`` or ``.`` segment, an empty segment (``//``),
a backslash, a NUL, or anything that resolves outside ``static/`` gets 404; so does every
path that is not a regular file there (no directory listings). It binds to 127.0.0.1 unless
told otherwise.
"""

from __future__ import annotations

import json
import mimetypes
import posixpath
import socket
import threading
from http import HTTPStatus
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any
from urllib.parse import parse_qs, unquote, urlsplit

from .. import __version__
from . import backend

__all__ = ["STATIC_DIR", "ExplorerHandler", "make_server", "resolve_static"]

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
    """GET and HEAD for the static page and the ``/api/`` endpoints; nothing else."""

    server_version = f"roughdiffuse-explorer/{__version__}"
    quiet = True

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
        self._send(status, json.dumps(obj).encode(), "application/json", head)

    def _not_found(self, head: bool = False) -> None:
        self._send(HTTPStatus.NOT_FOUND, b"404 not found\n", "text/plain; charset=utf-8", head)

    def do_HEAD(self) -> None:  # noqa: N802 - stdlib name
        self._get(head=True)

    def do_GET(self) -> None:  # noqa: N802 - stdlib name
        self._get(head=False)

    def _get(self, head: bool) -> None:
        try:
            url = urlsplit(self.path)
        except ValueError:
            self._not_found(head)
            return
        if self.path.startswith("/api/"):
            self._api(url.path, parse_qs(url.query), head)
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
                from .. import registry

                self._json(HTTPStatus.OK, registry.to_json(), head)
            elif path == "/api/vase.png":
                self._send(HTTPStatus.OK, backend.vase_png(q), "image/png", head)
            elif path == "/api/groundtruth.json":
                self._json(HTTPStatus.OK, backend.ground_truth(q), head)
            else:
                self._not_found(head)
        except backend.Unavailable as exc:
            self._json(HTTPStatus.NOT_FOUND, {"error": str(exc)}, head)
        except ValueError as exc:
            self._json(HTTPStatus.BAD_REQUEST, {"error": str(exc)}, head)


def make_server(host: str = "127.0.0.1", port: int | None = None) -> ThreadingHTTPServer:
    """A server bound to ``host``:``port`` (a free port when ``port`` is None or 0).

    Call ``serve_forever()`` on it (or :func:`serve_in_thread`); ``server_address`` holds the
    port actually bound.
    """
    if port is not None and not 0 <= port <= 65535:
        raise ValueError(f"port must be in [0, 65535] (got {port})")
    cls = ThreadingHTTPServer
    if ":" in host:

        class _V6(ThreadingHTTPServer):
            address_family = socket.AF_INET6

        cls = _V6
    server = cls((host, port or 0), ExplorerHandler)
    server.daemon_threads = True
    return server


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
