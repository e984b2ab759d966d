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
