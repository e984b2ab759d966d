"""Messages are short and true: long input is never echoed whole, by the command line
(argparse's own errors included) or by the explorer's 4xx replies."""

from __future__ import annotations

import http.client
import json

import pytest

from roughdiffuse.cli import main
from roughdiffuse.explorer import make_server, serve_in_thread
from roughdiffuse.io.reading import LONG_WORD, clip_echo

LONG = "x" * 100_000


def run(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


@pytest.mark.parametrize(
    "argv",
    [
        ["eval", "--model", "eon", "--param", f"{LONG}=1"],
        ["eval", "--model", "eon", "--param", f"roughness={LONG}"],
        ["eval", "--model", "eon", "--albedo", LONG],
        ["eval", "--model", "eon", f"--{LONG}", "1"],
        ["render", "--model", "eon", "--shape", LONG, "-o", "x.png"],
        [LONG],
        ["eval", "--model", LONG],
    ],
)
def test_long_input_is_clipped_in_every_cli_message(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(argv) == 2
    captured = capsys.readouterr()
    err = captured.err
    assert len(err) < 1000 and "100" in err and "characters" in err
    assert len(err.strip().splitlines()) == 1 and captured.out == ""


def test_clip_echo_keeps_ordinary_messages_and_the_ends_of_a_long_word():
    message = "folder '/tmp/a/b' does not exist"
    assert clip_echo(message) == message
    word = "a" * 200 + "MIDDLE" + "b" * 200
    clipped = clip_echo(f"bad {word}!")
    assert clipped.startswith("bad aaaa") and "bbbb!" in clipped and "MIDDLE" not in clipped
    assert f"({len(word) + 1} characters)" in clipped
    assert clip_echo("y" * LONG_WORD) == "y" * LONG_WORD  # the limit itself is kept


@pytest.fixture
def server():
    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    yield srv
    srv.shutdown()
    srv.server_close()


def test_explorer_400_does_not_echo_a_long_query(server):
    host, port = server.server_address[:2]
    conn = http.client.HTTPConnection(host, port, timeout=60)
    conn.request("GET", "/api/vase.png?model=oren-nayar&sigma=" + "9" * 20_000)
    reply = conn.getresponse()
    body = reply.read()
    conn.close()
    assert reply.status == 400
    error = json.loads(body)["error"]
    assert "sigma" in error and len(body) < 1000
