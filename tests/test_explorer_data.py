"""Measured data in the explorer: uploads, slices, fits and their limits (server over HTTP),
and the page loading a MERL file and fitting it (headless Chromium).

The MERL file tabulates a known model, Oren–Nayar (full), ρ = (0.6, 0.45, 0.3), σ = 0.35 rad,
written by :func:`roughdiffuse.fit.write_merl`: each cell holds the model at the cell's centre
and :meth:`~roughdiffuse.fit.MERLBRDF.to_measurements` returns the samples at those centres,
so the least-squares minimum is the truth itself (zero residual up to float64 rounding) and
the fit must recover ρ and σ to the optimiser's tolerance, not to a noise level.
"""

from __future__ import annotations

import http.client
import json
import math
import socket
import threading
import time

import numpy as np
import pytest

from explorer_browser import open_page

TRUTH = {"albedo": (0.6, 0.45, 0.3), "sigma": 0.35}


@pytest.fixture(scope="module")
def merl_file(tmp_path_factory):
    from roughdiffuse.fit import MERLBRDF, write_merl
    from roughdiffuse.models import OrenNayar

    path = tmp_path_factory.mktemp("merl") / "oren-nayar-035.binary"
    model = OrenNayar(albedo=TRUTH["albedo"], sigma=TRUTH["sigma"], variant="full")
    write_merl(path, MERLBRDF.from_model(model))
    return path


def _conn(url: str) -> http.client.HTTPConnection:
    host, port = url.split("//")[1].rstrip("/").split(":")
    return http.client.HTTPConnection(host, int(port), timeout=120)


def request(url, method, path, body=None, headers=None):
    """(status, JSON or text) of one request on a new connection."""
    c = _conn(url)
    try:
        c.request(method, path, body=body, headers=headers or {})
        r = c.getresponse()
        data = r.read()
    finally:
        c.close()
    try:
        return r.status, json.loads(data)
    except ValueError:
        return r.status, data.decode()


def post_json(url, path, obj):
    return request(url, "POST", path, json.dumps(obj), {"Content-Type": "application/json"})


@pytest.fixture(scope="module")
def merl_dataset(explorer_url, merl_file):  # noqa: F811 - fixture
    status, out = request(
        explorer_url, "POST", "/api/data?format=merl&name=on.binary", merl_file.read_bytes()
    )
    assert status == 200, out
    return out


def test_merl_upload_fit_and_ranking_recover_the_model(explorer_url, merl_dataset):  # noqa: F811
    from roughdiffuse.explorer.datasets import FIT_SAMPLES

    assert merl_dataset["kind"] == "merl"
    assert merl_dataset["fit_samples"] == FIT_SAMPLES
    assert merl_dataset["theta_i"][:3] == [0.0, 1.0, 2.0]
    assert "oren-nayar-full" in merl_dataset["candidates"]
    status, r = post_json(
        explorer_url, "/api/fit", {"dataset": merl_dataset["id"], "model": "oren-nayar-full"}
    )
    assert status == 200, r
    got = dict(zip(r["names"], r["values"], strict=True))
    # exact data: the optimiser stops within its tolerances (xtol, ftol 1e-8 relative)
    for k, rho in enumerate(TRUTH["albedo"]):
        assert got[f"albedo[{k}]"] == pytest.approx(rho, rel=1e-6)
    assert got["sigma"] == pytest.approx(TRUTH["sigma"], rel=1e-6)
    assert r["rms"] < 1e-9 and r["residuals"] == 3 * FIT_SAMPLES
    # the ranking puts the generating model first; Lambert (σ = 0) is far behind
    status, rk = post_json(
        explorer_url,
        "/api/rank",
        {"dataset": merl_dataset["id"], "models": ["lambert", "oren-nayar-full", "oren-nayar"]},
    )
    assert status == 200, rk
    order = [e["model"] for e in rk["ranking"]]
    assert order[0] == "oren-nayar-full", order
    bic = [e["bic"] for e in rk["ranking"]]
    assert bic == sorted(bic)


def test_merl_slice_is_the_nearest_cell(explorer_url, merl_dataset, merl_file):  # noqa: F811
    """The slice's values are read_merl's own nearest-cell lookup at the same directions, and
    close to the model itself (one cell is ≤ 1° in θd and φd)."""
    from roughdiffuse.fit import read_merl
    from roughdiffuse.models import OrenNayar

    status, s = request(
        explorer_url, "GET", f"/api/data/slice?id={merl_dataset['id']}&theta_i=40&dphi=30"
    )
    assert status == 200, s
    tr = np.radians(np.abs(s["theta_r"]))
    phi = np.where(np.asarray(s["theta_r"]) >= 0, math.radians(30), math.radians(210))
    wi = np.tile([math.sin(math.radians(40)), 0.0, math.cos(math.radians(40))], (tr.size, 1))
    wo = np.stack([np.sin(tr) * np.cos(phi), np.sin(tr) * np.sin(phi), np.cos(tr)], axis=-1)
    expected = read_merl(merl_file).lookup(wi, wo)
    got = np.array([v if v is not None else [np.nan] * 3 for v in s["brdf"]])
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    ok = ~np.isnan(got[:, 0])
    assert ok.sum() > 150
    np.testing.assert_allclose(got[ok], expected[ok], rtol=1e-12)
    model = OrenNayar(albedo=TRUTH["albedo"], sigma=TRUTH["sigma"], variant="full")
    f = np.asarray(model.brdf(wi[ok], wo[ok]))
    # the nearest cell's centre is within half a cell: a few % of a smooth diffuse BRDF
    inner = np.abs(np.asarray(s["theta_r"])[ok]) < 80
    np.testing.assert_allclose(got[ok][inner], f[inner], rtol=0.05)


def _merl_bytes(merl_file) -> bytes:
    return merl_file.read_bytes()


@pytest.mark.parametrize(
    ("case", "status", "message"),
    [
        ("short", 400, "not a MERL file: 34991004 bytes"),
        ("dims", 400, "MERL dimensions must be 90 x 90 x 180"),
        ("nan", 400, "entries are NaN or infinite"),
        ("csv", 400, "line 3"),
        ("format", 400, "format must be 'merl' or 'csv'"),
    ],
)
def test_malformed_uploads_are_refused_with_a_message(
    explorer_url,  # noqa: F811 - fixture
    merl_file,
    case,
    status,
    message,
):
    blob = bytearray(_merl_bytes(merl_file))
    fmt = "merl"
    if case == "short":
        blob = blob[:-1008]
    elif case == "dims":
        blob[0:4] = np.int32(45).tobytes()
    elif case == "nan":
        blob[12 + 8 * 1000 : 12 + 8 * 1001] = np.float64(np.nan).tobytes()
    elif case == "csv":
        fmt = "csv"
        blob = bytearray(b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n10,x,0,1\n")
    elif case == "format":
        fmt, blob = "png", bytearray(b"\x89PNG")  # refused before the body is read
    code, out = request(explorer_url, "POST", f"/api/data?format={fmt}&name=f", bytes(blob))
    assert code == status, out
    assert message in out["error"], out


def test_oversized_and_unframed_uploads_are_refused_unread(explorer_url):  # noqa: F811
    from roughdiffuse.explorer.datasets import MAX_CSV_BYTES, MAX_MERL_BYTES

    for fmt, limit in (("merl", MAX_MERL_BYTES), ("csv", MAX_CSV_BYTES)):
        c = _conn(explorer_url)
        c.putrequest("POST", f"/api/data?format={fmt}")
        c.putheader("Content-Length", str(limit + 1))
        c.endheaders()  # no body is sent: the answer comes from the header alone
        r = c.getresponse()
        assert r.status == 413
        assert f"at most {limit}" in json.loads(r.read())["error"]
        c.close()
    c = _conn(explorer_url)
    c.putrequest("POST", "/api/data?format=csv", skip_accept_encoding=True)
    c.putheader("Transfer-Encoding", "chunked")
    c.endheaders()
    r = c.getresponse()
    assert r.status == 411
    c.close()


def test_cross_origin_post_is_refused(explorer_url):  # noqa: F811
    code, _ = request(
        explorer_url,
        "POST",
        "/api/data?format=csv",
        b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n0,0,0,0.2\n",
        {"Origin": "http://example.com"},
    )
    assert code == 403


def test_fits_and_uploads_are_bounded(explorer_url, merl_dataset, monkeypatch):  # noqa: F811
    """A second fit while one runs gets 503 at once; so does an upload beyond the slots; a
    trickling upload is cut off; an unknown dataset or model gets 404/400."""
    from roughdiffuse.explorer import datasets, server

    req = {"dataset": merl_dataset["id"], "model": "lambert"}
    with datasets.FIT_LOCK:
        code, out = post_json(explorer_url, "/api/fit", req)
    assert code == 503 and "already running" in out["error"]
    held = [server.UPLOAD_SLOTS.acquire(blocking=False) for _ in range(server.UPLOADS_AT_ONCE)]
    try:
        assert all(held)
        code, out = request(explorer_url, "POST", "/api/data?format=csv", b"x")
        assert code == 503
    finally:
        for _ in held:
            server.UPLOAD_SLOTS.release()
    code, out = post_json(explorer_url, "/api/fit", {"dataset": "nope", "model": "lambert"})
    assert code == 404 and "load the file again" in out["error"]
    code, out = post_json(explorer_url, "/api/fit", {**req, "model": "vcavity-x"})
    assert code == 400 and "model must be one of" in out["error"]
    code, out = post_json(explorer_url, "/api/rank", {**req, "models": ["lambert"] * 9})
    assert code == 400
    # a client that announces 1000 bytes and sends 10 is cut off after UPLOAD_SECONDS
    monkeypatch.setattr(server, "UPLOAD_SECONDS", 1.0)
    host, port = explorer_url.split("//")[1].rstrip("/").split(":")
    with socket.create_connection((host, int(port)), timeout=30) as s:
        s.sendall(
            f"POST /api/data?format=csv HTTP/1.1\r\nHost: {host}:{port}\r\n"
            "Content-Length: 1000\r\n\r\n0123456789".encode()
        )
        t0 = time.monotonic()
        answer = s.recv(4096).decode()
    assert answer.startswith("HTTP/1.0 408") or answer.startswith("HTTP/1.1 408"), answer
    assert time.monotonic() - t0 < 25  # cut off by the deadline, not the client


def test_store_keeps_the_most_recently_used():
    from roughdiffuse.explorer.datasets import DatasetStore, parse_upload

    store = DatasetStore(maxsize=2)
    text = b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n30,20,0,0.2\n"
    a, b = (parse_upload("csv", n, text, store) for n in ("a.csv", "b.csv"))
    assert a.theta_i == [10.0, 30.0]
    store.get(a.id)  # a is used: b is now the least recently used
    c = parse_upload("csv", "c.csv", text, store)
    assert len(store) == 2
    assert store.get(a.id) is a and store.get(c.id) is c
    with pytest.raises(KeyError):
        store.get(b.id)


def test_merl_through_the_page_is_fitted(browser, explorer_url, merl_file):  # noqa: F811
    """Choose the file on the page, fit model A (Oren–Nayar full), rank two models: the
    sliders move to the truth, the table shows it, no console error."""
    log = open_page(browser, explorer_url)
    p = log.page
    try:
        p.select_option("#a-model", "oren-nayar-full")
        p.set_input_files("#data-file", str(merl_file))
        p.wait_for_function("() => document.body.dataset.dataLoaded === 'merl'", timeout=120_000)
        p.wait_for_function("() => Number(document.body.dataset.slicePoints) > 150")
        assert "MERL BRDF" in p.locator("#data-status").inner_text()
        # θi selector: stepping it moves the light to the data's angle
        p.locator("#data-theta-i").fill("40")
        p.wait_for_function(
            "() => document.getElementById('light-readout').textContent"
            ".startsWith('light θ = 40.0°')"
        )
        p.wait_for_function("() => Number(document.body.dataset.csvPoints) > 150")
        p.click("#fit-run")
        p.wait_for_function("() => document.body.dataset.fit === 'done'", timeout=120_000)
        a = p.evaluate("() => window.rdExplorer.state.a")
        # the state holds the fitted values; the sliders show them to one step
        np.testing.assert_allclose(a["albedo"], TRUTH["albedo"], rtol=1e-5)
        assert a["sigmaDeg"] == pytest.approx(math.degrees(TRUTH["sigma"]), rel=1e-5)
        assert abs(float(p.locator("#a-sigma").input_value()) - 20.05) <= 0.5
        assert abs(float(p.locator("#a-albedo-b").input_value()) - 0.3) <= 0.005
        table = p.locator("#fit-table").inner_text()
        assert "sigma" in table and "20.054°" in table, table
        assert "RMS residual" in p.locator("#fit-status").inner_text()
        order = p.evaluate("() => window.rdData.rank(['lambert', 'oren-nayar-full'])")
        assert order[0] == "oren-nayar-full"
        assert p.locator("#rank-table tr[data-model]").first.get_attribute("data-model") == (
            "oren-nayar-full"
        )
        # Δφ and channel: the model curves and the data stay together (red channel, 60°)
        p.locator("#data-dphi").fill("60")
        p.select_option("#data-channel", "0")
        p.wait_for_function("() => Number(document.body.dataset.csvPoints) > 150")
        # the curves' geometry at Δφ = 60°: cos_io = wi·wo with wo at azimuth 60° (θr > 0)
        # or 240° (θr < 0), from the vectors themselves
        cos = p.evaluate(
            """async () => {
                const { sliceCosines } = await import("./js/data.js");
                return Array.from(sliceCosines(40, [-30, 50]));
            }"""
        )
        ti = math.radians(40)
        wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
        for k, (tr, az) in enumerate(((30, 240), (50, 60))):
            t, a = math.radians(tr), math.radians(az)
            wo = np.array([math.sin(t) * math.cos(a), math.sin(t) * math.sin(a), math.cos(t)])
            expected = [wi[2], wo[2], wi @ wo]
            np.testing.assert_allclose(cos[3 * k : 3 * k + 3], expected, atol=1e-6)  # float32
        assert not log.errors, log.errors
    finally:
        p.close()


def test_bad_files_on_the_page_give_a_message(browser, explorer_url):  # noqa: F811
    log = open_page(browser, explorer_url)
    p = log.page
    try:
        with p.expect_response(lambda r: "/api/data" in r.url) as resp:
            p.set_input_files(
                "#data-file",
                files=[
                    {
                        "name": "short.binary",
                        "mimeType": "application/octet-stream",
                        "buffer": b"\x5a\x00\x00\x00" * 3 + b"\x00" * 5000,
                    }
                ],
            )
        assert resp.value.status == 400
        p.wait_for_function("() => document.body.dataset.dataLoaded === 'error'")
        status = p.locator("#data-status")
        assert "not a MERL file: 5012 bytes" in status.inner_text()
        assert "error" in status.get_attribute("class")
        # larger than any MERL file: refused on the page before it is sent
        from roughdiffuse.explorer.datasets import MAX_MERL_BYTES

        # (made in the page: sending 36 MB through Playwright's protocol takes minutes)
        p.evaluate(
            """(n) => {
                const dt = new DataTransfer();
                dt.items.add(new File([new ArrayBuffer(n)], "big.binary"));
                const init = { dataTransfer: dt, bubbles: true, cancelable: true };
                document.getElementById("dropzone").dispatchEvent(new DragEvent("drop", init));
            }""",
            MAX_MERL_BYTES + 1,
        )
        p.wait_for_function(
            "() => document.getElementById('data-status').textContent.includes('too large')"
        )
        # the browser itself logs the refused request ("status of 400"); nothing else
        assert all("status of 400" in e for e in log.errors), log.errors
    finally:
        p.close()


def test_concurrent_requests_do_not_break_the_server(explorer_url, merl_dataset):  # noqa: F811
    """Many uploads and fits at once: every one is answered (200, 4xx or 503), and the
    server still serves the page afterwards."""
    text = b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n30,20,0,0.2\n"
    codes: list[int] = []

    def one(k: int) -> None:
        try:
            if k % 2:
                code, _ = request(explorer_url, "POST", "/api/data?format=csv", text)
            else:
                code, _ = post_json(
                    explorer_url, "/api/fit", {"dataset": merl_dataset["id"], "model": "lambert"}
                )
        except (ConnectionError, http.client.HTTPException):
            code = -1  # refused at the door (503 written before the request was read)
        codes.append(code)

    threads = [threading.Thread(target=one, args=(k,)) for k in range(40)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
    assert len(codes) == 40
    # 404: the CSV uploads pushed the MERL dataset out of the store (it keeps DATASETS_KEPT)
    assert set(codes) <= {200, 404, 503, -1}, codes
    assert 200 in codes
    code, _ = request(explorer_url, "GET", "/api/info.json")
    assert code == 200


def test_csv_upload_fit_recovers_the_shipped_samples(explorer_url):  # noqa: F811
    """The shipped samples.csv (Oren–Nayar full, ρ = 0.7, σ = 0.35 rad, 1 % noise, see
    roughdiffuse.data): the fit lands within 4 standard errors of the truth."""
    from roughdiffuse import data

    text = data.path("samples.csv").read_bytes()
    code, ds = request(explorer_url, "POST", "/api/data?format=csv&name=samples.csv", text)
    assert code == 200, ds
    assert ds["kind"] == "csv" and ds["theta_i"] == [float(t) for t in range(0, 90, 10)]
    code, r = post_json(explorer_url, "/api/fit", {"dataset": ds["id"], "model": "oren-nayar-full"})
    assert code == 200, r
    got = dict(zip(r["names"], zip(r["values"], r["errors"], strict=True), strict=True))
    for name, truth in (("albedo", 0.7), ("sigma", 0.35)):
        value, err = got[name]
        assert 0 < err < 0.05 and abs(value - truth) < 4 * err, (name, value, err)
