"""Rules 2, 5 and 6: results are never silently the starting guess; every failure of the
system is a one-line named error and a refused run leaves nothing that blocks the next;
races, network bindings, environment flags and bound values are handled one way."""

from __future__ import annotations

import errno
import math
import os
import socket
import types

import numpy as np
import pytest

from roughdiffuse.cli import main
from roughdiffuse.io import WriteError, write_text


def run(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


# ----------------------------------------------------------------- rule 2: results


def test_fit_problem_names_a_residual_of_the_datas_size_and_no_convergence():
    from roughdiffuse.fit.sanity import fit_problem

    assert fit_problem(0.05) is None
    assert "100%" in fit_problem(1.0)  # a model at zero has relative residual 1
    assert "did not converge" in fit_problem(math.nan)
    assert "did not converge" in fit_problem(0.05, ("optimizer: max evaluations",))


def test_fit_command_refuses_the_start_values_as_a_result(tmp_path, monkeypatch, capsys):
    import roughdiffuse.fit as fitpkg

    start = types.SimpleNamespace(
        rms=1e18,
        aic=0.0,
        bic=0.0,
        values=np.array([0.5, 0.785]),
        rms_relative=1.0,
        warnings=(),
        model_name="OrenNayar",
        table=lambda: "rho 0.5 sigma 45 deg",
    )
    monkeypatch.setattr(fitpkg, "fit", lambda *a, **k: start)
    data = tmp_path / "d.csv"
    data.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,1e18\n30,0,0,1e18\n")
    assert run(["fit", str(data), "--model", "oren-nayar"]) == 2
    out, err = capsys.readouterr()
    assert "relative RMS residual of 100%" in err and "sigma 45" not in out


@pytest.mark.parametrize("sigma", [1e-300, 1e-200, 1e-160, 1e-13])
def test_vcavity_is_accurate_down_to_the_smallest_sigma(sigma):
    import roughdiffuse as rd
    from roughdiffuse import simulate

    wi = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    wo = np.array([0.0, 0.0, 1.0])
    flat = 0.8 / math.pi  # σ -> 0: a flat Lambertian plane, f = ρ/π
    assert float(rd.VCavity(0.8, sigma).brdf(wi, wo)) == pytest.approx(flat, rel=1e-14)
    assert float(simulate.brdf(0.5, 0.0, 0.0, sigma, 0.8, "all")) == pytest.approx(flat, rel=1e-14)


# ----------------------------------------------------------------- rule 5: system failures


def _full_disk(monkeypatch):
    real = os.statvfs
    monkeypatch.setattr(
        os, "statvfs", lambda p: types.SimpleNamespace(**{**_fields(real(p)), "f_bavail": 0})
    )


def _fields(st):
    return {k: getattr(st, k) for k in dir(st) if k.startswith("f_")}


def test_a_library_error_on_a_full_disk_is_a_named_write_error(tmp_path, monkeypatch):
    from roughdiffuse.io import atomic_write

    _full_disk(monkeypatch)

    def library_writer(tmp):
        raise RuntimeError("Cannot write image file")  # as OpenEXR and others say it

    with pytest.raises(WriteError) as info:
        atomic_write(tmp_path / "r.exr", library_writer)
    assert info.value.errno == errno.ENOSPC
    assert str(info.value) == f"cannot write {str(tmp_path / 'r.exr')!r}: No space left on device"
    assert sorted(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "argv",
    [
        ["render", "--size", "8", "--spp", "1", "-o", "{tmp}/r.exr"],
        ["plot", "plane", "--model", "lambert", "-o", "{tmp}/p.pdf"],
        ["render", "--size", "8", "--spp", "1", "-o", "{tmp}/r.npy"],
    ],
)
def test_full_disk_under_every_writer_is_exit_2(argv, tmp_path, monkeypatch, capsys):
    _full_disk(monkeypatch)
    real_fsync = os.fsync

    def fsync(fd):  # where a full disk shows itself at the latest
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    import matplotlib.figure
    import OpenEXR

    class Exr:
        def __init__(self, *a, **k):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *a):
            return False

        def write(self, path):
            raise RuntimeError("Cannot write")

    monkeypatch.setattr(OpenEXR, "File", Exr)
    monkeypatch.setattr(
        matplotlib.figure.Figure, "savefig", lambda *a, **k: (_ for _ in ()).throw(RuntimeError())
    )
    monkeypatch.setattr(os, "fsync", fsync)
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    assert run(argv) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and "internal error" not in err
    assert sorted(tmp_path.iterdir()) == []
    monkeypatch.setattr(os, "fsync", real_fsync)


def test_the_longest_legal_name_can_be_written(tmp_path):
    for name in ("a" * 251 + ".txt", "é" * 125 + ".npy", "b" * 255):
        write_text(tmp_path / name, "x")
        assert (tmp_path / name).read_text() == "x"
    assert len(list(tmp_path.iterdir())) == 3  # no temporary left


def test_a_full_disk_leaves_no_empty_lock_file(tmp_path, monkeypatch):
    from roughdiffuse.simulate import table

    def full(fd, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(table.os, "write", full)
    with pytest.raises(OSError):
        with table._TableLock(tmp_path / "t.npz"):
            pass
    assert sorted(tmp_path.iterdir()) == []


def test_a_refused_table_run_does_not_block_the_next(tmp_path, monkeypatch):
    from roughdiffuse.simulate import table

    calls = []

    def unreachable(todo, *a, **k):
        calls.append(len(todo))
        raise OSError(errno.ECONNREFUSED, "cannot reach the scheduler")

    monkeypatch.setattr(table, "_run_chunks", unreachable)
    out = tmp_path / "t.npz"
    grid = np.radians([0.0, 45.0])
    with pytest.raises(OSError):
        table.compute_table(out, grid, grid, grid, [0.2], 0.8, 1)
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no chunks folder, no lock
    with pytest.raises(OSError):  # other settings: computed, not refused for old chunks
        table.compute_table(out, grid, grid, grid, [0.3], 0.8, 1)
    assert len(calls) == 2
    # a manifest left by a crashed run, without any chunk, does not block either
    (tmp_path / "t.npz.chunks").mkdir()
    (tmp_path / "t.npz.chunks" / "manifest.json").write_text('{"key": "other"}')
    with pytest.raises(OSError):
        table.compute_table(out, grid, grid, grid, [0.3], 0.8, 1)
    assert len(calls) == 3


def test_data_dir_under_a_file_is_a_value_error(tmp_path, monkeypatch):
    from roughdiffuse import data

    (tmp_path / "file").write_text("x")
    monkeypatch.setenv("ROUGHDIFFUSE_DATA_DIR", str(tmp_path / "file" / "data"))
    with pytest.raises(ValueError, match="ROUGHDIFFUSE_DATA_DIR .* is not a folder"):
        data.path("oren-nayar.binary")


# ----------------------------------------------------------------- rule 6: races and bindings


def test_a_file_made_meanwhile_is_not_replaced_without_force(tmp_path):
    from roughdiffuse.commands._checks import output_file

    out = output_file(tmp_path / "cc.png", (".png",))  # checked: free
    out.write_text("another run's image")  # another writer finishes first
    with pytest.raises(WriteError, match="exists; use --force"):
        write_text(out, "ours")
    assert out.read_text() == "another run's image"
    output_file(out, (".png",), force=True)
    write_text(out, "ours")  # with --force it is replaced
    assert out.read_text() == "ours"


@pytest.mark.parametrize("command", ["render", "fit-report"])
def test_concurrent_writers_without_force_cannot_both_write(command, tmp_path, monkeypatch, capsys):
    import roughdiffuse.render as render_pkg

    target = tmp_path / ("cc.png" if command == "render" else "r.html")
    real = render_pkg.render

    def racing(*a, **k):  # the other run writes the file while this one renders
        target.write_text("the other run")
        return real(*a, **k)

    if command == "render":
        monkeypatch.setattr(render_pkg, "render", racing)
        argv = ["render", "--size", "8", "--spp", "1", "-o", str(target)]
    else:
        import roughdiffuse.fit as fitpkg

        def fit(*a, **k):
            target.write_text("the other run")
            return types.SimpleNamespace(
                rms=0.01,
                aic=0.0,
                bic=0.0,
                values=np.array([0.5]),
                rms_relative=0.01,
                warnings=(),
                model_name="Lambert",
                table=lambda: "",
            )

        monkeypatch.setattr(fitpkg, "fit", fit)
        monkeypatch.setattr(
            "roughdiffuse.fit.report.write_report", lambda p, *a: write_text(p, "x")
        )
        data = tmp_path / "d.csv"
        data.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n30,0,0,0.2\n")
        argv = ["fit", str(data), "--model", "lambert", "--report", str(target)]
    assert run(argv) == 2
    assert "exists; use --force" in capsys.readouterr().err
    assert target.read_text() == "the other run"


def test_fit_report_is_kept_without_force(tmp_path, capsys):
    report = tmp_path / "r.html"
    report.write_text("kept")
    data = tmp_path / "d.csv"
    data.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n")
    assert run(["fit", str(data), "--report", str(report)]) == 2
    assert "exists; use --force" in capsys.readouterr().err and report.read_text() == "kept"


@pytest.mark.parametrize("host", ["0.0.0.0", "::", "192.0.2.1"])
def test_explore_refuses_hosts_other_machines_reach(host, capsys):
    assert run(["explore", "--host", host, "--no-browser"]) == 2
    assert "--expose-to-network" in capsys.readouterr().err


@pytest.mark.parametrize("host", ["", " "])
def test_an_empty_host_is_refused_as_every_empty_option_value(host, capsys):
    """"" would bind every interface (Python's socket): refused by the parser, by name."""
    assert run(["explore", "--host", host, "--no-browser"]) == 2
    assert "--host: empty value" in capsys.readouterr().err


def test_explore_binds_a_wildcard_only_when_asked():
    from roughdiffuse.explorer import make_server

    with pytest.raises(ValueError, match="--expose-to-network"):
        make_server("0.0.0.0", None)
    srv = make_server("0.0.0.0", None, expose_to_network=True)
    srv.server_close()


def test_stalled_upload_message_says_the_enforced_time(monkeypatch):
    from roughdiffuse.explorer import make_server, serve_in_thread, server

    monkeypatch.setattr(server, "IDLE_TIMEOUT", 0.5)
    monkeypatch.setattr(server.ExplorerHandler, "timeout", 0.5)
    srv = make_server("127.0.0.1", None)
    serve_in_thread(srv)
    try:
        host, port = srv.server_address[:2]
        with socket.create_connection((host, port), timeout=30) as s:
            s.sendall(
                f"POST /api/data?format=csv HTTP/1.1\r\nHost: {host}:{port}\r\n"
                "Content-Length: 1000\r\n\r\n0123456789".encode()
            )
            chunks = []
            while chunk := s.recv(4096):  # the server closes after its answer
                chunks.append(chunk)
            answer = b"".join(chunks).decode()
    finally:
        srv.shutdown()
        srv.server_close()
    assert " 408 " in answer.splitlines()[0]
    assert "nothing arrived for 0.5 s" in answer and "120" not in answer


@pytest.mark.parametrize(
    ("value", "traceback"),
    [("false", False), ("0", False), ("", False), ("TRUE", True), ("1", True)],
)
def test_boolean_environment_flags_parse_one_way(value, traceback, monkeypatch, capsys):
    monkeypatch.setenv("ROUGHDIFFUSE_DEBUG", value)
    assert run(["eval", "--model", "no-such"]) == 2
    assert ("Traceback" in capsys.readouterr().err) is traceback


def test_an_unreadable_boolean_flag_is_refused_by_name(monkeypatch, capsys):
    from roughdiffuse._env import env_flag

    monkeypatch.setenv("ROUGHDIFFUSE_DEBUG", "maybe")
    assert run(["models"]) == 2
    assert "ROUGHDIFFUSE_DEBUG" in capsys.readouterr().err
    monkeypatch.setenv("ROUGHDIFFUSE_FASTPATH", " Off ")
    assert env_flag("ROUGHDIFFUSE_FASTPATH", default=True) is False


def test_tiny_and_huge_direction_vectors_are_normalised_before_judging():
    import roughdiffuse as rd

    m = rd.OrenNayar(0.8, 0.3)
    wo = np.array([0.0, 0.0, 1.0])
    ref = float(m.brdf(np.array([1.0, 0.0, 1.0]), wo))
    for scale in (1e-200, 1e-160, 1e200):
        assert float(m.brdf(np.array([scale, 0.0, scale]), wo)) == pytest.approx(ref, rel=1e-15)
    with pytest.raises(ValueError, match="zero, NaN or infinite"):
        m.brdf(np.array([0.0, 0.0, 0.0]), wo)


@pytest.mark.parametrize(
    "argv",
    [
        ["eval", "--model", "hapke", "--param", "theta_bar=60"],
        ["eval", "--model", "hapke", "--param", "theta_bar=0"],
        ["eval", "--model", "oren-nayar", "--sigma", "90"],
        ["eval", "--model", "oren-nayar", "--param", "sigma=90"],
    ],
)
def test_a_bound_typed_in_degrees_is_inside_its_range(argv, capsys):
    assert run(argv) == 0, capsys.readouterr().err


def test_kernel_cache_under_a_folder_others_can_write_is_not_used(tmp_path, monkeypatch):
    from roughdiffuse.engine import cache

    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o777)  # writable by every user, not sticky: a parent others control
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(shared / "me" / "cache"))
    (shared / "me").mkdir()
    assert cache.private_cache_dir() is None
    os.chmod(shared, 0o1777)  # sticky, like /tmp: others cannot rename what is not theirs
    assert cache.private_cache_dir() == shared / "me" / "cache"


def test_albedo_computes_each_curve_once(tmp_path, monkeypatch):
    from roughdiffuse import energy

    calls = []
    real = energy.albedo_curves

    def counted(models, th, progress=False):
        calls.extend(models)
        return real(models, th, progress)

    monkeypatch.setattr(energy, "albedo_curves", counted)
    argv = ["albedo", "--model", "lambert,oren-nayar", "--sigma", "0,30"]
    assert run([*argv, "-o", str(tmp_path / "a.png"), "--table", str(tmp_path / "a.csv")]) == 0
    assert len(calls) == 3  # lambert once, oren-nayar at two σ: each computed once
