"""Rule: every input is bounded before it is read. Every reader of a user's file refuses a
non-regular file (a FIFO, ``/dev/zero``) and deep or oversized structure with a named
error; every HTTP endpoint with a body answers 400 for them; messages quote a short prefix."""

from __future__ import annotations

import http.client
import json
import os

import numpy as np
import pytest

from roughdiffuse.cli import main


def _fifo(folder, name):
    path = folder / name
    os.mkfifo(path)
    return path


def _readers():
    from roughdiffuse.fit import read_csv, read_image, read_merl, read_normals
    from roughdiffuse.io.reading import read_json
    from roughdiffuse.stereo import read_diligent, read_lights, read_mask

    def diligent(path):
        d = path.parent / "obj"
        d.mkdir()
        os.rename(path, d / "filenames.txt")
        for n in ("light_directions.txt", "light_intensities.txt", "mask.png"):
            (d / n).write_text("1 0 0")
        return read_diligent(d)

    return {
        "data.csv": read_csv,
        "brdf.binary": read_merl,
        "image.npy": read_image,
        "image.png": read_image,
        "image.exr": read_image,
        "normals.npy": read_normals,
        "lights.json": read_lights,
        "mask.npy": read_mask,
        "mask.png": read_mask,
        "any.json": read_json,
        "filenames.txt": diligent,
    }


@pytest.mark.parametrize("name", sorted(_readers()))
def test_every_reader_refuses_a_fifo_without_blocking(name, tmp_path):
    path = _fifo(tmp_path, name)  # opening it for reading would block for ever
    with pytest.raises(ValueError, match="not a regular file"):
        _readers()[name](path)


@pytest.mark.parametrize(
    "argv",
    [
        ["stereo", "a.npy", "b.npy", "c.npy", "--lights", "/dev/zero", "-o", "{tmp}/o"],
        ["fit", "/dev/zero"],
        ["fit", "{tmp}/fifo.csv"],
    ],
)
def test_cli_refuses_devices_in_one_line(argv, tmp_path, capsys):
    _fifo(tmp_path, "fifo.csv")
    for n in "abc":
        np.save(tmp_path / f"{n}.npy", np.ones((4, 4)))
    argv = [a.replace("{tmp}", str(tmp_path)) if "{" in a else a for a in argv]
    argv = [str(tmp_path / a) if a.endswith(".npy") and "/" not in a else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "regular file" in err, err


def test_deep_json_is_refused_by_name(tmp_path):
    from roughdiffuse.stereo import read_lights

    path = tmp_path / "lights.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    with pytest.raises(ValueError, match="nested deeper than 64"):
        read_lights(path)
    path.write_text('{"directions": [[0, 0, 1]], "intensities": [NaN]}')
    with pytest.raises(ValueError, match="NaN is not JSON"):
        read_lights(path)


def test_long_csv_line_is_refused_naming_the_line(tmp_path):
    from roughdiffuse.fit import read_csv

    path = tmp_path / "d.csv"
    path.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n" + "1," * 60_000 + "\n")
    with pytest.raises(ValueError, match="line 2: 120000 characters"):
        read_csv(path)


@pytest.mark.parametrize(
    ("header", "row", "message"),
    [
        ("theta_i_deg,theta_r_deg,delta_phi_deg,brdf,brdf", "10,20,0,0.1,0.2", "'brdf' appears"),
        (
            "theta_i_deg,theta_r_deg,delta_phi_deg,phi_i_deg,phi_r_deg,brdf",
            "10,20,0,0,90,0.1",
            "contradicts phi_r - phi_i",
        ),
    ],
)
def test_duplicated_or_contradicting_columns_are_refused(header, row, message, tmp_path):
    from roughdiffuse.fit import read_csv

    path = tmp_path / "d.csv"
    path.write_text(f"{header}\n{row}\n")
    with pytest.raises(ValueError, match=message):
        read_csv(path)
    path.write_text(f"{header.replace(',brdf,brdf', ',brdf')}\n10,20,0,0,0,0.1\n")
    if "phi_i" in header:  # agreeing columns are accepted
        assert read_csv(path).size == 1


@pytest.mark.parametrize("name", ["image.npy", "normals.npy", "mask.npy"])
def test_complex_arrays_are_refused(name, tmp_path):
    path = tmp_path / name
    np.save(path, np.ones((4, 4, 3)) * (1 + 1j))
    with pytest.raises(ValueError, match="complex numbers"):
        _readers()[name](path)


def test_diligent_names_outside_the_folder_are_refused(tmp_path):
    from roughdiffuse.stereo import read_diligent

    d = tmp_path / "obj"
    d.mkdir()
    (d / "filenames.txt").write_text("001.png\n../../etc/passwd\n")
    for n in ("light_directions.txt", "light_intensities.txt", "mask.png"):
        (d / n).write_text("1 0 0")
    with pytest.raises(ValueError, match="outside the object's folder"):
        read_diligent(d)


def test_messages_quote_a_short_prefix(capsys):
    assert main(["eval", "--model", "x" * 100_000]) == 2
    err = capsys.readouterr().err
    assert "(100000 characters)" in err and len(err) < 1000


@pytest.fixture
def explorer():
    from roughdiffuse.explorer import make_server, serve_in_thread

    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    yield srv.server_address[:2]
    srv.shutdown()
    srv.server_close()


def _post(address, path, body: bytes):
    conn = http.client.HTTPConnection(*address, timeout=60)
    conn.request("POST", path, body, {"Content-Type": "application/json"})
    r = conn.getresponse()
    out = json.loads(r.read() or b"{}")
    conn.close()
    return r.status, out


@pytest.mark.parametrize(
    ("path", "body", "message"),
    [
        ("/api/fit", b"[" * 4000 + b"]" * 4000, "nested deeper"),
        ("/api/rank", b'{"models": ' + b"[" * 4000 + b"]" * 4000 + b"}", "nested deeper"),
        ("/api/fit", b'{"dataset": NaN}', "NaN is not JSON"),
        (
            "/api/data?format=csv",
            b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n1,2,3," + b"9" * 200_000 + b"\n",
            "characters; a line may have at most",
        ),
        (
            "/api/data?format=csv",
            b"theta_i_deg,theta_r_deg,delta_phi_deg,brdf,brdf\n1,2,3,4,5\n",
            "appears more than once",
        ),
    ],
)
def test_every_endpoint_with_a_body_answers_400_for_hostile_bodies(explorer, path, body, message):
    status, out = _post(explorer, path, body)
    assert status == 400 and message in out["error"], out
