"""A writer writes only what it was told to, to a regular file: no device or FIFO replaced,
every file it writes named and kept without --force, a child's output checked."""

from __future__ import annotations

import os
import socket
import stat
import sys

import pytest

from roughdiffuse.cli import main
from roughdiffuse.exporters import blender_run
from roughdiffuse.io import write_text


def run(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


@pytest.fixture
def no_blender(monkeypatch):
    monkeypatch.delenv(blender_run.ENV, raising=False)
    monkeypatch.setattr(blender_run, "_beside_package", lambda: [])


def _fifo(tmp_path, name):
    path = tmp_path / name
    os.mkfifo(path)
    return path


def _socket(tmp_path, name):
    path = tmp_path / name
    sock = socket.socket(socket.AF_UNIX)
    sock.bind(str(path))
    sock.close()
    return path


@pytest.mark.parametrize("make", [_fifo, _socket])
@pytest.mark.parametrize("force", [[], ["--force"]])
def test_export_never_replaces_a_fifo_or_socket(tmp_path, capsys, make, force):
    special = make(tmp_path, "out.xml")
    code = run(["export", "--model", "eon", "--to", "mitsuba", "-o", str(special), *force])
    err = capsys.readouterr().err
    assert code == 2 and "not a regular file" in err and len(err.strip().splitlines()) == 1
    assert not stat.S_ISREG(os.lstat(special).st_mode)
    assert not (tmp_path / "out.py").exists()


@pytest.mark.parametrize("make", [_fifo, _socket])
def test_the_atomic_writer_refuses_a_special_file_for_every_caller(tmp_path, make):
    special = make(tmp_path, "t.txt")
    with pytest.raises(ValueError, match="not a regular file"):
        write_text(special, "x")
    assert not stat.S_ISREG(os.lstat(special).st_mode)


def test_mitsuba_export_keeps_the_py_beside_the_xml(tmp_path, capsys):
    xml, py = tmp_path / "x.xml", tmp_path / "x.py"
    py.write_text("mine\n")
    assert run(["export", "--model", "eon", "--to", "mitsuba", "-o", str(xml)]) == 2
    err = capsys.readouterr().err
    assert str(py) in err and "--force" in err
    assert py.read_text() == "mine\n" and not xml.exists()
    assert run(["export", "--model", "eon", "--to", "mitsuba", "-o", str(xml), "--force"]) == 0
    out = capsys.readouterr().out
    assert str(xml) in out and str(py) in out  # the summary names every file written
    assert py.read_text() != "mine\n"


def test_mitsuba_builtin_scene_is_named_and_kept(tmp_path, capsys):
    builtin = tmp_path / "x_builtin.xml"
    builtin.write_text("mine\n")
    argv = ["export", "--model", "lambert", "--to", "mitsuba", "-o", str(tmp_path / "x.xml")]
    assert run(argv) == 2
    assert str(builtin) in capsys.readouterr().err and builtin.read_text() == "mine\n"


def test_an_existing_output_is_kept_without_force(tmp_path, capsys, no_blender):
    out = tmp_path / "m.mtlx"
    out.write_text("mine\n")
    assert run(["export", "--model", "eon", "--to", "materialx", "-o", str(out)]) == 2
    assert out.read_text() == "mine\n"


def test_blender_export_keeps_an_existing_blend_before_blender_runs(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv(blender_run.ENV, sys.executable)  # "found": the .blend will be written
    blend = tmp_path / "m.blend"
    blend.write_bytes(b"BLENDER-mine")
    assert run(["export", "--model", "eon", "--to", "blender", "-o", str(tmp_path / "m.py")]) == 2
    assert str(blend) in capsys.readouterr().err
    assert blend.read_bytes() == b"BLENDER-mine" and not (tmp_path / "m.py").exists()


def test_a_child_that_exits_0_and_writes_nothing_leaves_no_blend(tmp_path, capsys, monkeypatch):
    fake = tmp_path / "fake-blender-python"
    fake.write_text("#!/bin/sh\nexit 0\n")
    fake.chmod(0o755)
    monkeypatch.setenv(blender_run.ENV, str(fake))
    code = run(["export", "--model", "eon", "--to", "blender", "-o", str(tmp_path / "m.py")])
    err = capsys.readouterr().err
    assert code == 2 and "wrote no .blend" in err
    assert not (tmp_path / "m.blend").exists()


def test_a_blend_writes_nothing_but_the_blend_beside_it(tmp_path, capsys, monkeypatch):
    """Blender saving over an existing file also writes a backup NAME.blend1; a child doing
    so leaves only m.py and m.blend in the output's folder (a 0-byte .blend1 was left)."""
    fake = tmp_path / "bin" / "fake-blender-python"
    fake.parent.mkdir()
    fake.write_text(
        f"#!{sys.executable}\nimport json, pathlib, sys\n"
        "job = json.loads(pathlib.Path(sys.argv[-1]).read_text())['jobs'][0]\n"
        "out = pathlib.Path(job['output'])\n"
        "pathlib.Path(str(out) + '1').write_bytes(b'')\n"
        "out.write_bytes(b'BLENDER-v500 a scene')\n"
    )
    fake.chmod(0o755)
    monkeypatch.setenv(blender_run.ENV, str(fake))
    out = tmp_path / "out"
    out.mkdir()
    assert run(["export", "--model", "eon", "--to", "blender", "-o", str(out / "m.py")]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["m.blend", "m.py"]
    assert (out / "m.blend").read_bytes() == b"BLENDER-v500 a scene"


def test_check_blend_accepts_the_three_headers_and_refuses_others(tmp_path):
    f = tmp_path / "a.blend"
    for head in (b"BLENDER-v304", b"\x28\xb5\x2f\xfd....", b"\x1f\x8b\x08...."):
        f.write_bytes(head)
        blender_run.check_blend(f)
    for bad in (b"", b"<html>"):
        f.write_bytes(bad)
        with pytest.raises(blender_run.BlenderError, match="not a .blend"):
            blender_run.check_blend(f)


def test_empty_output_name_is_named_as_empty(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(["export", "--model", "eon", "--to", "mitsuba", "-o", ""]) == 2
    err = capsys.readouterr().err
    assert "-o/--output: empty value" in err and "'.'" not in err
    with pytest.raises(ValueError, match="''"):
        write_text("", "x")


EMPTY_VALUES = [
    (["figures", "-o", ""], "-o/--output"),  # was: the figures drawn into the current folder
    (["figures", "--output="], "-o/--output"),
    (["albedo", "--model", "lambert", "--table", ""], "--table"),  # was: no table, exit 0
    (["fit", "data:samples.csv", "--model", "lambert", "--report", ""], "--report"),
    (["bench", "--output-dir", ""], "--output-dir"),  # was: the whole benchmark, then "."
    (["simulate", "--table", " "], "--table"),  # was: a simulation without its table
    (["photometry", "fit", "x.csv", "--report", ""], "--report"),  # a nested command
    (["photometry", "correct", "x.npy", "-o", ""], "-o/--output"),
    (["eval", "--param", ""], "--param"),
    (["render", "--model", "lambert", "-o", "r.png", "--shape", ""], "--shape"),
]


@pytest.mark.parametrize(
    ("argv", "flag"), EMPTY_VALUES, ids=lambda v: " ".join(v) if isinstance(v, list) else v
)
def test_an_empty_value_of_any_option_is_refused_before_any_work(
    tmp_path, capsys, monkeypatch, argv, flag
):
    """An empty option value is never read as "not given": refused by name, nothing written."""
    monkeypatch.chdir(tmp_path)
    assert run(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"argument {flag}: empty value" in err, err
    assert os.listdir(tmp_path) == []


def test_output_suffix_is_the_targets(tmp_path, capsys):
    """-o X.py with --to mitsuba would write the XML and its .py to one name."""
    assert run(["export", "--model", "eon", "--to", "mitsuba", "-o", str(tmp_path / "x.py")]) == 2
    assert ".xml" in capsys.readouterr().err and not (tmp_path / "x.py").exists()


def test_export_help_names_every_file(capsys):
    with pytest.raises(SystemExit):
        main(["export", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    for name in ("FILE.py", "FILE_builtin.xml", "FILE.mtlx", "FILE.blend", "--force"):
        assert name in out


def test_fit_export_keeps_existing_files_before_fitting(tmp_path, capsys, no_blender):
    data = tmp_path / "d.csv"
    data.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n30,0,0,0.2\n")
    kept = tmp_path / "m_mitsuba.py"
    kept.write_text("mine\n")
    argv = ["fit", str(data), "--model", "lambert", "--export", "mitsuba",
            "--export-prefix", str(tmp_path / "m")]  # fmt: skip
    assert run(argv) == 2
    assert str(kept) in capsys.readouterr().err and kept.read_text() == "mine\n"


def test_a_table_with_a_254_character_name_is_written(tmp_path, capsys):
    """Its lock and folder of chunks get shortened names (io.atomic.beside), as the
    temporary files do."""
    from roughdiffuse.io.atomic import beside
    from roughdiffuse.simulate.table import load_table

    path = tmp_path / ("t" * 250 + ".npz")
    argv = ["simulate", "--table", str(path), "--step", "45", "--delta-phi-step", "180",
            "--sigma", "10", "--bounces", "1", "--no-progress"]  # fmt: skip
    assert run(argv) == 0, capsys.readouterr().err
    assert load_table(path).values.shape[0] == 3
    lock = beside(path, ".lock")
    assert len(lock.name.encode()) <= 255 and lock != beside(tmp_path / ("t" * 251), ".lock")


def _planes(tmp_path):
    import numpy as np

    for name, value in {"img": 0.1, "i": 30.0, "e": 20.0, "g": 40.0}.items():
        np.save(tmp_path / f"{name}.npy", np.full((8, 8), value, np.float32))
    rasterio = pytest.importorskip("rasterio")  # a DEM is a map: GDAL reads it
    from rasterio.transform import from_origin

    kw = {"crs": "EPSG:32633", "transform": from_origin(5e5, 4e6, 100.0, 100.0)}
    with rasterio.open(tmp_path / "dem.tif", "w", driver="GTiff", width=8, height=8,
                       count=1, dtype="float32", **kw) as dem:  # fmt: skip
        dem.write(np.zeros((1, 8, 8), np.float32))
    return ["--incidence", "i.npy", "--emission", "e.npy", "--phase", "g.npy"]


PHOTOMETRY_WRITERS = [
    pytest.param(["photometry", "correct", "img.npy", "PLANES", "-o", "out.npy"], ["out.npy"],
                 id="correct"),
    pytest.param(
        ["photometry", "angles", "dem.tif", "--sun-vector", "0,0,1", "--observer-vector",
         "0,0,1", "-o", "a.npy"],
        ["a-incidence.npy", "a-emission.npy", "a-phase.npy", "a-slope.npy", "a-azimuth.npy"],
        id="angles",
    ),
    pytest.param(  # the fit and its report's figures: about 4 s
        ["photometry", "fit", "data.csv", "--model", "lommel-seeliger", "--report", "fit.html"],
        ["fit.html"], marks=pytest.mark.slow, id="fit",
    ),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "outputs"), PHOTOMETRY_WRITERS)
def test_photometry_keeps_existing_outputs_without_force(
    tmp_path, capsys, monkeypatch, argv, outputs
):
    """photometry correct, angles and fit --report follow every writer's rule: an existing
    output is kept unless --force (they replaced it unasked)."""
    monkeypatch.chdir(tmp_path)
    planes = _planes(tmp_path)
    argv = [a for word in argv for a in (planes if word == "PLANES" else [word])]
    geometries = [(i, e, i + e - 5) for i in (20, 35, 50, 65) for e in (10, 30, 50)]
    rows = ["incidence,emission,phase,iof", *(f"{i},{e},{g},0.1" for i, e, g in geometries)]
    (tmp_path / "data.csv").write_text("\n".join(rows) + "\n")
    (tmp_path / outputs[-1]).write_text("keep")
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert f"{outputs[-1]} exists; use --force" in err, err
    assert (tmp_path / outputs[-1]).read_text() == "keep"
    assert all(not (tmp_path / o).exists() for o in outputs[:-1])
    assert run([*argv, "--force"]) == 0, capsys.readouterr().err
    assert all((tmp_path / o).stat().st_size > 4 for o in outputs)
