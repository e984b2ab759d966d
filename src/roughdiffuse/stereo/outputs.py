"""Writing a photometric-stereo result: arrays, images, a mesh, parameters and a report.

Every file is written whole or not at all (the image writers of
:mod:`roughdiffuse.io`). The folder holds:

``normals.npy``      (H, W, 3) unit normals, camera frame, NaN outside the mask
``albedo.npy``       (H, W) or (H, W, 3), NaN outside the mask
``depth.npy``        (H, W) depth in pixel units (z towards the camera), NaN outside
``depth.ply``        the depth as a triangle mesh
``params.json``      model, fitted global parameters with standard errors, error statistics
``*.png``, ``*.exr`` normal, albedo, roughness (per-pixel fits) and residual maps
``report.html``      the images and statistics, the Lambertian result beside the rough one
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

from .inputs import StereoInput
from .lambertian import LambertianResult
from .rough import RoughResult

__all__ = ["result_maps", "write_outputs"]


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
        if np.ndim(result.roughness):
            maps[result.roughness_name] = _scatter(m, result.roughness)
    return maps


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


def _encode_png(linear: np.ndarray, mask: np.ndarray) -> bytes:
    import tempfile

    from ..io.images import write_png

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "x.png"
        write_png(p, linear, exposure=0.0, mask=mask.astype(np.float64))
        return p.read_bytes()


def write_outputs(
    folder: str | os.PathLike[str],
    data: StereoInput,
    rough: RoughResult,
    lambert: LambertianResult,
    depth: np.ndarray,
    *,
    model_id: str,
    truth_normals: np.ndarray | None = None,
    extra: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """Write every output file into ``folder`` (which must exist); return the parameters."""
    from ..io.atomic import write_text
    from ..io.images import write_exr, write_npy, write_png
    from .depth import write_ply
    from .synthetic import angular_error

    out = Path(folder)
    if not out.is_dir():
        raise ValueError(f"output folder {str(out)!r} does not exist")
    m = data.mask
    maps = result_maps(data, rough)
    lmaps = result_maps(data, lambert)
    write_npy(out / "normals.npy", maps["normals"])
    write_npy(out / "albedo.npy", maps["albedo"])
    write_npy(out / "depth.npy", depth)
    write_ply(out / "depth.ply", depth)
    shown = {}
    for key, image in maps.items():
        if key == "normals":
            write_exr(out / "normals.exr", np.nan_to_num(image))
        else:
            write_exr(out / f"{key}.exr", np.nan_to_num(image))
        lin = _png_of(image, key)
        write_png(out / f"{key}.png", lin, exposure=0.0, mask=m.astype(np.float64))
        shown[key] = (out / f"{key}.png").read_bytes()
    shown["depth"] = _encode_png(_png_of(depth, "depth"), m & np.isfinite(depth))
    shown["lambertian normals"] = _encode_png(_png_of(lmaps["normals"], "normals"), m)
    shown["lambertian residual"] = _encode_png(_png_of(lmaps["residual"], "residual"), m)
    rough_val = rough.roughness
    params: dict[str, Any] = {
        "model": model_id,
        "images": data.count,
        "pixels": int(m.sum()),
        "roughness": {
            "name": rough.roughness_name,
            "per_pixel": bool(np.ndim(rough_val)),
        },
        "rough": {
            "relative_rms_residual": _stats(rough.residual),
            "normal_standard_error_deg": _stats(np.degrees(rough.normal_se)),
            "iterations": rough.iterations,
        },
        "lambertian": {"relative_rms_residual": _stats(lambert.residual)},
    }
    if np.ndim(rough_val):
        params["roughness"].update(
            {
                "median": float(np.nanmedian(rough_val)),
                "median_standard_error": float(np.nanmedian(rough.roughness_se)),
            }
        )
    else:
        params["roughness"].update(
            {"value": float(rough_val), "standard_error": float(rough.roughness_se)}
        )
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


def _report_html(params: dict[str, Any], images: dict[str, bytes]) -> str:
    def img(name: str) -> str:
        b64 = base64.b64encode(images[name]).decode()
        return (
            f'<figure><img alt="{html.escape(name)}" src="data:image/png;base64,{b64}">'
            f"<figcaption>{html.escape(name)}</figcaption></figure>"
        )

    r = params["roughness"]
    if r["per_pixel"]:
        rline = (
            f"{r['name']} per pixel: median {r['median']:.4g} "
            f"(median standard error {r['median_standard_error']:.2g})"
        )
    else:
        rline = f"{r['name']} = {r['value']:.4g} ± {r['standard_error']:.2g} (one for the object)"
    rows = []
    for label, key in (("rough model", "rough"), ("Lambertian", "lambertian")):
        s = params[key]
        res = s["relative_rms_residual"]
        ang = s.get("angular_error_deg")
        rows.append(
            f"<tr><td>{label}</td><td>{res['median']:.3g}</td><td>{res['p95']:.3g}</td>"
            + (
                f"<td>{ang['mean']:.3g}°</td><td>{ang['median']:.3g}°</td>"
                if ang
                else "<td>–</td><td>–</td>"
            )
            + "</tr>"
        )
    buf = io.StringIO()
    buf.write(
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        "<title>roughdiffuse stereo report</title><style>"
        "body{font-family:system-ui,sans-serif;margin:2em;max-width:70em}"
        "figure{display:inline-block;margin:0 1em 1em 0}"
        "img{width:256px;image-rendering:pixelated;background:#222}"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 8px}"
        "</style></head><body>"
    )
    buf.write(f"<h1>Photometric stereo: {html.escape(params['model'])}</h1>")
    buf.write(
        f"<p>{params['images']} images, {params['pixels']} object pixels. {html.escape(rline)}. "
        f"{params['rough']['iterations']} iterations.</p>"
    )
    buf.write(
        "<table><tr><th>method</th><th>median relative RMS residual</th><th>95th percentile</th>"
        "<th>mean angular error</th><th>median angular error</th></tr>" + "".join(rows) + "</table>"
    )
    buf.write("<h2>Rough model</h2>")
    for name in images:
        if not name.startswith("lambertian"):
            buf.write(img(name))
    buf.write("<h2>Lambertian photometric stereo</h2>")
    for name in images:
        if name.startswith("lambertian"):
            buf.write(img(name))
    buf.write("</body></html>\n")
    return buf.getvalue()
