"""Progress bars: tqdm on standard error, only on a terminal; an early end says why and
ends at 100 %."""

from __future__ import annotations

import io
import sys

import pytest

from roughdiffuse.progress import finish, progress, progress_enabled


class FakeTTY(io.StringIO):
    """A text stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_bar_shown_only_on_a_terminal() -> None:
    tty, pipe = FakeTTY(), io.StringIO()
    assert progress_enabled(tty) and not progress_enabled(pipe)
    for stream in (tty, pipe):
        with progress(4, "job", unit="step", file=stream) as bar:
            bar.update(4)
    assert "job" in tty.getvalue() and "4/4" in tty.getvalue()
    assert pipe.getvalue() == ""


def test_early_end_says_why_and_reaches_100_percent() -> None:
    tty = FakeTTY()
    with progress(30, "rough photometric stereo", file=tty) as bar:
        bar.update(5)
        finish(bar, "converged after 5 of 30 iterations")
    last = tty.getvalue().strip().split("\r")[-1]
    assert "30/30" in last and "100%" in last
    assert "converged after 5 of 30 iterations" in last
    assert bar.n == bar.total == 30


def _fit_compare(*extra: str) -> int:
    from roughdiffuse.cli import main

    return main(["fit", "data:samples.csv", "--compare", "--models", "lambert,oren-nayar", *extra])


def test_fit_compare_counts_models_on_a_terminal(monkeypatch) -> None:  # noqa: ANN001
    tty = FakeTTY()
    # in the test's body: pytest puts its own capture back on sys.stderr after the fixtures
    monkeypatch.setattr(sys, "stderr", tty)
    assert _fit_compare() == 0
    text = tty.getvalue().strip().split("\r")[-1]
    assert "fitting models" in text and "2/2" in text and "100%" in text


def test_fit_compare_prints_nothing_on_stderr_without_a_terminal(capsys) -> None:  # noqa: ANN001
    assert _fit_compare() == 0
    assert capsys.readouterr().err == ""


def test_stereo_bar_that_converges_early_ends_at_100_percent(capsys) -> None:  # noqa: ANN001
    import roughdiffuse as rd
    from roughdiffuse import stereo

    data = stereo.synthetic_sphere(rd.OrenNayar(0.7, 0.4, "full"), size=24, noise=0.0)
    res = stereo.rough(data, rd.OrenNayar(variant="full"), iterations=30, progress=True)
    assert res.roughness == pytest.approx(0.4, abs=1e-3)
    last = capsys.readouterr().err.strip().split("\r")[-1]
    assert "converged after" in last and "30/30" in last and "100%" in last


def test_long_render_counts_its_bands_on_a_terminal(monkeypatch, tmp_path) -> None:  # noqa: ANN001
    """`render` with many rays: a bar of bands of rows on a terminal, nothing on a pipe; the
    banded image is the closed form ρ/π n·l of a Lambertian sphere lit head-on (E0 = 1)."""
    import numpy as np

    from roughdiffuse.cli import main
    from roughdiffuse.render import Sphere, renderer

    monkeypatch.setattr(renderer, "BAND_RAYS", 32 * 10)  # 10 rows of 32 pixels a band: 4 bands
    args = ["render", "--model", "lambert", "--albedo", "0.8", "--size", "32", "--spp", "1"]
    tty = FakeTTY()
    monkeypatch.setattr(sys, "stderr", tty)
    assert main([*args, "-o", str(tmp_path / "a.npy")]) == 0
    last = tty.getvalue().strip().split("\r")[-1]
    assert "render" in last and "4/4" in last and "100%" in last
    pipe = io.StringIO()
    monkeypatch.setattr(sys, "stderr", pipe)
    assert main([*args, "-o", str(tmp_path / "b.npy")]) == 0
    assert pipe.getvalue() == ""
    x, y = renderer.pixel_coordinates(Sphere(), size=32)
    r2 = x[None, :] ** 2 + y[:, None] ** 2
    inside = r2 < 1.0
    expected = np.where(inside, 0.8 / np.pi * np.sqrt(np.clip(1.0 - r2, 0.0, None)), 0.0)
    image = np.load(tmp_path / "b.npy")
    assert image.shape == (32, 32)
    np.testing.assert_allclose(image, expected, rtol=1e-5, atol=1e-6)


def test_photometry_correct_counts_chunks_on_a_terminal(monkeypatch, tmp_path) -> None:  # noqa: ANN001
    """`photometry correct` on an image of several chunks (--chunk 16: 2 × 2 windows of a
    24 × 24 image): a bar on a terminal, and the result of Lunar-Lambert (linear in its
    albedo) normalised to i = e = g = 0 is ρ."""
    import math

    import numpy as np

    import roughdiffuse as rd
    from roughdiffuse.cli import main
    from roughdiffuse.models.photometry import radiance_factor
    from roughdiffuse.planetary.backplanes import ellipsoid_backplanes

    bp = ellipsoid_backplanes((24, 24), (0.0, 30.0), (0.0, 0.0))
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    iof = np.full((24, 24), np.nan)
    model = rd.LunarLambert(0.12, 0.6)
    iof[lit] = radiance_factor(model, bp.incidence[lit], bp.emission[lit], bp.phase[lit])
    np.save(tmp_path / "iof.npy", iof)
    chunks = 4
    tty = FakeTTY()
    monkeypatch.setattr(sys, "stderr", tty)
    argv = ["photometry", "correct", str(tmp_path / "iof.npy"), "--subsolar", "0,30",
            "--subobserver", "0,0", "--model", "lunar-lambert", "--param", "L=0.6",
            "--chunk", "16", "-o", str(tmp_path / "out.npy")]  # fmt: skip
    assert main(argv) == 0
    last = tty.getvalue().strip().split("\r")[-1]
    assert "photometry correct" in last and f"{chunks}/{chunks}" in last and "100%" in last
    keep = bp.on_body & (bp.incidence < math.radians(80)) & (bp.emission < math.radians(80))
    np.testing.assert_allclose(np.load(tmp_path / "out.npy")[keep], 0.12, rtol=1e-6)
