"""The accuracy report: how close Lambert, Oren–Nayar, Fujii and EON come to the V-cavity truth.

``roughdiffuse simulate --report -o DIR`` writes ``DIR/index.md`` (tables and the settings
that produced them), ``DIR/*.png`` (plane-of-incidence curves, error maps) and the
ground-truth tables it computed (``DIR/tables/*.npz``, reused when the report is run again).

Comparisons (Oren & Nayar 1994, Secs. 3–4; docs/accuracy.md):

* Oren–Nayar L1 (the full model's direct term) and the qualitative model against one bounce;
  L1 + L2 (the full model) against two bounces and against all bounces; Lambert against all.
* Fujii (FON) and EON take a roughness r in [0, 1] that is not an angle and has no published
  mapping from σ: for each σ the report uses the r that minimises the RMS relative error
  against all bounces (FON: against one bounce, as it is a single-scattering model), and
  prints it.
* The slope-measure question: Oren–Nayar's L1 against one bounce under both readings.
* A second ground truth (:mod:`.smith_checks`): the Smith microsurface's checks, and
  rendered Gaussian heightfields against both solvers; and every registry model against the
  V-cavity, Smith-Beckmann and Smith-GGX surfaces at ρ = 0.5 and 0.9
  (:mod:`.model_scores`).

L1 is taken from the model code, not re-derived: the full model is f = a ρ + b ρ², so
L1(ρ) = a ρ = 4 f(ρ/2) − f(ρ).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .. import registry
from .._version import version
from ..io.atomic import atomic_write, deferred, write_text
from ..simulate.surface import Settings
from ..simulate.table import compute_table, load_table

__all__ = ["SIGMAS", "write_report"]

SIGMAS = (0.1, 0.2, 0.3, 0.5, 0.7)
ALBEDO = 0.9


def _cosines(ti, tr, dp):
    return np.cos(ti), np.cos(tr), np.cos(ti) * np.cos(tr) + np.sin(ti) * np.sin(tr) * np.cos(dp)


def _label(model_id: str, suffix: str = "") -> str:
    """The registry's label of a model (:mod:`roughdiffuse.registry`), plus ``suffix``."""
    return registry.get(model_id).label + suffix


L1 = "oren-nayar-full:L1"
"""The full Oren–Nayar model's direct term alone (not a registry model): L1(ρ) = 4 f(ρ/2) − f(ρ)."""


def model_values(model_id: str, ti, tr, dp, sigma: float, albedo: float, r: float | None = None):
    """BRDF (1/sr) at angle arrays of the registry model ``model_id`` (its σ or its roughness
    r, whichever it takes), or of :data:`L1`."""
    mi, mo, c = _cosines(ti, tr, dp)
    if model_id == L1:
        full = registry.get("oren-nayar-full")
        half = full.create(albedo=albedo / 2, sigma=sigma).brdf_cosines(mi, mo, c)
        return 4.0 * half - full.create(albedo=albedo, sigma=sigma).brdf_cosines(mi, mo, c)
    entry = registry.get(model_id)
    takes = {p.name for p in entry.parameters}
    kw = {"albedo": albedo}
    if "sigma" in takes:
        kw["sigma"] = sigma
    if "roughness" in takes:
        kw["roughness"] = r
    return entry.create(**kw).brdf_cosines(mi, mo, c)


def _errors(model: np.ndarray, truth: np.ndarray) -> np.ndarray:
    return (model - truth) / truth


def _best_r(name, ti, tr, dp, sigma, truth) -> tuple[float, float]:
    rs = np.linspace(0.0, 1.0, 101)
    rms = [
        np.sqrt(np.mean(_errors(model_values(name, ti, tr, dp, sigma, ALBEDO, r), truth) ** 2))
        for r in rs
    ]
    k = int(np.argmin(rms))
    return float(rs[k]), float(rms[k])


def _grid(quick: bool):
    if quick:
        ang = np.radians([0.0, 40.0, 80.0])
        return ang, ang, np.radians([0.0, 180.0]), (0.3,)
    ang = np.radians(np.arange(0.0, 81.0, 10.0))
    return ang, ang, np.radians([0.0, 45.0, 90.0, 135.0, 180.0]), SIGMAS


def _where(t, idx) -> str:
    i, j, k = idx
    return (
        f"θi={math.degrees(t.theta_i[i]):.0f}°, θr={math.degrees(t.theta_r[j]):.0f}°, "
        f"Δφ={math.degrees(t.delta_phi[k]):.0f}°"
    )


def _table_source(out: Path, grid, workers: int, scheduler: str | None, progress: bool):
    """``table(measure, bounces)``: the report's truth table, reused from ``out/tables`` when
    it holds this grid, else computed (and a table of another grid replaced)."""
    ti, tr, dp, sigmas = grid

    def table(measure: str, bounces):
        path = out / "tables" / f"truth_{measure}_{bounces}.npz"
        if path.exists():
            t = load_table(path)
            if (
                t.settings == Settings(measure=measure)
                and t.bounces == bounces
                and t.values.shape == (ti.size, tr.size, dp.size, len(sigmas))
            ):
                return t
        return compute_table(
            path,
            ti,
            tr,
            dp,
            sigmas,
            ALBEDO,
            bounces,
            Settings(measure=measure),
            workers=workers,
            scheduler=scheduler,
            progress=progress,
            force=True,  # a table of this report's other grid (checked above) is replaced
            package_version=version(),
        )

    return table


def _settings_lines(quick: bool, ti, dp, sigmas) -> list[str]:
    """The report's title and the settings that produced it."""
    return [
        "# V-cavity ground truth: accuracy of the reflectance models",
        "",
        "Generated by `roughdiffuse simulate --report" + (" --quick" if quick else "") + "`.",
        "",
        "## Settings",
        "",
        f"* facet albedo ρ = {ALBEDO}; σ (rad) = {', '.join(f'{s:g}' for s in sigmas)}",
        f"* θi, θr ∈ {{{', '.join(f'{math.degrees(a):.0f}' for a in ti)}}}°, "
        f"Δφ ∈ {{{', '.join(f'{math.degrees(a):.0f}' for a in dp)}}}°",
        "* solver: the defaults of `roughdiffuse.simulate.Settings` (elements=16, "
        "extrapolate=True, n_theta=16, n_phi=16, n_theta_inter=32; the measure as chosen "
        "below): K elements per facet, Richardson-extrapolated from K and 2K; "
        "Gauss–Legendre rules split at the integrand's kinks; doubling every rule changes f by "
        "< 1e-4 relative",
        "* error = (model − truth) / truth; RMS and maximum |error| over the grid",
        "",
    ]


def _measure_lines(g, sigmas, one) -> tuple[list[str], str]:
    """Which reading of the slope measure Oren–Nayar's L1 fits (the lines, and the reading)."""
    lines = [
        "## Which reading of the slope measure do the Oren–Nayar coefficients fit?",
        "",
        "Oren–Nayar L1 (the full model's direct term) against one bounce, per reading:",
        "",
        "| σ | RMS, density in dθa (`angle`) | RMS, per solid angle (`solid-angle`) |",
        "| --- | --- | --- |",
    ]
    rms_measure = {"angle": [], "solid-angle": []}
    l1 = [model_values(L1, *g, s, ALBEDO) for s in sigmas]
    for k, s in enumerate(sigmas):
        row = []
        for m in ("angle", "solid-angle"):
            e = _errors(l1[k], one[m].values[..., k])
            rms_measure[m].append(float(np.sqrt(np.mean(e**2))))
            row.append(f"{rms_measure[m][-1]:.4f}")
        lines.append(f"| {s:g} | {row[0]} | {row[1]} |")
    better = min(rms_measure, key=lambda m: float(np.mean(rms_measure[m])))
    lines += [
        "",
        f"Overall the `{better}` reading fits better (mean RMS "
        f"{np.mean(rms_measure[better]):.4f} against "
        f"{np.mean(rms_measure['angle' if better != 'angle' else 'solid-angle']):.4f}). "
        "The rest of this report uses it.",
        "",
        "At v = n the single-bounce truth is ρ/π E[cos θa] for every θi (tests/"
        "test_simulate_surface.py), and L1 there is ρ/π C1, C1 = 1 − 0.5σ²/(σ² + 0.33):",
        "",
        "| σ | C1 | E[cos θa], `angle` | E[cos θa], `solid-angle` |",
        "| --- | --- | --- | --- |",
        *[
            f"| {s:g} | {1 - 0.5 * s * s / (s * s + 0.33):.4f} | "
            f"{one['angle'].values[0, 0, 0, k] * math.pi / ALBEDO:.4f} | "
            f"{one['solid-angle'].values[0, 0, 0, k] * math.pi / ALBEDO:.4f} |"
            for k, s in enumerate(sigmas)
        ],
        "",
    ]
    return lines, better


COMPARISONS = (
    ("lambert", "", "all bounces"),
    ("oren-nayar", "", "1 bounce"),
    ("oren-nayar", "", "all bounces"),
    (L1, "", "1 bounce"),
    ("oren-nayar-full", " (L1 + L2)", "2 bounces"),
    ("oren-nayar-full", " (L1 + L2)", "all bounces"),
    ("fujii", ", best r", "1 bounce"),
    ("eon", ", best r", "all bounces"),
)
"""(registry id or :data:`L1`, label suffix, truth) of each row group of the error table."""


def _error_lines(g, sigmas, truths, better: str) -> list[str]:
    """Each model's RMS and maximum error against its truths, per σ."""
    inf = truths["all bounces"]
    lines = [
        f"## Model errors (measure `{better}`)",
        "",
        "| model | against | σ | RMS | max | where the max is | r |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, suffix, against in COMPARISONS:
        label = "Oren–Nayar L1" if name == L1 else _label(name, suffix)
        for k, s in enumerate(sigmas):
            truth = truths[against].values[..., k]
            r = None
            if name in ("fujii", "eon"):
                r, _ = _best_r(name, *g, s, truth)
            e = _errors(model_values(name, *g, s, ALBEDO, r), truth)
            idx = np.unravel_index(int(np.argmax(np.abs(e))), e.shape)
            lines.append(
                f"| {label} | {against} | {s:g} | {np.sqrt(np.mean(e**2)):.4f} | "
                f"{np.abs(e).max():.4f} | {_where(inf, idx)} | {'' if r is None else f'{r:.2f}'} |"
            )
    return lines


def write_report(
    out: str | Path,
    quick: bool = False,
    progress: bool = True,
    workers: int = 1,
    scheduler: str | None = None,
) -> Path:
    """Compute the ground truth and write the accuracy report into folder ``out``.

    The tables are computed by :func:`compute_table` (``workers`` processes, or the Dask
    ``scheduler`` at that address) and reused by later runs with the same grid.
    """
    from .._figure import subplots  # Figure objects, no pyplot (see roughdiffuse._figure)

    out = Path(out)
    (out / "tables").mkdir(parents=True, exist_ok=True)
    ti, tr, dp, sigmas = _grid(quick)
    table = _table_source(out, (ti, tr, dp, sigmas), workers, scheduler, progress)
    one = {m: table(m, 1) for m in ("angle", "solid-angle")}
    g = np.meshgrid(ti, tr, dp, indexing="ij")
    lines = _settings_lines(quick, ti, dp, sigmas)
    measure_lines, better = _measure_lines(g, sigmas, one)
    lines += measure_lines
    two = table(better, 2)
    inf = table(better, "all")
    truths = {"1 bounce": one[better], "2 bounces": two, "all bounces": inf}
    lines += _error_lines(g, sigmas, truths, better)
    with deferred(out):  # the report's pages and figures appear together, or none
        lines += _convergence_lines(quick)
        lines += _second_truth_lines(out, quick, progress)
        # figures: plane of incidence and error maps
        figs = _plots(subplots, out, better, sigmas, quick, progress, workers)
        lines += ["", "## Figures", ""] + [f"![{t}]({p})" for t, p in figs]
        lines += [
            "",
            "K-convergence of the all-bounce table: max |f(K) − f(2K)| / f = "
            f"{np.max(np.abs(inf.k_difference) / inf.values):.2e} (before extrapolation).",
            "",
        ]
        write_text(out / "index.md", "\n".join(lines))
    return out / "index.md"


def _second_truth_lines(out: Path, quick: bool, progress: bool) -> list[str]:
    """The Smith microsurface's checks and the rendered heightfields (:mod:`.smith_checks`),
    and every registry model against the three all-bounce truths (:mod:`.model_scores`)."""
    from .model_scores import model_score_lines
    from .smith_checks import heightfield_lines, smith_check_lines

    return (
        smith_check_lines(quick)
        + heightfield_lines(out, quick, progress)
        + model_score_lines(quick, progress, out)
    )


def _convergence_lines(quick: bool) -> list[str]:
    """Relative change of f when each quadrature rule (and K) is doubled."""
    from ..simulate.surface import quadrature_convergence

    g = np.radians([[0, 0, 0], [30, 45, 0], [60, 60, 180], [80, 85, 90], [89, 30, 30]])
    if quick:
        g = g[:2]
    lines = [
        "",
        "## Quadrature convergence",
        "",
        "Largest relative change of f (all bounces, ρ = 0.9) over the geometries "
        + ", ".join(f"({a:.0f}°, {b:.0f}°, {c:.0f}°)" for a, b, c in np.degrees(g))
        + " (θi, θr, Δφ) when one rule, or K, or everything is doubled:",
        "",
        "| measure | σ | n_theta | n_phi | n_theta_inter | K | all doubled |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for measure in ("angle", "solid-angle"):
        for s in (0.3,) if quick else (0.1, 0.3, 0.7):
            c = quadrature_convergence(
                g[:, 0], g[:, 1], g[:, 2], s, ALBEDO, "all", Settings(measure=measure)
            )
            lines.append(
                f"| {measure} | {s:g} | {c['n_theta']:.1e} | {c['n_phi']:.1e} | "
                f"{c['n_theta_inter']:.1e} | {c['elements']:.1e} | {c['all']:.1e} |"
            )
    return lines


def _plots(subplots, out: Path, measure: str, sigmas, quick: bool, progress: bool, workers: int):
    from ..simulate.surface import brdf

    figs = []
    theta_i = math.radians(60.0)
    thr = np.radians(np.arange(0.0, 86.0, 20.0 if quick else 5.0))
    x = np.concatenate([-thr[::-1], thr[1:]])  # negative: Δφ = 180° (back to the light)
    xs = np.abs(x)
    dps = np.where(x < 0, math.pi, 0.0)
    ti = np.full_like(x, theta_i)
    show = sigmas if quick else (0.1, 0.3, 0.7)
    fig, axes = subplots(1, len(show), figsize=(4.2 * len(show), 3.6), squeeze=False)
    for ax, s in zip(axes[0], show, strict=True):
        st = Settings(measure=measure)
        truth1 = brdf(ti, xs, dps, s, ALBEDO, 1, st)
        truth = brdf(ti, xs, dps, s, ALBEDO, "all", st)
        ax.plot(np.degrees(x), truth * math.pi, "k-", lw=2, label="V-cavity, all bounces")
        ax.plot(np.degrees(x), truth1 * math.pi, "k--", lw=1, label="V-cavity, 1 bounce")
        for name, style in (("oren-nayar-full", "C0-"), ("oren-nayar", "C1-"), ("lambert", "C2:")):
            ax.plot(
                np.degrees(x),
                model_values(name, ti, xs, dps, s, ALBEDO) * math.pi,
                style,
                label=name,
            )
        ax.set_title(f"σ = {s:g} rad, θi = 60°")
        ax.set_xlabel("θr (°): Δφ = 0 right, Δφ = 180° left")
        ax.set_ylabel("π f")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    atomic_write(out / "plane_of_incidence.png", lambda tmp: fig.savefig(tmp, dpi=110))
    figs.append(("Plane of incidence", "plane_of_incidence.png"))
    # error maps over θi × θr at Δφ = 0, σ = 0.3, against all bounces
    ang = np.radians(np.arange(0.0, 86.0, 20.0 if quick else 5.0))
    a, b = np.meshgrid(ang, ang, indexing="ij")
    s = 0.3
    truth = brdf(a, b, 0.0, s, ALBEDO, "all", Settings(measure=measure))
    names = ("oren-nayar-full", "oren-nayar", "lambert")
    fig, axes = subplots(1, len(names), figsize=(4.2 * len(names), 3.6), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        e = _errors(model_values(name, a, b, 0.0, s, ALBEDO), truth)
        lim = max(0.05, float(np.abs(e).max()))
        im = ax.pcolormesh(
            np.degrees(ang), np.degrees(ang), e.T, cmap="RdBu_r", vmin=-lim, vmax=lim
        )
        ax.set_title(f"{name} vs all bounces, σ = 0.3, Δφ = 0")
        ax.set_xlabel("θi (°)")
        ax.set_ylabel("θr (°)")
        fig.colorbar(im, ax=ax, label="relative error")
    fig.tight_layout()
    atomic_write(out / "error_maps.png", lambda tmp: fig.savefig(tmp, dpi=110))
    figs.append(("Error maps", "error_maps.png"))
    try:
        import mitsuba as mi
    except ImportError:  # optional: the finite-pixel figure needs Mitsuba 3
        return figs
    _pixels_figure(subplots, mi, out, quick)
    figs.append(("Finite pixels: a rendered V-groove surface averaged to pixels", "pixels.png"))
    return figs


def _pixels_figure(subplots, mi, out: Path, quick: bool) -> None:
    """Render a V-groove surface with visible facets, average it to pixels, and compare the
    averaged brightness over view angles with the solver (the lecture's finite-pixel point)."""
    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    try:
        _pixels_render(subplots, mi, out, quick)
    finally:
        if previous is not None:  # leave Mitsuba as the caller had it
            mi.set_variant(previous)


def _pixels_render(subplots, mi, out: Path, quick: bool) -> None:
    import tempfile

    from ..simulate.cavity import cavity_radiance
    from ..simulate.grooves import render_grooves, write_groove_ply

    theta_a, theta_i, rho = 0.6, math.radians(50.0), 0.8
    wi = np.array([math.sin(theta_i), 0.0, math.cos(theta_i)])

    def view(t):  # t > 0: on the light's side of the normal (Δφ = 0)
        return np.array([math.sin(t), 0.0, math.cos(t)])

    with tempfile.TemporaryDirectory() as tmp:
        ply = write_groove_ply(Path(tmp) / "grooves.ply", theta_a)
        fine = render_grooves(
            mi, ply, rho, wi, view(math.radians(20.0)), 64, spp=16, res=256, n_periods=4
        )
        angles = np.radians(np.arange(-80.0, 81.0, 40.0 if quick else 10.0))
        means = [
            float(render_grooves(mi, ply, rho, wi, view(t), 64, spp=16, res=32).mean())
            for t in angles
        ]
    curve_t = np.radians(np.linspace(-85.0, 85.0, 171))
    curve = cavity_radiance(theta_a, 0.0, wi, np.stack([view(t) for t in curve_t]), rho, "all")
    coarse = fine.reshape(4, 64, 4, 64).mean(axis=(1, 3))  # 4 x 4 pixels, one period each
    fig, axes = subplots(1, 3, figsize=(13, 3.8), gridspec_kw={"width_ratios": [1, 1, 1.6]})
    vmax = float(fine.max())
    axes[0].imshow(fine, cmap="gray", vmin=0, vmax=vmax)
    axes[0].set_title("rendered, facets visible (θr = 20°)")
    axes[1].imshow(np.kron(coarse, np.ones((64, 64))), cmap="gray", vmin=0, vmax=vmax)
    axes[1].set_title("averaged to pixels one groove wide")
    for ax in axes[:2]:
        ax.set_xticks([])
        ax.set_yticks([])
    axes[2].plot(np.degrees(curve_t), curve, "k-", label="solver: cavity radiance, all bounces")
    axes[2].plot(np.degrees(angles), means, "o", color="C3", label="Mitsuba: pixel average")
    axes[2].plot(
        np.degrees(curve_t),
        np.full_like(curve_t, rho / math.pi * math.cos(theta_i)),
        "C2:",
        label="flat Lambertian plane",
    )
    axes[2].axvline(math.degrees(theta_i), color="0.7", lw=0.8)
    axes[2].set_xlabel("θr (°): > 0 towards the light (θi = 50°, marked)")
    axes[2].set_ylabel("radiance / E0")
    axes[2].set_title(f"V-grooves θa = {theta_a} rad, ρ = {rho}, across the plane of incidence")
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    atomic_write(out / "pixels.png", lambda tmp: fig.savefig(tmp, dpi=110))
