"""The explorer's server and command: what it serves, what it refuses, how it starts.

No browser here (tests/test_explorer_page.py drives the page in Chromium).
"""

from __future__ import annotations

import http.client
import json
import math
import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse import Lambert, OrenNayar, TorranceSparrow
from roughdiffuse.explorer import STATIC_DIR, make_server, model_from_params, serve_in_thread
from roughdiffuse.explorer.server import resolve_static


@pytest.fixture(scope="module")
def server():
    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    yield srv
    srv.shutdown()
    srv.server_close()


def get(server, path: str, method: str = "GET") -> tuple[int, dict[str, str], bytes]:
    host, port = server.server_address[:2]
    conn = http.client.HTTPConnection(host, port, timeout=60)
    conn.putrequest(method, path, skip_host=False, skip_accept_encoding=True)
    conn.endheaders()
    r = conn.getresponse()
    body = r.read()
    conn.close()
    return r.status, {k.lower(): v for k, v in r.getheaders()}, body


def test_binds_to_loopback_on_a_free_port(server):
    host, port = server.server_address[:2]
    assert host == "127.0.0.1"
    assert 0 < port < 65536


def test_serves_the_page_and_its_modules(server):
    status, headers, body = get(server, "/")
    assert status == 200
    assert headers["content-type"].startswith("text/html")
    assert body == (STATIC_DIR / "index.html").read_bytes()
    status, headers, body = get(server, "/js/main.js")
    assert status == 200 and headers["content-type"].startswith("text/javascript")
    status, headers, body = get(server, "/glsl/models.glsl")  # printed from the models
    assert status == 200 and b"vec3 rd_brdf(RDParams p" in body and b"#define RD_EON " in body
    status, headers, body = get(server, "/index.html", method="HEAD")
    assert status == 200 and body == b"" and int(headers["content-length"]) > 100


@pytest.mark.parametrize(
    "path",
    [
        "/../pyproject.toml",
        "/../../../../etc/passwd",
        "/js/../../server.py",
        "/%2e%2e/server.py",
        "/js/%2E%2E/%2e%2e/params.py",
        "/..%2fserver.py",
        "//etc/passwd",
        "/etc/passwd",
        "/js/",
        "/js",
        "/./index.html",
        "/js\\..\\..\\server.py",
        "/index.html%00.js",
        "/%ff",
        "http://127.0.0.1/etc/passwd",
        "/nonexistent.js",
        "/api/nothing",
    ],
)
def test_serves_only_its_own_files(server, path):
    """../, absolute paths, encoded tricks, directories: 404, never a file from elsewhere."""
    status, _, body = get(server, path)
    # an absolute-form target makes http.client send "Host: 127.0.0.1" without the port: the
    # Host check refuses it (421) before the path is looked at
    assert status == (421 if path.startswith("http:") else 404), (path, status)
    assert b"root:" not in body and b"import" not in body


def test_resolve_static_stays_inside_the_folder(tmp_path):
    (tmp_path / "a.txt").write_text("a")
    outside = tmp_path.parent / "outside.txt"
    outside.write_text("secret")
    (tmp_path / "link.txt").symlink_to(outside)
    assert resolve_static("/a.txt", tmp_path) == (tmp_path / "a.txt").resolve()
    assert resolve_static("/link.txt", tmp_path) is None  # a symlink pointing out
    assert resolve_static("/../outside.txt", tmp_path) is None


def test_info_says_what_the_server_can_do(server):
    status, headers, body = get(server, "/api/info.json")
    assert status == 200 and headers["content-type"] == "application/json"
    info = json.loads(body)
    assert set(info) >= {"vase", "groundtruth", "version"}


def test_bad_api_query_is_a_400_naming_the_parameter(server):
    status, _, body = get(server, "/api/vase.png?model=oren-nayar&sigma=abc")
    assert status == 400 and "sigma must be a number" in json.loads(body)["error"]
    status, _, body = get(server, "/api/vase.png?model=nope")
    assert status == 400 and "model must be one of" in json.loads(body)["error"]
    status, _, body = get(server, "/api/vase.png?model=oren-nayar&sigma=3")
    assert status == 400 and "sigma" in json.loads(body)["error"]


def test_vase_is_rendered_by_the_python_renderer(server):
    status, _, body = get(server, "/api/info.json")
    if not json.loads(body)["vase"]:
        pytest.fail("the renderer (roughdiffuse.render) is importable in this project")
    status, headers, body = get(
        server, "/api/vase.png?model=lambert&albedo=1,1,1&size=64&light_theta=0"
    )
    assert status == 200 and headers["content-type"] == "image/png"
    assert body[:8] == b"\x89PNG\r\n\x1a\n"
    import io

    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(body)).convert("RGB"), dtype=np.float64) / 255.0
    assert img.shape == (64, 64, 3)
    # a white Lambert surface lit head-on with E0 = π: radiance n·l, at most 1 (sRGB 255),
    # and the brightest pixels, where the vase's wall faces the light, are close to 1
    assert img.max() > 0.97
    assert img[0, 0].max() < 0.05  # background


def test_ground_truth_is_lambert_for_a_nearly_flat_surface(server):
    """The solver's curve, served for the page: σ → 0 is a Lambertian plane, f = ρ/π."""
    status, _, body = get(server, "/api/info.json")
    if not json.loads(body)["groundtruth"]:
        pytest.fail("the V-cavity solver (roughdiffuse.simulate) is importable in this project")
    status, headers, body = get(server, "/api/groundtruth.json?sigma=0.01&theta_i=30&albedo=0.5")
    assert status == 200 and headers["content-type"] == "application/json"
    gt = json.loads(body)
    assert gt["theta_r"][0] == -88 and gt["theta_r"][-1] == 88 and len(gt["theta_r"]) == 45
    np.testing.assert_allclose(gt["brdf"], 0.5 / math.pi, rtol=2e-3)
    # radiance as on the page: f E0 cos θi with E0 = π
    np.testing.assert_allclose(gt["radiance"], 0.5 * math.cos(math.radians(30)), rtol=2e-3)
    for query, name in (
        ("sigma=0", "sigma"),
        ("sigma=0.3&theta_i=90", "theta_i"),
        ("sigma=0.3&albedo=2", "albedo"),
        ("sigma=x", "sigma"),
        ("sigma=0.3&bounces=2", "bounces"),
    ):
        status, _, body = get(server, f"/api/groundtruth.json?{query}")
        assert status == 400 and name in json.loads(body)["error"], query


def test_model_from_params_is_the_named_model():
    n = np.array([0.0, 0.0, 1.0])
    wi = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    f = model_from_params({"model": "lambert", "albedo": [0.2, 0.4, 0.6]}).brdf(wi, n)
    np.testing.assert_allclose(f, np.array([0.2, 0.4, 0.6]) / math.pi, rtol=1e-12)
    m = model_from_params({"model": "oren-nayar-full", "albedo": [0.5] * 3, "sigma": 0.4})
    assert isinstance(m, OrenNayar) and m.variant == "full" and m.sigma == 0.4
    np.testing.assert_array_equal(np.asarray(m.albedo), [0.5, 0.5, 0.5])
    # the mix is (1 - w) diffuse + w specular
    mix = model_from_params(
        {"model": "mix", "albedo": [0.5] * 3, "sigma": 0.3, "weight": 0.25, "eta": 1.4}
    )
    wo = np.array([-math.sin(0.5), 0.0, math.cos(0.5)])
    expected = 0.75 * np.asarray(OrenNayar([0.5] * 3, 0.3, "full").brdf(wi, wo)) + 0.25 * float(
        TorranceSparrow(1.4, 0.3).brdf(wi, wo)
    )
    np.testing.assert_allclose(mix.brdf(wi, wo), expected, rtol=1e-12)
    # σ = 0: every diffuse model is Lambert
    for name in ("oren-nayar", "oren-nayar-full"):
        f = model_from_params({"model": name, "albedo": [0.7] * 3, "sigma": 0.0}).brdf(wi, wo)
        np.testing.assert_allclose(f, Lambert([0.7] * 3).brdf(wi, wo), rtol=1e-12)
    with pytest.raises(ValueError, match="model must be one of"):
        model_from_params({"model": "phong"})
    with pytest.raises(ValueError, match="weight"):
        model_from_params({"model": "mix", "weight": 1.5})


def test_package_data_lists_every_static_file():
    """pyproject's package-data patterns cover every file of the page (so wheels ship it)."""
    import fnmatch
    import tomllib

    root = Path(__file__).resolve().parents[1]
    patterns = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"][
        "package-data"
    ]["roughdiffuse"]
    pkg = STATIC_DIR.parents[1]
    for f in STATIC_DIR.rglob("*"):
        if f.is_file():
            rel = f.relative_to(pkg).as_posix()
            assert any(fnmatch.fnmatch(rel, p) for p in patterns), rel


# The command as a terminal runs it: SIGINT at its default. A process started in the
# background by a shell inherits SIGINT ignored, and Python then installs no KeyboardInterrupt
# handler, so when pytest itself runs in the background (``make test &``) Ctrl-C could not
# reach the server; the child restores the default before it runs ``python -m roughdiffuse``.
_AS_FROM_A_TERMINAL = (
    "import runpy, signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
    "sys.argv[0] = 'roughdiffuse'; runpy.run_module('roughdiffuse', run_name='__main__')"
)


def _start_cli(*args: str) -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen(
        # -X faulthandler: a SIGABRT prints every thread's stack (see _stop_with_ctrl_c)
        [sys.executable, "-X", "faulthandler", "-c", _AS_FROM_A_TERMINAL, "explore",
         "--no-browser", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "BROWSER": "false"},
    )
    line = proc.stdout.readline()
    return proc, line


def _stop_with_ctrl_c(proc: subprocess.Popen) -> None:
    """SIGINT, then wait; a process still running after 30 s fails the test with the stacks of
    its threads (faulthandler on SIGABRT), so that a rare hang can be read from the log."""
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=30)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGABRT)
        _, err = proc.communicate(timeout=30)
        pytest.fail(f"explore did not stop within 30 s of SIGINT; its threads:\n{err[-6000:]}")


def test_cli_serves_the_page_and_stops_on_ctrl_c():
    proc, line = _start_cli()
    try:
        assert line.startswith("roughdiffuse explorer at http://127.0.0.1:"), line
        url = line.split()[3]
        port = int(url.rsplit(":", 1)[1].strip("/"))
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        conn.request("GET", "/")
        r = conn.getresponse()
        assert r.status == 200 and b"roughdiffuse explorer" in r.read()
        conn.close()
    finally:
        _stop_with_ctrl_c(proc)
    assert proc.returncode == 0


def test_cli_bad_port_is_one_line_exit_2():
    r = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "explore", "--no-browser", "--port", "70000"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "port" in r.stderr
