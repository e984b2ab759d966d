"""The CLI's errors: a user error is one line naming what is wrong and exit status 2, found
before any work; a bug is an internal error, exit status 1; no NaN leaves with status 0.

Unwritable output paths are made with a regular file as the parent folder: that holds for
root too, who ignores the mode bits of a folder.
"""

from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse import cli
from roughdiffuse.commands import UsageError
from roughdiffuse.commands._checks import (
    available_memory,
    fits_in_memory,
    output_file,
    output_folder,
    reading,
    require_finite,
)


def samples_csv(path: Path, value: str) -> Path:
    """BRDF samples at 12 geometries, all of value ``value``."""
    rows = [f"{ti},{tr},0,{value}" for ti in (10, 30, 50, 70) for tr in (0, 30, 60)]
    path.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n" + "\n".join(rows) + "\n")
    return path


def one_line_error(capsys, argv: list[str], *names: str) -> str:
    """Run the CLI; assert exit status 2 and one stderr line naming each of ``names``."""
    status = cli.main(argv)
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err and "internal error" not in err
    for name in names:
        assert name in lines[0], (name, lines[0])
    return lines[0]


@pytest.fixture
def not_a_folder(tmp_path: Path) -> Path:
    f = tmp_path / "regular-file"
    f.write_text("x")
    return f


# --- unusable output paths, found before any work ---------------------------------------


@pytest.mark.parametrize(
    "argv",
    [
        ["render", "--size", "8", "-o", "{F}/x.png"],
        ["plot", "plane", "-o", "{F}/x.png"],
        ["albedo", "-o", "{F}/a.png"],
        ["figures", "-o", "{F}/figs"],
        ["figures", "-o", "{F}"],
        ["simulate", "--table", "{F}/t.npz", "--step", "45", "--delta-phi-step", "180"],
        ["simulate", "--report", "-o", "{F}/report"],
    ],
)
def test_unwritable_output_is_refused_before_work(capsys, not_a_folder, argv):
    argv = [a.replace("{F}", str(not_a_folder)) for a in argv]
    one_line_error(capsys, argv, str(not_a_folder))


def test_missing_output_folder_is_named(capsys, tmp_path):
    one_line_error(
        capsys, ["render", "--size", "8", "-o", str(tmp_path / "nope" / "x.png")], "nope"
    )


def test_fit_report_path_is_checked_before_the_fit(capsys, tmp_path, not_a_folder):
    data = samples_csv(tmp_path / "s.csv", "0.2")
    status = cli.main(["fit", str(data), "--report", f"{not_a_folder}/r.html"])
    out, err = capsys.readouterr()
    assert status == 2 and "--report" in err and len(err.strip().splitlines()) == 1
    assert "data:" not in out  # refused before the data was read and fitted
    folder = tmp_path / "r.html"
    folder.mkdir()
    one_line_error(capsys, ["fit", str(data), "--report", str(folder)], "is a folder")
    assert {p.name for p in tmp_path.iterdir()} == {"s.csv", "r.html", not_a_folder.name}


def test_folder_as_output_file_is_refused_even_with_force(capsys, tmp_path):
    d = tmp_path / "x.png"
    d.mkdir()
    one_line_error(capsys, ["render", "--size", "8", "--force", "-o", str(d)], "is a folder")
    t = tmp_path / "t.npz"
    t.mkdir()
    argv = ["simulate", "--table", str(t), "--step", "45", "--delta-phi-step", "180"]
    one_line_error(capsys, argv, "--table", "is a folder")


def test_albedo_checks_the_table_before_writing_the_plot(capsys, tmp_path, not_a_folder):
    plot = tmp_path / "a.png"
    one_line_error(
        capsys, ["albedo", "-o", str(plot), "--table", f"{not_a_folder}/t.csv"], "--table"
    )
    assert not plot.exists()


def test_figures_only_bogus_creates_no_folder(capsys, tmp_path):
    out = tmp_path / "figures"
    one_line_error(capsys, ["figures", "--only", "bogus", "-o", str(out)], "--only", "bogus")
    assert not out.exists()


def test_output_checks_probe_the_folder(tmp_path, not_a_folder):
    assert output_file(tmp_path / "a.png", (".png",)) == tmp_path / "a.png"
    assert list(tmp_path.iterdir()) == [not_a_folder]  # the probe file is gone
    with pytest.raises(UsageError, match="must end in .png"):
        output_file(tmp_path / "a.jpg", (".png",))
    (tmp_path / "a.png").write_text("x")
    with pytest.raises(UsageError, match="exists; use --force"):
        output_file(tmp_path / "a.png", (".png",))
    assert output_file(tmp_path / "a.png", (".png",), force=True).name == "a.png"
    assert output_folder(tmp_path / "new") == tmp_path / "new"
    assert not (tmp_path / "new").exists()
    with pytest.raises(UsageError, match="not a folder"):
        output_folder(not_a_folder / "sub")


# --- files that cannot be read are named --------------------------------------------------


def test_garbage_exr_is_named(capsys, tmp_path):
    pytest.importorskip("OpenEXR")
    bad = tmp_path / "garbage.exr"
    bad.write_bytes(b"this is not an OpenEXR file\n" * 4)
    argv = ["fit", str(bad), "--shape", "sphere", "--light", "30,0"]
    one_line_error(capsys, argv, "garbage.exr")


def test_png_with_a_bad_header_is_named(capsys, tmp_path):
    bad = tmp_path / "bad.png"
    ihdr = b"IHDR\x00\x00"  # 2 bytes of the 13 an IHDR holds: struct.error in the reader
    bad.write_bytes(
        b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 2) + ihdr + struct.pack(">I", zlib.crc32(ihdr))
    )
    argv = ["fit", str(bad), "--shape", "sphere", "--light", "30,0"]
    one_line_error(capsys, argv, "bad.png")


def test_csv_that_is_not_text_is_named(capsys, tmp_path):
    bad = tmp_path / "garbage.csv"
    bad.write_bytes(bytes(range(128, 256)) * 3)
    line = one_line_error(capsys, ["fit", str(bad)], "garbage.csv", "UTF-8")
    assert "codec" not in line


def test_reading_names_the_file_and_passes_bugs_through():
    with pytest.raises(UsageError, match="'d.npy'.*truncated"), reading("d.npy"):
        struct.unpack(">I", b"")
    with pytest.raises(TypeError), reading("d.npy"):
        raise TypeError("a bug is not a bad file")
    with pytest.raises(RuntimeError), reading("d.npy"):
        raise RuntimeError("only the OpenEXR reader's RuntimeError means a bad file")


# --- values and sizes that should not pass --------------------------------------------------


def test_exposure_overflow_is_refused(capsys, tmp_path):
    argv = ["render", "--size", "8", "--exposure", "1e308", "-o", str(tmp_path / "e.png")]
    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "--exposure" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "e.png").exists()


def test_irradiance_beyond_float32_is_refused(capsys, tmp_path):
    out = tmp_path / "x.npy"
    one_line_error(
        capsys, ["render", "--size", "8", "--irradiance", "1e39", "-o", str(out)], "--irradiance"
    )
    assert not out.exists()


def test_render_too_large_for_memory_is_refused_with_the_estimate(capsys, tmp_path):
    # 8192² pixels × 256 samples × 13 bytes (scalar radiance) = 2.23e11 bytes
    room = available_memory()
    if room is None or room > 2.2e11:
        pytest.skip(f"needs a machine with less than 220 GB available (has {room})")
    argv = ["render", "--size", "8192", "--spp", "256", "-o", str(tmp_path / "big.npy")]
    line = one_line_error(capsys, argv, "--size 8192x8192 --spp 256", "223 GB")
    assert "available" in line


def test_fits_in_memory_compares_with_what_is_available():
    fits_in_memory(1e9, "--x", available=2_000_000_000)
    with pytest.raises(UsageError, match=r"--x needs about 3 GB of memory; 2 GB is available"):
        fits_in_memory(3e9, "--x", available=2_000_000_000)


@pytest.mark.parametrize(
    ("argv", "name"),
    [
        (["simulate", "--elements", "100000000"], "--elements"),
        (["simulate", "--bounces", "1000000"], "--bounces"),
        (["eval", "--delta-phi", "nan"], "--delta-phi"),
        (["simulate", "--delta-phi", "inf"], "--delta-phi"),
    ],
)
def test_sizes_and_non_numbers_are_refused_by_option(capsys, argv, name):
    try:
        status = cli.main(argv)
    except SystemExit as exc:  # argparse's own refusals
        status = exc.code
    err = capsys.readouterr().err
    assert status == 2 and name in err and len(err.strip().splitlines()) == 1, err


def test_eval_never_prints_nan(capsys):
    status = cli.main(["eval", "--model", "torrance-sparrow", "--eta", "1e300"])
    out, err = capsys.readouterr()
    assert status == 2, out
    assert "nan" not in out.lower() and "eta" in err


def test_require_finite_refuses_nan_and_inf():
    require_finite(np.ones(3), "x")
    with pytest.raises(UsageError, match=r"the image holds NaN and infinity \(2 of 3 values\)"):
        require_finite(np.array([1.0, np.nan, np.inf]), "the image")


@pytest.mark.parametrize("value", ["1e308", "1e-320"])
def test_fit_refuses_data_it_cannot_square(capsys, tmp_path, value):
    data = samples_csv(tmp_path / "huge.csv", value)
    line = one_line_error(capsys, ["fit", str(data)], "huge.csv")
    assert "nan" not in line


# --- internal errors are not usage errors ---------------------------------------------------


def _with_command(monkeypatch, func):
    """Make ``roughdiffuse eval`` run ``func`` instead."""
    import roughdiffuse.commands.eval as ev

    monkeypatch.setattr(ev, "run", func)


def test_a_bug_is_an_internal_error_exit_1(capsys, monkeypatch):
    def buggy(args):
        return {}["missing"]

    _with_command(monkeypatch, buggy)
    assert cli.main(["eval"]) == 1
    err = capsys.readouterr().err
    assert "internal error" in err and "KeyError" in err and "--debug" in err
    assert "Traceback" not in err and "test_cli_errors.py" in err  # says where
    assert cli.main(["eval", "--debug"]) == 1
    err = capsys.readouterr().err
    assert "Traceback" in err and "internal error" in err


def test_a_valueerror_inside_numpy_is_a_bug_not_bad_input(capsys, monkeypatch):
    def buggy(args):
        np.zeros(3).reshape(2, 2)  # ValueError raised inside NumPy

    _with_command(monkeypatch, buggy)
    assert cli.main(["eval"]) == 1
    assert "internal error" in capsys.readouterr().err


def test_refusals_from_roughdiffuse_are_user_errors(capsys, monkeypatch):
    from roughdiffuse import Lambert

    def refuses(args):
        Lambert(2.0)  # the model's check names albedo and its range

    _with_command(monkeypatch, refuses)
    assert cli.main(["eval"]) == 2
    err = capsys.readouterr().err
    assert "albedo" in err and "[0, 1]" in err and "internal" not in err


def test_file_system_errors_are_one_line(capsys, monkeypatch):
    def full_disk(args):
        raise OSError(28, "No space left on device", "/data/out.npz")

    _with_command(monkeypatch, full_disk)
    line = one_line_error(capsys, ["eval"], "/data/out.npz", "No space left")
    assert line.startswith("roughdiffuse eval: error:")


def test_truncated_merl_file_is_named(capsys, tmp_path):
    bad = tmp_path / "fabric.binary"
    bad.write_bytes(struct.pack("<iii", 90, 90, 180) + b"\0" * 100)  # far too short
    one_line_error(capsys, ["fit", str(bad)], "fabric.binary")


def test_console_script_prints_no_traceback(tmp_path):
    """The same through a real process: exit status 2, one line on stderr."""
    import subprocess
    import sys

    blocker = tmp_path / "file"
    blocker.write_text("x")
    out = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "figures", "-o", str(blocker)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "Traceback" not in out.stderr
    assert "is not a folder" in out.stderr


@pytest.mark.parametrize(
    ("opts", "name"),
    [(["--spp", "3"], "--spp"), (["--size", "0"], "--size"), (["--size", "9000x8"], "--size")],
)
def test_render_names_its_size_options(capsys, tmp_path, opts, name):
    one_line_error(capsys, ["render", *opts, "-o", str(tmp_path / "x.png")], name)
    assert not (tmp_path / "x.png").exists()


def test_output_into_a_closed_pipe_stops_quietly():
    """`roughdiffuse models | head -1`: no error message, the status of SIGPIPE (128 + 13)."""
    import os
    import subprocess
    import sys

    read_end, write_end = os.pipe()
    os.close(read_end)  # the reader is gone before anything is written
    try:
        out = subprocess.run(
            [sys.executable, "-m", "roughdiffuse", "models"],
            stdout=write_end,
            stderr=subprocess.PIPE,
            text=True,
            timeout=120,
        )
    finally:
        os.close(write_end)
    assert out.returncode == 141 and out.stderr == ""
