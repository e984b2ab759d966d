"""Messages are short and true: long input is never echoed whole, by the command line
(argparse's own errors included) or by the explorer's 4xx replies."""

from __future__ import annotations

import http.client
import json
import math

import numpy as np
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


@pytest.mark.parametrize(
    ("argv", "flag"),
    [
        (["plot", "plane", "--shape", "vase"], "--shape"),
        (["plot", "polar", "--spp", "4"], "--spp"),
        (["plot", "plane", "--light-theta", "10"], "--light-theta"),
        (["plot", "cross-section", "--theta-i", "30"], "--theta-i"),
    ],
)
def test_plot_refuses_flags_its_mode_does_not_use(argv, flag, capsys, tmp_path):
    out = tmp_path / "p.png"
    assert run([*argv, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert flag in err and "applies only" in err and not out.exists()


def test_bench_refuses_a_results_name_taken_by_a_folder_before_any_benchmark(tmp_path, capsys):
    (tmp_path / "results.json").mkdir()
    assert run(["bench", "--output-dir", str(tmp_path)]) == 2
    captured = capsys.readouterr()
    assert "results.json" in captured.err and captured.out == ""  # nothing was run


def test_a_tiny_light_direction_is_a_direction_and_a_zero_one_is_named():
    from roughdiffuse.stereo.inputs import _unit_directions

    d = _unit_directions([[1e-170, 1e-170, 0.0], [0.0, 0.0, 1.0], [0.0, 5e-324, 0.0]])
    assert d[0] == pytest.approx([2**-0.5, 2**-0.5, 0.0]) and d[2] == pytest.approx([0, 1, 0])
    with pytest.raises(ValueError, match="direction 2 is the zero vector"):
        _unit_directions([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match="direction 1 is not finite"):
        _unit_directions([[float("nan"), 0.0, 1.0]])


@pytest.mark.parametrize("port", ["70000", "-1"])
def test_a_bad_port_is_reported_under_port(port, capsys):
    assert run(["explore", "--port", port, "--no-browser"]) == 2
    err = capsys.readouterr().err
    assert "--port" in err and "--host" not in err


# ----------------------------------------------------------------- bounded requests


def test_headers_trickled_byte_by_byte_are_cut_off_at_the_header_deadline(monkeypatch):
    import socket
    import time

    from roughdiffuse.explorer import server as srv_module

    monkeypatch.setattr(srv_module, "HEADER_SECONDS", 1.0)
    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    try:
        sock = socket.create_connection(srv.server_address[:2], timeout=30)
        sock.sendall(b"GET /api/info.json HTTP/1.1\r\n")
        cut = False
        for _ in range(60):  # one byte every 0.2 s: never silent for IDLE_TIMEOUT (15 s)
            try:
                sock.sendall(b"X")
                time.sleep(0.2)
                sock.setblocking(False)
                try:
                    if sock.recv(1024) == b"":
                        cut = True
                        break
                except BlockingIOError:
                    pass
                finally:
                    sock.setblocking(True)
            except OSError:
                cut = True
                break
        sock.close()
        assert cut  # closed long before the 12 s of trickling ended
    finally:
        srv.shutdown()
        srv.server_close()


def test_a_layered_truth_beyond_the_cost_budget_is_a_400_before_any_walk(monkeypatch):
    from roughdiffuse.explorer import layered_truth as lt

    def no_walk(key):
        raise AssertionError("the walk ran")

    monkeypatch.setattr(lt, "_plane_of_incidence", no_walk)
    with pytest.raises(ValueError, match=r"eta must be in \[1, 5\]"):  # the model's range
        lt.layered_truth({"model": "coated", "eta": "1000", "albedo": "1", "theta_i": "30"})
    with pytest.raises(ValueError, match="lower η or the albedo"):  # the walk's own budget
        lt.check_cost(1000.0, 1.0)
    assert lt.arrivals(1.5, 0.0) == 1.0  # a black base: the one arrival of each path
    # a closed form: the mean of a geometric count with continuation p is 1 / (1 - p)
    eta, rho = 2.0, 0.5
    e = (1 - (1 / 3) ** 2) / 4
    assert lt.arrivals(eta, rho) == pytest.approx(1 / (1 - rho * (1 - e)))


def test_an_unwritable_data_dir_is_one_line_naming_it(tmp_path, monkeypatch, capsys):
    import errno
    from pathlib import Path

    from roughdiffuse import data

    def refuse(self, *args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied", str(self))

    monkeypatch.setenv("ROUGHDIFFUSE_DATA_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(Path, "mkdir", refuse)  # as a read-only folder does (root is exempt)
    generated = next(n for n in data.names() if not (data._HERE / n).is_file())
    assert run(["data", "--path", generated]) == 2
    err = capsys.readouterr().err
    assert "ROUGHDIFFUSE_DATA_DIR" in err and "Permission denied" in err
    assert len(err.strip().splitlines()) == 1


def test_a_table_being_computed_by_another_run_is_a_one_line_refusal(tmp_path, capsys):
    from roughdiffuse.simulate.table import _TableLock

    path = tmp_path / "t.npz"
    with _TableLock(path):  # another run holds the lock
        argv = ["simulate", "--table", str(path), "--step", "45", "--delta-phi-step", "180",
                "--sigma", "10", "--bounces", "1", "--no-progress"]  # fmt: skip
        assert run(argv) == 2
    err = capsys.readouterr().err
    assert "being computed by another run" in err and "internal error" not in err


_COAT = {"model": "coated", "eta": "1.5", "albedo": "0.8", "theta_i": "30", "sigma": "0.2"}


def _fake_walk(monkeypatch, calls):
    from roughdiffuse.explorer import layered_truth as lt
    from roughdiffuse.explorer.backend import THETA_R_DEG
    from roughdiffuse.simulate import layered

    def brdf(*args, seed, **kwargs):
        calls.append(seed)
        n = len(THETA_R_DEG)
        return np.full(n, float(seed)), np.full(n, 0.1 * seed)

    monkeypatch.setattr(layered, "brdf", brdf)
    monkeypatch.setattr(lt, "_CACHE", {})
    return lt


def test_the_layered_walk_stops_when_the_client_has_left(monkeypatch):
    calls = []
    lt = _fake_walk(monkeypatch, calls)
    with pytest.raises(ConnectionError, match="went away"):
        lt.layered_truth(_COAT, still_wanted=lambda: False)
    assert calls == []  # no part of the walk ran
    answers = iter([True, True, False])
    with pytest.raises(lt.Stopped):
        lt.layered_truth(_COAT, still_wanted=lambda: next(answers))
    assert calls == [1, 2]  # stopped between parts


def test_the_layered_walk_stops_at_its_deadline(monkeypatch):
    calls = []
    lt = _fake_walk(monkeypatch, calls)
    monkeypatch.setattr(lt, "DEADLINE_SECONDS", -1.0)
    with pytest.raises(ValueError, match="took more than"):
        lt.layered_truth(_COAT)
    assert calls == []


def test_the_parts_of_the_walk_combine_to_its_mean_and_standard_error(monkeypatch):
    calls = []
    lt = _fake_walk(monkeypatch, calls)
    out = lt.layered_truth(_COAT)
    k = lt.CHUNKS
    seeds = np.arange(1, k + 1)
    assert calls == list(seeds)
    assert out["brdf"][0] == pytest.approx(seeds.mean())  # equal parts: the mean of means
    # independent parts: the variance of the mean is the sum of the variances over K²
    assert out["stderr"][0] == pytest.approx(math.sqrt(np.sum((0.1 * seeds) ** 2)) / k)


def test_client_connected_reads_a_closed_connection_as_gone():
    import socket
    import types

    from roughdiffuse.explorer.server import ExplorerHandler

    ours, theirs = socket.socketpair()
    handler = types.SimpleNamespace(connection=ours, timeout=5.0)
    assert ExplorerHandler._client_connected(handler) is True
    theirs.close()
    assert ExplorerHandler._client_connected(handler) is False
    assert ours.gettimeout() == 5.0
    ours.close()
