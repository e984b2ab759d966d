"""Writing a photometric-stereo result: arrays, images, a mesh, parameters and a report.

Every file is written whole or not at all (the image writers of
:mod:`roughdiffuse.io`). The folder holds:

``normals.npy``      (H, W, 3) unit normals, camera frame, NaN outside the mask
``albedo.npy``       (H, W) or (H, W, 3), NaN outside the mask
``depth.npy``        (H, W) depth in pixel units (z towards the camera), NaN outside
``depth.ply``        the depth as a triangle mesh
``params.json``      model, fitted global parameters with standard errors, error statistics
``*.png``, ``*.exr`` normal, albedo, roughness (per-pixel fits) and residual maps
``report.html``      inputs, lights, maps with colour bars (Lambertian and rough on one scale)
"""

from __future__ import annotations

import base64
import html
import io
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput
from .lambertian import LambertianResult
from .report_figures import NORMAL_KEY, report_pngs
from .rough import RoughResult

__all__ = [
    "coat_params",
    "figure_html",
    "fitted_values",
    "method_stats",
    "methods_table_html",
    "result_maps",
    "write_outputs",
]


def _scatter(mask: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Per-pixel values (P, ...) back into an (H, W, ...) image, NaN outside the mask."""
    out = np.full(mask.shape + values.shape[1:], np.nan)
    out[mask] = values
    return out


def result_maps(data: StereoInput, result: RoughResult | LambertianResult) -> dict[str, np.ndarray]:
    """The per-pixel results of ``result`` as (H, W, ...) maps, NaN outside the mask."""
    m = data.mask
    maps = {
        "normals": _scatter(m, result.normals),
        "albedo": _scatter(m, result.albedo if data.channels > 1 else result.albedo[:, 0]),
        "residual": _scatter(m, result.residual),
    }
    if isinstance(result, RoughResult):
        maps["normal_se_deg"] = _scatter(m, np.degrees(result.normal_se))
    for name, value, se in fitted_values(result):
        if np.ndim(value):  # one per pixel: its map and its standard error's
            maps[name] = _scatter(m, value)
            maps[f"{name}_se"] = _scatter(m, se)
    return maps


def coat_params(result: Any) -> dict[str, Any]:
    """The coat's entry of params.json (a coated result: :class:`.coated.CoatedResult`): α
    (one value with its standard error, or the median of the per-pixel map), η, the base,
    the shadow rounds, and whether the coat explains the images (α ``None`` if not)."""
    coat: dict[str, Any] = {
        "eta": float(result.eta),
        "base": getattr(result, "base", None),
        "shadow_rounds": getattr(result, "shadow_rounds", None),
        "coat_explains_the_images": bool(result.coat),
    }
    if not result.coat:
        coat["alpha"] = None
    elif np.ndim(result.alpha):
        coat["alpha"] = {"per_pixel": True, "median": float(np.nanmedian(result.alpha)),
                         "median_standard_error": float(np.nanmedian(result.alpha_se))}
    else:
        coat["alpha"] = {"per_pixel": False, "value": float(result.alpha),
                         "standard_error": float(result.alpha_se)}
    return coat


def fitted_values(result: Any) -> list[tuple[str, Any, Any]]:
    """The fitted parameters of a rough or coated result besides its normals and albedo, as
    (name, value, standard error): the base's roughness (``sigma``...) and, for a coated
    fit whose coat explains the images, the coat's ``alpha``; each a number or an array (P,)
    of one per pixel. A Lambertian result has none."""
    if not hasattr(result, "roughness"):  # by its fields: a Lambertian result has none
        return []
    name = getattr(result, "roughness_name", "sigma")
    out = [(name, result.roughness, result.roughness_se)]
    if getattr(result, "coat", False):
        out.append(("alpha", result.alpha, result.alpha_se))
    return out


def _stats(values: np.ndarray) -> dict[str, float]:
    v = values[np.isfinite(values)]
    if v.size == 0:
        return {"mean": math.nan, "median": math.nan, "p95": math.nan}
    return {
        "mean": float(v.mean()),
        "median": float(np.median(v)),
        "p95": float(np.percentile(v, 95)),
    }


def _png_of(image: np.ndarray, kind: str) -> np.ndarray:
    """A displayable linear image (values in [0, 1]) of a map."""
    valid = np.isfinite(image) if image.ndim == 2 else np.all(np.isfinite(image), axis=-1)
    if kind == "normals":
        return np.where(valid[..., None], 0.5 * (np.nan_to_num(image) + 1.0), 0.0)
    v = np.nan_to_num(image)
    if kind == "albedo":  # albedo is in [0, 1] already: shown as it is
        return np.clip(v, 0.0, 1.0)
    if kind == "depth":  # nearest white, farthest black
        lo = np.min(v[valid]) if valid.any() else 0.0
        v = np.where(valid, v - lo, 0.0)
    top = np.percentile(v[valid], 99) if valid.any() else 1.0
    return np.clip(v / (top if top > 0 else 1.0), 0.0, 1.0)


def _roughness_entry(rough: RoughResult) -> dict[str, Any]:
    """``params["roughness"]``: its name, and its value and standard error (one for the
    object) or their medians (per pixel)."""
    value = rough.roughness
    entry: dict[str, Any] = {"name": rough.roughness_name, "per_pixel": bool(np.ndim(value))}
    if np.ndim(value):
        entry["median"] = float(np.nanmedian(value))
        entry["median_standard_error"] = float(np.nanmedian(rough.roughness_se))
    else:
        entry["value"] = float(value)
        entry["standard_error"] = float(rough.roughness_se)
    return entry


def write_outputs(
    folder: str | os.PathLike[str],
    data: StereoInput,
    rough: RoughResult | None,
    lambert: LambertianResult,
    depth: np.ndarray,
    *,
    model_id: str,
    truth_normals: np.ndarray | None = None,
    extra: dict[str, Any] | None = None,
    methods: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Write every output file into ``folder`` (which must exist); return the parameters.

    With ``rough=None`` the result is Lambertian photometric stereo alone (Woodham 1980):
    the same files from ``lambert``, with no roughness (``"roughness": null``); a
    ``model_id`` naming a robust method (``l1``, ``sparse``, ``rpca``) labels ``lambert``
    as that method's result. ``methods`` (name -> result with ``normals`` and ``weights``)
    adds, per method, the fraction of observations it rejected, its angular error against
    ``truth_normals`` when known, their maps and a table (``params["methods"]``).
    """
    from ..io.atomic import write_text
    from ..io.images import write_exr, write_npy, write_png
    from .depth import write_ply
    from .synthetic import angular_error

    out = Path(folder)
    if not out.is_dir():
        raise ParameterError(f"output folder {str(out)!r} does not exist")
    m = data.mask
    maps = result_maps(data, lambert if rough is None else rough)
    lmaps = result_maps(data, lambert)
    write_npy(out / "normals.npy", maps["normals"])
    write_npy(out / "albedo.npy", maps["albedo"])
    write_npy(out / "depth.npy", depth)
    write_ply(out / "depth.ply", depth)
    for key, image in maps.items():
        write_exr(out / f"{key}.exr", np.nan_to_num(image))
        lin = _png_of(image, key)
        write_png(out / f"{key}.png", lin, exposure=0.0, mask=m.astype(np.float64))
    extra = dict(extra or {})
    if methods:
        extra["methods"] = method_stats(m, methods, truth_normals)
    if rough is None:
        shown = report_pngs(data, maps, None, depth, model_id, None)
        shown.update(_methods_pngs(m, methods, truth_normals))  # keys: METHODS_PREFIX
        return _write_params(out, data, lambert, shown, model_id, truth_normals, extra)
    shown = report_pngs(data, maps, lmaps, depth, model_id,
                        [name for name, value, _ in fitted_values(rough) if np.ndim(value)])
    shown.update(_methods_pngs(m, methods, truth_normals))
    params: dict[str, Any] = {
        "model": model_id,
        "images": data.count,
        "pixels": int(m.sum()),
        "roughness": _roughness_entry(rough),
        "rough": {
            "relative_rms_residual": _stats(rough.residual),
            "normal_standard_error_deg": _stats(np.degrees(rough.normal_se)),
            "iterations": rough.iterations,
        },
        "lambertian": {"relative_rms_residual": _stats(lambert.residual)},
    }
    if hasattr(rough, "coat"):  # a coated fit: its coat's α and η
        params["coat"] = coat_params(rough)
    if truth_normals is not None:
        t = truth_normals[m]
        params["rough"]["angular_error_deg"] = _stats(angular_error(rough.normals, t))
        params["lambertian"]["angular_error_deg"] = _stats(angular_error(lambert.normals, t))
    params.update(extra or {})
    from ..io.jsonfile import write_json

    write_json(out / "params.json", params, indent=2)
    page = _report_html(params, shown)
    write_text(out / "report.html", page)
    return params


def method_stats(
    mask: np.ndarray, results: dict[str, Any], truth: np.ndarray | None
) -> dict[str, dict[str, Any]]:
    """Per method: the fraction of observations rejected and, with ``truth`` (H, W, 3), the
    angular error statistics (degrees) over the object pixels with a normal."""
    from .synthetic import angular_error

    out: dict[str, dict[str, Any]] = {}
    for name, r in results.items():
        w = np.asarray(r.weights)
        entry: dict[str, Any] = {
            "rejected_fraction": float(1.0 - w.mean()),
            "pixels_without_normal": int(np.sum(~np.all(np.isfinite(r.normals), axis=-1))),
        }
        if truth is not None:
            entry["angular_error_deg"] = _stats(angular_error(r.normals, truth[mask]))
        out[name] = entry
    return out


METHODS_PREFIX = "every method: "
"""The captions of the per-method pictures begin so: the report shows them in their section."""


def _methods_pngs(
    mask: np.ndarray, results: dict[str, Any] | None, truth: np.ndarray | None
) -> dict[str, bytes]:
    if not results:
        return {}
    from .report_figures import methods_pngs

    return {METHODS_PREFIX + k: v for k, v in methods_pngs(mask, results, truth).items()}


def methods_table_html(stats: dict[str, dict[str, Any]]) -> str:
    """The per-method table of the report: rejected fraction and angular error (if known)."""
    from .methods import METHOD_LABELS

    angles = any("angular_error_deg" in s for s in stats.values())
    head = "<tr><th>method</th><th>observations rejected</th>" + (
        "<th>mean angular error</th><th>median</th><th>95th percentile</th>" if angles else ""
    ) + "</tr>"
    rows = []
    for name, s in stats.items():
        label = html.escape(METHOD_LABELS.get(name, name))
        cells = f"<td>{label}</td><td class=num>{100 * s['rejected_fraction']:.1f} %</td>"
        if angles:
            a = s["angular_error_deg"]
            cells += "".join(f"<td class=num>{a[k]:.3g}°</td>" for k in ("mean", "median", "p95"))
        rows.append(f"<tr>{cells}</tr>")
    return f"<table>{head}{''.join(rows)}</table>"


def _write_params(
    out: Path,
    data: StereoInput,
    lambert: LambertianResult,
    shown: dict[str, bytes],
    model_id: str,
    truth_normals: np.ndarray | None,
    extra: dict[str, Any] | None,
) -> dict[str, Any]:
    """params.json and report.html of Lambertian photometric stereo alone."""
    from ..io.atomic import write_text
    from .synthetic import angular_error

    m = data.mask
    params: dict[str, Any] = {
        "model": model_id,
        "images": data.count,
        "pixels": int(m.sum()),
        "roughness": None,
        "lambertian": {"relative_rms_residual": _stats(lambert.residual)},
    }
    if truth_normals is not None:
        err = angular_error(lambert.normals, truth_normals[m])
        params["lambertian"]["angular_error_deg"] = _stats(err)
    params.update(extra or {})
    from ..io.jsonfile import write_json

    write_json(out / "params.json", params, indent=2)
    write_text(out / "report.html", _report_html(params, shown))
    return params


REPORT_STYLE = (
    "body{font-family:system-ui,sans-serif;margin:2em;max-width:80em}"
    "figure{margin:0 0 1.5em 0}img{max-width:100%}"
    "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px}"
    "td.num{text-align:right}"
)
"""The style sheet of the stereo reports."""


def figure_html(caption: str, png: bytes, alt: str | None = None) -> str:
    """A PNG embedded in a report page, with its caption."""
    b64 = base64.b64encode(png).decode()
    return (
        f'<figure><img alt="{html.escape(alt or caption)}" src="data:image/png;base64,{b64}">'
        f"<figcaption>{html.escape(caption)}</figcaption></figure>"
    )


def _coat_text(coat: dict[str, Any] | None) -> str:
    """The coat's part of the report's summary (``params["coat"]``): α with its standard
    error, or the median of its per-pixel map, and η; or that no coat fits."""
    if not coat:
        return ""
    a = coat.get("alpha")
    if a is None:
        return ("; no coat: a coat does not fit these images better than the bare base (the "
                "result is the rough fit's)")
    if a["per_pixel"]:
        text = (f"; coat α per pixel: median {a['median']:.4g} (median standard error "
                f"{a['median_standard_error']:.2g})")
    else:
        text = f"; coat α = {a['value']:.4g} ± {a['standard_error']:.2g} (one for the object)"
    return text + f", η = {coat['eta']:g} (fixed)"


def _report_html(params: dict[str, Any], images: dict[str, bytes]) -> str:
    def img(name: str) -> str:
        return figure_html(name + (f" ({NORMAL_KEY})" if name == "normals" else ""),
                           images[name], alt=name)

    r = params["roughness"]
    truth = params.get("truth") or {}
    true_value = truth.get(r["name"]) if r is not None else None
    if r is None:
        from .methods import METHOD_LABELS

        method = METHOD_LABELS.get(params["model"], "Lambertian least squares (Woodham 1980)")
        rline = f"Lambertian photometric stereo, {method}: no roughness"
    elif r["per_pixel"]:
        rline = (
            f"{r['name']} per pixel: median {r['median']:.4g} "
            f"(median standard error {r['median_standard_error']:.2g})"
        )
    else:
        rline = f"{r['name']} = {r['value']:.4g} ± {r['standard_error']:.2g} (one for the object)"
    if true_value is not None:
        rline += f"; the true {r['name']} of the rendered object is {true_value:.4g}"
        if not r["per_pixel"] and r["standard_error"] > 0:
            off = abs(r["value"] - true_value) / r["standard_error"]
            rline += f" ({off:.1f} standard errors away)"
    rline += _coat_text(params.get("coat"))
    fitted = "coated model" if params.get("coat") else "rough model"
    rows = []
    lam_label = "Lambertian" if r is not None or params["model"] == "lambert" else params["model"]
    for label, key in ((fitted, "rough"), (lam_label, "lambertian")):
        if key not in params:
            continue
        s = params[key]
        res = s["relative_rms_residual"]
        ang = s.get("angular_error_deg")
        rows.append(
            f"<tr><td>{label}</td><td class=num>{res['median']:.3g}</td>"
            f"<td class=num>{res['p95']:.3g}</td>"
            + (
                f"<td class=num>{ang['mean']:.3g}°</td><td class=num>{ang['median']:.3g}°</td>"
                if ang
                else ""
            )
            + "</tr>"
        )
    angles = any(params.get(k, {}).get("angular_error_deg") for k in ("rough", "lambertian"))
    buf = io.StringIO()
    buf.write(
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        "<title>roughdiffuse stereo report</title><style>" + REPORT_STYLE +
        "</style></head><body>"
    )
    buf.write(f"<h1>Photometric stereo: {html.escape(params['model'])}</h1>")
    buf.write(
        f"<p>{params['images']} images, {params['pixels']} object pixels. {html.escape(rline)}. "
        + (f"{params['rough']['iterations']} iterations." if "rough" in params else "")
        + "</p>"
    )
    buf.write(
        "<table><tr><th>method</th><th>median relative RMS residual</th><th>95th percentile</th>"
        + ("<th>mean angular error (vs truth)</th><th>median angular error</th>" if angles
           else "")
        + "</tr>" + "".join(rows) + "</table>"
    )
    buf.write(f"<h2>The {fitted} beside Lambertian photometric stereo</h2>" if r is not None
              else "<h2>Lambertian photometric stereo</h2>")
    for name in images:
        if not name.startswith(METHODS_PREFIX):
            buf.write(img(name))
    if "methods" in params:
        buf.write("<h2>Every method</h2>" + methods_table_html(params["methods"]))
        for name, png in images.items():
            if name.startswith(METHODS_PREFIX):
                buf.write(figure_html(name[len(METHODS_PREFIX):], png))
    buf.write("</body></html>\n")
    return buf.getvalue()
