"""``roughdiffuse explore``: the explorer page on a local web server."""

from __future__ import annotations

import argparse
import sys

EXAMPLES = """\
examples:
  roughdiffuse explore                   # a free port on 127.0.0.1, opens the browser
  roughdiffuse explore --port 8765 --no-browser
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "explore",
        help="open the explorer: sliders, a lit sphere and plots in the browser",
        description="Serve the explorer page (static files and a small API) on a local web "
        "server and open it in the browser. Stop with Ctrl-C.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to bind (default: 127.0.0.1, this machine only)",
    )
    p.add_argument("--port", type=int, default=None, help="port (default: a free one)")
    p.add_argument(
        "--expose-to-network",
        action="store_true",
        help="allow a --host that other machines can reach (an address of a network "
        "interface, 0.0.0.0 or ::); without it only loopback addresses are accepted",
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    p.set_defaults(func=run)


def _open_browser(url: str) -> None:
    """Open ``url`` in a graphical browser; without a display (Linux) only say so, rather
    than let :mod:`webbrowser` start a text browser in this terminal."""
    import os
    import webbrowser

    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        print("no display here: open the URL in a browser yourself", flush=True)
        return
    from ..programs import trusted_environ

    with trusted_environ():  # webbrowser looks its programs up on PATH: not in this folder
        opened = webbrowser.open(url)
    if not opened:
        print("could not start a browser: open the URL yourself", flush=True)


def run(args: argparse.Namespace) -> int:
    from ..explorer.server import make_server, url_of
    from . import UsageError

    if args.port is not None and not 0 <= args.port <= 65535:  # the port's own flag
        raise UsageError(f"--port must be in [0, 65535] (got {args.port})")
    try:
        server = make_server(args.host, args.port, expose_to_network=args.expose_to_network)
    except ValueError as exc:
        raise UsageError(f"--host: {exc}") from None
    except OSError as exc:
        raise UsageError(f"cannot listen on {args.host}:{args.port or 0}: {exc.strerror}") from None
    url = url_of(server)
    print(f"roughdiffuse explorer at {url}  (Ctrl-C to stop)", flush=True)
    if args.host not in ("127.0.0.1", "localhost", "::1"):
        print(f"note: listening on {args.host}: other machines may reach this page", flush=True)
    if not args.no_browser:
        _open_browser(url)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("stopped", file=sys.stderr)
    finally:
        server.server_close()
    return 0
