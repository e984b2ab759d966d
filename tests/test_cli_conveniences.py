"""Command-line conveniences: shipped data by name, did-you-mean model ids, the ``rad``
suffix on angle options, the geometry echo, ``stereo --model lambert``, ``render --lights``."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughdiffuse.cli import main


def _run(capsys, *argv: str) -> tuple[int, str, str]:  # noqa: ANN001
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_data_lists_the_shipped_files(capsys) -> None:  # noqa: ANN001
    from roughdiffuse import data

    code, out, _ = _run(capsys, "data")
    assert code == 0
    for name in data.names():
        assert f"data:{name}" in out
    code, out, _ = _run(capsys, "data", "--path", "samples.csv")
    assert code == 0 and out.strip() == str(data.path("samples.csv"))


def test_unknown_data_name_suggests_the_closest(capsys) -> None:  # noqa: ANN001
    with pytest.raises(SystemExit) as exc:
        main(["fit", "data:sample.csv"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "did you mean samples.csv?" in err and err.count("\n") == 1


@pytest.mark.parametrize(
    ("argv", "closest"),
    [
        (["eval", "--model", "oren-nayar-ful"], "oren-nayar-full"),
        (["fit", "data:samples.csv", "--model", "oren-nayer"], "oren-nayar"),
        (["stereo", "--demo", "--model", "lamber", "-o", "x"], "lambert"),
    ],
)
def test_misspelt_model_suggests_the_closest_ids(capsys, argv, closest) -> None:  # noqa: ANN001
    code, _, err = _run(capsys, *argv)
    assert code == 2
    line = err.strip()
    assert "did you mean" in line and closest in line.split("did you mean")[1]


def test_rad_suffix_on_angle_options(capsys) -> None:  # noqa: ANN001
    deg = [f"{math.degrees(0.5):.15g}", f"{math.degrees(0.35):.15g}"]
    _, with_rad, _ = _run(capsys, "eval", "--theta-i", "0.5rad", "--sigma", "0.35rad")
    _, with_deg, _ = _run(capsys, "eval", "--theta-i", deg[0], "--sigma", deg[1])
    line = next(x for x in with_rad.splitlines() if x.startswith("brdf"))
    assert line == next(x for x in with_deg.splitlines() if x.startswith("brdf"))


def test_bad_angle_is_refused_on_one_line(capsys) -> None:  # noqa: ANN001
    with pytest.raises(SystemExit) as exc:
        main(["eval", "--theta-r", "1.2parsecs"])
    assert exc.value.code == 2
    assert "0.52rad" in capsys.readouterr().err


def test_eval_echoes_geometry_and_defaults(capsys) -> None:  # noqa: ANN001
    code, out, _ = _run(capsys, "eval", "--model", "oren-nayar", "--theta-i", "30")
    assert code == 0
    assert "geometry: θi = 30°, θr = 0° (default), Δφ = 0° (default)" in out
    assert "defaults used for: albedo, sigma" in out


def test_help_states_the_geometry_defaults(capsys) -> None:  # noqa: ANN001
    for cmd, defaults in (("eval", ("0", "0", "0")), ("simulate", ("30", "30", "0"))):
        with pytest.raises(SystemExit):
            main([cmd, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        for flag, d in zip(("--theta-i", "--theta-r", "--delta-phi"), defaults, strict=True):
            after = text.split(f"{flag} ANGLE")[-1]  # the option's help, not the usage line
            assert f"(default: {d})" in after.split("--")[0]


def _true_sphere_normals(size: int) -> tuple[np.ndarray, np.ndarray]:
    from roughdiffuse.fit import shape_normals
    from roughdiffuse.render import Sphere

    return shape_normals(Sphere(), size)


def test_render_lights_stack_matches_single_renders(tmp_path, capsys) -> None:  # noqa: ANN001
    from roughdiffuse import OrenNayar, data
    from roughdiffuse.render import DistantLight, Sphere, render

    stack = tmp_path / "stack"
    code, out, _ = _run(
        capsys, "render", "--model", "oren-nayar-full", "--albedo", "0.6", "--sigma", "0.4rad",
        "--size", "32", "--spp", "1", "--lights", "data:lights.json", "-o", str(stack),
    )  # fmt: skip
    assert code == 0, out
    spec = json.loads((stack / "lights.json").read_text())
    given = json.loads(data.path("lights.json").read_text())
    assert np.allclose(spec["directions"], given["directions"], atol=1e-12)
    files = sorted(p.name for p in stack.glob("light-*.npy"))
    assert files == [f"light-{k:02d}.npy" for k in range(8)]
    d = np.asarray(given["directions"][3])
    light = DistantLight(math.acos(d[2]), math.atan2(d[1], d[0]))
    one, _ = render(OrenNayar(0.6, 0.4, "full"), Sphere(), light, size=32, samples_per_pixel=1)
    assert np.allclose(np.load(stack / "light-03.npy"), np.asarray(one), rtol=1e-5, atol=1e-7)
    code, _, err = _run(capsys, "render", "--lights", "data:lights.json", "-o", str(stack))
    assert code == 2 and "--force" in err  # a folder that holds files is not overwritten


def test_stereo_lambert_recovers_lambertian_normals_exactly(tmp_path, capsys) -> None:  # noqa: ANN001
    stack, out = tmp_path / "stack", tmp_path / "out"
    size = 48
    code, _, _ = _run(
        capsys, "render", "--model", "lambert", "--albedo", "0.7", "--size", str(size),
        "--spp", "1", "--no-shadows", "--lights", "data:lights.json", "-o", str(stack),
    )  # fmt: skip
    assert code == 0
    images = sorted(str(p) for p in stack.glob("light-*.npy"))
    code, text, _ = _run(
        capsys, "stereo", *images, "--lights", str(stack / "lights.json"),
        "--model", "lambert", "-o", str(out),
    )  # fmt: skip
    assert code == 0 and "no roughness" in text
    params = json.loads((out / "params.json").read_text())
    assert params["roughness"] is None and params["model"] == "lambert"
    normals = np.load(out / "normals.npy")
    truth, on = _true_sphere_normals(size)
    ok = np.all(np.isfinite(normals), axis=-1) & on
    assert ok.sum() > 0.5 * on.sum()
    a, b = normals[ok], truth[ok].astype(np.float64)
    b /= np.linalg.norm(b, axis=-1, keepdims=True)
    # the angle from atan2(|a × b|, a · b): arccos near 1 would lose it to rounding
    angle = np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.sum(a * b, axis=-1))
    # float32 images (relative rounding 6e-8): the least-squares normals are exact to ~1e-6 rad
    assert np.degrees(angle).max() < 1e-3
    albedo = np.load(out / "albedo.npy")
    assert np.allclose(albedo[ok], 0.7, rtol=1e-4)
    assert "Woodham" in (out / "report.html").read_text()
