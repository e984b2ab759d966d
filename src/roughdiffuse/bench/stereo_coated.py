"""Benchmark: coated photometric stereo on Mitsuba renders in DiLiGenT's layout.

Every object folder ``<renders>/pmsData/<shape>-<material>PNG`` written by
``scripts/stereo_renders.py`` (a sphere, a lumpy blob and a vase; full Oren–Nayar ρ 0.6,
σ 0.4, bare (``matte``), under a coat of η 1.5 and GGX α 0.1 or 0.3 (``coat01``,
``coat03``), or with an aluminium GGX lobe (``metal``); 96 lights, 1 % noise, 12 bits) is
solved by Lambertian least squares, by the robust Lambertian solvers (``l1``, ``sparse``,
``rpca`` of :mod:`roughdiffuse.stereo.robust`), by the rough fit (full Oren–Nayar, one σ) and
by the coated fit (its table solver from its own Lambertian start; once with the light
intensities as given and once with a fitted light scale). The table gives the mean angular
error against ``Normal_gt.mat`` and the fitted σ, α and light scale with their standard
errors (and σ once more from the pixels within 60° of the view only: :data:`INNER`); the
``metal`` objects are fitted with the η of :data:`ETA`. Speed is seconds per megapixel of
object pixels with 96 lights, warm, on the first object or on each ``--speed FOLDER`` (large
renders, where the fixed costs of a fit, the subsample's direct fit and the table, weigh
what they would on a real image; the target is judged on the largest), as a ratio to the
Lambertian solve timed in the same run. With ``--write RESULTS.md`` the section "Coated
photometric stereo" there is rewritten::

    python scripts/stereo_renders.py /tmp/renders --size 128
    python scripts/stereo_renders.py /tmp/big --size 512 --only sphere-coat03
    python scripts/stereo_renders.py /tmp/huge --size 1024 --only sphere-coat03
    python -m roughdiffuse.bench.stereo_coated --renders /tmp/renders \
        --speed /tmp/big/pmsData/sphere-coat03PNG \
        --speed /tmp/huge/pmsData/sphere-coat03PNG [--write FILE]
    python bench/stereo_coated.py --renders /tmp/renders [--write]  # bench/RESULTS.md

The coats are roughdiffuse's coated Oren–Nayar (its Mitsuba plugin; base σ 0.4). Targets:
coated ≤ 1.0° on the α = 0.3 sphere and ≤ 2° on the α = 0.3 mesh (blob), below every
Lambertian solver and the rough fit on the coated objects, no worse than the rough fit on the
matte ones, σ within its error bars, ≤ 60 s per megapixel on 2 cores.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import time
from pathlib import Path
from typing import Any

import numpy as np

from roughdiffuse import stereo

from .timing import write_section

BEGIN = "<!-- stereo-coated:begin -->"
END = "<!-- stereo-coated:end -->"
HEADING = "## Coated photometric stereo"

ROBUST = ("l1", "sparse", "rpca")
TRUE_SIGMA = {"matte": 0.4, "coat01": 0.4, "coat03": 0.4}
"""σ of each material's base: full Oren–Nayar, bare (``matte``) or under the coats
(roughdiffuse's ``roughdiffuse_coated`` plugin). The ``metal`` blend has no σ."""
TRUE_ALPHA = {"coat01": 0.1, "coat03": 0.3}
ETA = {"metal": 2.5}
"""η given to the coated fit per material (1.5 otherwise, the coats' own). The ``metal``
blend's specular lobe (a quarter of aluminium's, normal reflectance about 0.23) is no
dielectric coat of η 1.5 (0.04): 2.5 (0.18) is the dielectric nearest to it whose table
stays within its error bound (:data:`roughdiffuse.stereo.coated_table.ERROR_BOUND`)."""
INNER = 0.5
"""n_z of the true normal above which a pixel counts for the footprint-free σ: within 60°
of the view, where a pixel's normals spread little and the model at their mean is the
mean of the model."""


def _truth(folder: Path, mask: np.ndarray) -> np.ndarray:
    from scipy.io import loadmat

    n = np.asarray(loadmat(folder / "Normal_gt.mat")["Normal_gt"], dtype=np.float64)
    return n[mask]


def _error(normals: np.ndarray, truth: np.ndarray) -> float:
    return float(np.nanmean(stereo.angular_error(normals, truth)))


def _timed(fn: Any) -> tuple[Any, float, float]:
    t, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t, time.process_time() - c


def robust_errors(data: Any, truth: np.ndarray) -> dict[str, float]:
    """The mean angular error of each robust Lambertian solver (:data:`ROBUST`, by
    :func:`roughdiffuse.stereo.robust.robust` with its defaults) on one object: the rows the
    coated fit must stay below."""
    from roughdiffuse.stereo.robust import robust

    return {m: _error(robust(data, m).normals, truth) for m in ROBUST}


def measure(folder: Path, robust: Any) -> dict[str, Any]:
    """Errors, fitted values and times of every method on one object folder."""
    import roughdiffuse as rd

    data = stereo.read_diligent(folder)
    truth = _truth(folder, data.mask)
    row: dict[str, Any] = {"name": folder.name[:-3], "pixels": int(data.mask.sum())}
    lam, row["t_lambertian"], _ = _timed(lambda: stereo.lambertian(data))
    row["lambertian"] = _error(lam.normals, truth)
    if robust is not None:
        row.update(robust_errors(data, truth))
    rough, t_rough, c_rough = _timed(lambda: stereo.rough(data, rd.OrenNayar(variant="full")))
    row["rough"] = _error(rough.normals, truth)
    row["sigma_rough"] = (float(rough.roughness), float(rough.roughness_se))
    material = row["name"].split("-")[-1]
    eta = ETA.get(material, 1.5)
    res, t_coat, c_coat = _timed(lambda: stereo.coated(data, eta=eta))
    row["eta"] = eta
    row["coated"] = _error(res.normals, truth)
    # σ of the pixels within 60° of the view only (their true normals): the footprint's bias
    # left out, the measure of the fit itself
    inner = np.zeros_like(data.mask)
    inner[data.mask] = truth[:, 2] >= INNER
    centre = stereo.coated(dataclasses.replace(data, mask=inner), eta=eta)
    row["sigma_inner"] = (float(centre.sigma), float(centre.sigma_se))
    row["sigma"] = (float(res.sigma), float(res.sigma_se))
    row["alpha"] = (float(res.alpha), float(res.alpha_se))
    row["table_error"] = float(res.table_error)
    row["t_coated"], row["c_coated"] = t_coat, c_coat
    nan = (math.nan, math.nan)
    row["coated_s"], row["scale"], row["alpha_s"], row["sigma_s"] = math.nan, nan, nan, nan
    if "coat" in material:  # a matte object: the rough fit, no scale
        scaled = stereo.coated(data, light_scale=True, eta=eta)
        row["coated_s"] = _error(scaled.normals, truth)
        row["scale"] = (float(scaled.light_scale), float(scaled.light_scale_se))
        row["alpha_s"] = (float(scaled.alpha), float(scaled.alpha_se))
        row["sigma_s"] = (float(scaled.sigma), float(scaled.sigma_se))
    row["data"] = data
    return row


def _speed(folder: Path) -> dict[str, Any]:
    """Warm times of one object: the Lambertian solve, the rough fit, the shadows of the
    model (:func:`roughdiffuse.stereo.coated.model_weights`, cast shadows included) and the
    coated fit (table solver, from its own Lambertian start; wall and CPU seconds)."""
    import roughdiffuse as rd
    from roughdiffuse.stereo.coated import model_weights
    from roughdiffuse.stereo.depth import clear_cache

    data = stereo.read_diligent(folder)
    stereo.coated(data, shadow_rounds=0)  # compile whatever this size needs
    out: dict[str, Any] = {"name": folder.name[:-3], "mpx": int(data.mask.sum()) / 1e6,
                           "size": data.mask.shape}
    lam, out["lambertian"], _ = _timed(lambda: stereo.lambertian(data))
    clear_cache()
    _, out["weights"], _ = _timed(lambda: model_weights(data, lam.normals))
    _, out["rough"], _ = _timed(lambda: stereo.rough(data, rd.OrenNayar(variant="full")))
    clear_cache()  # the depth's factorisation, kept from the runs above: timed too
    res, out["coated"], out["coated_cpu"] = _timed(lambda: stereo.coated(data))
    out["rounds"] = res.shadow_rounds
    return out


def _speed_line(sp: dict[str, Any]) -> str:
    mpx = sp["mpx"]
    lam = sp["lambertian"] / mpx
    coat = sp["coated"] / mpx
    return (
        f"Speed on {sp['name']} ({sp['size'][1]} × {sp['size'][0]} image, {mpx * 1e6:.0f} "
        "object pixels, 96 lights, warm): Lambertian "
        f"{lam:.1f} s/Mpx; rough fit {sp['rough'] / mpx:.0f} s/Mpx; the model's shadows "
        f"(the normals integrated, cast shadows by one sweep per light; once per round) "
        f"{sp['weights'] / mpx:.1f} s/Mpx each; coated fit (table solver, its Lambertian "
        f"start and {sp['rounds']} shadow rounds included) {coat:.0f} s/Mpx "
        f"({sp['coated_cpu'] / mpx:.0f} CPU s/Mpx), {coat / max(lam, 1e-9):.0f}× the "
        "Lambertian solve."
    )


def _pm(v: tuple[float, float]) -> str:
    return f"{v[0]:.3f} ± {v[1]:.3f}"


def _table(rows: list[dict[str, Any]], robust: bool) -> list[str]:
    methods = ["lambertian", *(ROBUST if robust else ()), "rough", "coated", "coated_s"]
    names = [m if m != "coated_s" else "coated, light scale" for m in methods]
    head = ("| object | pixels | " + " | ".join(names)
            + " | σ rough | σ coated | σ coated, within 60° | α coated | σ, light scale "
            "| α, light scale | light scale |")
    lines = [head, "| --- | ---: | " + " | ".join("---:" for _ in methods)
             + " | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        material = r["name"].split("-")[-1]
        truth = f" ({TRUE_ALPHA[material]})" if material in TRUE_ALPHA else ""
        errs = " | ".join(f"{r[m]:.2f}°" for m in methods)
        eta = f" (η {r['eta']:g})" if r["eta"] != 1.5 else ""
        lines.append(
            f"| {r['name']}{eta} | {r['pixels']} | {errs} | {_pm(r['sigma_rough'])} | "
            f"{_pm(r['sigma'])} | {_pm(r['sigma_inner'])} | {_pm(r['alpha'])}{truth} | "
            f"{_pm(r['sigma_s'])} | "
            f"{_pm(r['alpha_s'])}{truth} | {_pm(r['scale'])} |"
        )
    return lines


def _within(value: tuple[float, float], truth: float) -> bool:
    """Whether a fitted value lies within two of its standard errors of the truth: a finite
    standard error (an infinite one, σ not determined, counts as missed)."""
    return math.isfinite(value[1]) and abs(value[0] - truth) <= 2 * value[1]


def _targets(rows: list[dict[str, Any]], robust: bool, per_mpx: float) -> list[str]:
    by = {r["name"]: r for r in rows}
    out = []

    def check(text: str, ok: bool | None) -> None:
        out.append(f"- {text}: {'✓' if ok else ('✗' if ok is not None else 'not measured')}")

    for name, bound in (("sphere-coat03", 1.0), ("blob-coat03", 2.0)):
        r = by.get(name)
        check(
            f"coated ≤ {bound}° on {name}" + (f" ({r['coated']:.2f}°)" if r else ""),
            None if r is None else r["coated"] <= bound,
        )
    lam_methods = ["lambertian", *(ROBUST if robust else ())]
    coat_rows = [r for r in rows if "coat" in r["name"].split("-")[-1]]
    below = [all(r["coated"] < r[m] for m in [*lam_methods, "rough"]) for r in coat_rows]
    check(
        f"coated below every Lambertian solver and the rough fit on the coated objects "
        f"({sum(below)} of {len(below)})",
        all(below) if below else None,
    )
    if robust:  # the target: below every robust solver on every object
        below_robust = [all(r["coated"] < r[m] for m in ROBUST) for r in rows]
        check(
            f"coated below every robust Lambertian solver ({', '.join(ROBUST)}) on every "
            f"object ({sum(below_robust)} of {len(below_robust)})",
            all(below_robust),
        )
    matte = [r for r in rows if r["name"].endswith("matte")]
    no_worse = [r["coated"] <= r["rough"] + 0.05 for r in matte]
    check(
        f"on the matte objects no worse than the rough fit (within 0.05°; {sum(no_worse)} of "
        f"{len(no_worse)})",
        all(no_worse) if no_worse else None,
    )
    within = [
        _within(r["sigma"], TRUE_SIGMA[m])
        for r in rows
        if (m := r["name"].split("-")[-1]) in TRUE_SIGMA
    ]
    check(
        f"coated σ within two standard errors of the truth ({sum(within)} of {len(within)})",
        all(within) if within else None,
    )
    inner = [
        _within(r["sigma_inner"], TRUE_SIGMA[m])
        for r in rows
        if (m := r["name"].split("-")[-1]) in TRUE_SIGMA
    ]
    check(
        f"coated σ of the pixels within 60° of the view within two standard errors of the "
        f"truth ({sum(inner)} of {len(inner)})",
        all(inner) if inner else None,
    )
    check(f"≤ 60 s per megapixel on the largest render timed ({per_mpx:.0f} s)", per_mpx <= 60)
    return out


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    parser.add_argument("--renders", required=True, help="folder holding pmsData/")
    parser.add_argument("--only", help="comma-separated object names (<shape>-<material>) "
                        "or shapes")
    parser.add_argument("--write", metavar="RESULTS.md", help="rewrite this table's section there")
    parser.add_argument("--speed", metavar="FOLDER", action="append",
                        help="object folder timed for speed (default: the first object; may "
                        "be given several times, the target judged on the largest): a large "
                        "render gives the per-megapixel figure without fixed costs")
    args = parser.parse_args(argv)
    robust = True  # the robust solvers' rows (robust_errors)
    folders = sorted((Path(args.renders) / "pmsData").glob("*PNG"))
    if args.only:
        keep = set(args.only.split(","))
        folders = [f for f in folders if f.name[:-3] in keep or f.name.split("-")[0] in keep]
    if not folders:
        raise SystemExit(f"no <object>PNG folder under {args.renders}/pmsData")
    load = os.getloadavg()[0]
    rows = []
    for folder in folders:
        rows.append(measure(folder, robust))
        load = max(load, os.getloadavg()[0])
        print(rows[-1]["name"], {k: v for k, v in rows[-1].items() if k in ("coated", "rough")})
    # speed, warm (the kernels compiled by now), with 96 lights
    speeds = [_speed(Path(f)) for f in (args.speed or [folders[0]])]
    load = max(load, os.getloadavg()[0])
    data = rows[0]["data"]
    largest = max(speeds, key=lambda sp: sp["mpx"])
    per_mpx = largest["coated"] / largest["mpx"]
    cores = len(os.sched_getaffinity(0))
    lines = [
        BEGIN,
        HEADING,
        "",
        f"`python -m roughdiffuse.bench.stereo_coated` ({cores} cores, load average up to "
        f"{load:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}): Mitsuba renders "
        f"of `scripts/stereo_renders.py`, {data.count} lights, {data.images.shape[2]}² pixels; "
        "mean angular error against the true normals; σ and α with their standard errors "
        "(truth: σ 0.4, the base of every material but metal; α in brackets; α nan: "
        "the coat did not lower the residual and the result is the rough fit's). "
        + ("" if robust else "The robust solvers (`roughdiffuse.stereo.robust`) were absent."),
        "",
        *_table(rows, robust is not None),
        "",
        *[line for sp in speeds for line in (_speed_line(sp), "")],
        "Targets:",
        "",
        *_targets(rows, robust is not None, per_mpx),
        END,
    ]
    text = "\n".join(lines)
    print(text)
    if args.write:
        write_section(Path(args.write), text, BEGIN, END)


if __name__ == "__main__":
    main()
