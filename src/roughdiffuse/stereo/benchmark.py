"""The DiLiGenT protocol: every method on every object, mean angular error per object.

Shi, Wu, Lu, Tan, Matsushita and Ikehata, "A Benchmark Dataset and Evaluation Method for
Non-Lambertian and Uncalibrated Photometric Stereo", CVPR 2016: a folder ``pmsData`` holds
one folder per object, ``<object>PNG``, with the images listed in ``filenames.txt`` (16-bit
PNG), ``light_directions.txt`` and ``light_intensities.txt`` (one row per image),
``mask.png`` and the true normals ``Normal_gt.mat`` (MATLAB, variable ``Normal_gt``, H × W × 3,
the camera frame of the lights). The score of a method on an object is the mean angle
between its normals and the true ones over the mask; the paper's table has the methods as
rows, the objects as columns, and here their average as the last column.
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput, read_diligent

__all__ = [
    "OBJECT_FILES",
    "BenchmarkResult",
    "benchmark_objects",
    "read_truth",
    "run_benchmark",
    "write_benchmark",
]

OBJECT_FILES = (
    "filenames.txt",
    "light_directions.txt",
    "light_intensities.txt",
    "mask.png",
    "Normal_gt.mat",
)
"""The files every object folder of the benchmark holds."""

DILIGENT_ORDER = (
    "ball", "cat", "pot1", "bear", "pot2", "buddha", "goblet", "reading", "cow", "harvest"
)
"""The objects in the column order of Shi et al.'s table; others follow by name."""


def benchmark_objects(folder: str | os.PathLike[str]) -> list[tuple[str, Path]]:
    """The (name, folder) of every object of a DiLiGenT-format folder, in the paper's order.

    ``folder`` holds ``pmsData/`` (the data set's top folder) or is ``pmsData`` itself.
    Every object folder is checked for :data:`OBJECT_FILES` before any work.
    """
    root = Path(folder)
    if not root.is_dir():
        raise ParameterError(f"--benchmark: {root} is not a folder")
    data = root / "pmsData" if (root / "pmsData").is_dir() else root
    objects = sorted(p for p in data.iterdir() if p.is_dir() and p.name.endswith("PNG"))
    if not objects:
        raise ParameterError(
            f"--benchmark: no object folder (<object>PNG) in {data} (a DiLiGenT folder holds "
            "pmsData/<object>PNG/)"
        )
    for obj in objects:
        for name in OBJECT_FILES:
            if not (obj / name).is_file():
                raise ParameterError(f"--benchmark: {obj / name} is missing")
    rank = {n: i for i, n in enumerate(DILIGENT_ORDER)}
    named = [(p.name[: -len("PNG")] or p.name, p) for p in objects]
    return sorted(named, key=lambda t: (rank.get(t[0], len(rank)), t[0]))


def read_truth(path: str | os.PathLike[str], shape: tuple[int, int]) -> np.ndarray:
    """The true normals (H, W, 3) of ``Normal_gt.mat``, unit length where not zero."""
    from scipy.io import loadmat

    try:
        mat = loadmat(os.fspath(path))
    except (OSError, ValueError, TypeError) as exc:
        raise ParameterError(f"{path}: not a readable MATLAB file ({exc})") from None
    if "Normal_gt" not in mat:
        raise ParameterError(f"{path}: holds no variable Normal_gt")
    n = np.asarray(mat["Normal_gt"], dtype=np.float64)
    if n.shape != (*shape, 3):
        raise ParameterError(
            f"{path}: Normal_gt is {n.shape}, the images need {(*shape, 3)}"
        )
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.where(length > 0, n / np.where(length > 0, length, 1.0), np.nan)


@dataclass
class BenchmarkResult:
    """Mean angular errors (degrees) by method and object, with what the report shows."""

    objects: list[str]
    methods: list[str]
    errors: dict[str, dict[str, float]]
    """method -> object -> mean angular error over the mask (pixels with a normal)."""
    failed: dict[str, dict[str, int]]
    """method -> object -> mask pixels the method gave no normal."""
    fitted: dict[str, dict[str, dict[str, tuple[float, float]]]] = field(default_factory=dict)
    """method -> object -> parameter -> (value, standard error), for the methods that fit
    more than normals and albedo (:func:`.outputs.fitted_values`: the rough fit's σ, the
    coated fit's σ and α; a per-pixel value by its median and its median error)."""
    details: dict[str, tuple[StereoInput, np.ndarray, dict[str, Any]]] = field(
        default_factory=dict, repr=False
    )
    """object -> (input, true normals, method -> result), for the report's maps."""

    def average(self, method: str) -> float:
        """Mean of the per-object errors of ``method`` (the table's last column)."""
        return float(np.mean([self.errors[method][o] for o in self.objects]))

    def rows(self) -> list[list[str]]:
        """The table, methods as rows, objects then the average as columns (2 decimals)."""
        head = ["method", *self.objects, "average"]
        body = [
            [m, *(f"{self.errors[m][o]:.2f}" for o in self.objects), f"{self.average(m):.2f}"]
            for m in self.methods
        ]
        return [head, *body]

    def markdown(self) -> str:
        """The table in Markdown."""
        rows = self.rows()
        lines = ["| " + " | ".join(r) + " |" for r in rows]
        lines.insert(1, "|" + "|".join([" --- "] + [" ---: "] * (len(rows[0]) - 1)) + "|")
        return (
            "Mean angular error (degrees) over each object's mask\n\n" + "\n".join(lines) + "\n"
        )

    def csv(self) -> str:
        """The table as CSV."""
        buf = io.StringIO()
        csv.writer(buf, lineterminator="\n").writerows(self.rows())
        return buf.getvalue()

    def json(self) -> dict[str, Any]:
        """The table as a JSON object (full precision)."""
        return {
            "unit": "degrees",
            "statistic": "mean angular error over the mask",
            "objects": self.objects,
            "methods": self.methods,
            "errors": self.errors,
            "average": {m: self.average(m) for m in self.methods},
            "pixels_without_normal": self.failed,
            "fitted": {
                m: {o: {k: {"value": v, "standard_error": se} for k, (v, se) in p.items()}
                    for o, p in by_object.items()}
                for m, by_object in self.fitted.items()
            },
        }

    def fitted_rows(self) -> list[list[str]]:
        """The fitted parameters as a table: one row per method and parameter, the objects
        as columns, each cell "value ± standard error" (3 decimals; "–" where the method
        fitted no such parameter, e.g. no coat explains a matte object)."""
        names = [
            (m, k)
            for m in self.methods
            for k in dict.fromkeys(k for p in self.fitted.get(m, {}).values() for k in p)
        ]
        rows = [["method", "parameter", *self.objects]]
        for m, k in names:
            cells = []
            for o in self.objects:
                v = self.fitted[m].get(o, {}).get(k)
                cells.append("–" if v is None else f"{v[0]:.3f} ± {v[1]:.3f}")
            rows.append([m, k, *cells])
        return rows if len(rows) > 1 else []


def run_benchmark(
    folder: str | os.PathLike[str],
    methods: list[str] | None = None,
    *,
    progress: bool = False,
    keep_details: bool = True,
) -> BenchmarkResult:
    """Run every method (default: all of :data:`.methods.METHODS`) on every object."""
    from ..progress import progress as bar
    from .methods import METHODS, run_method
    from .outputs import fitted_values
    from .synthetic import angular_error

    names = list(METHODS) if methods is None else list(methods)
    objects = benchmark_objects(folder)
    if "coated" in names:
        _check_coated_lights(objects)
    errors: dict[str, dict[str, float]] = {m: {} for m in names}
    failed: dict[str, dict[str, int]] = {m: {} for m in names}
    result = BenchmarkResult([o for o, _ in objects], names, errors, failed)
    with bar(len(objects) * len(names), "benchmark", unit="run", enabled=progress) as b:
        for obj, path in objects:
            data = read_diligent(path)
            truth = read_truth(path / "Normal_gt.mat", data.mask.shape)
            t = truth[data.mask]
            results = {}
            for m in names:
                b.set_postfix_str(f"{obj}: {m}")
                r = run_method(m, data)
                err = angular_error(r.normals, t)
                fine = np.isfinite(err)
                errors[m][obj] = float(err[fine].mean()) if fine.any() else math.nan
                failed[m][obj] = int(np.sum(~fine))
                values = {
                    name: (float(np.nanmedian(v)), float(np.nanmedian(se)))
                    for name, v, se in fitted_values(r)
                }
                if values:
                    result.fitted.setdefault(m, {})[obj] = values
                results[m] = r
                b.update(1)
            if keep_details:
                result.details[obj] = (data, truth, results)
    return result


def _check_coated_lights(objects: list[tuple[str, Path]]) -> None:
    """Refuse, before any work, an object with fewer images (lines of ``filenames.txt``) than
    the coated model's parameters per pixel (:func:`.coated.parameter_count`)."""
    from .coated import parameter_count

    need = parameter_count()
    for name, path in objects:
        lines = (path / "filenames.txt").read_text(errors="replace").splitlines()
        count = sum(1 for line in lines if line.strip())
        if count < need:
            raise ParameterError(
                f"--benchmark: the coated method fits {need} parameters per pixel (normal 2, "
                f"albedo, σ, coat α): object {name} has {count} images, it needs at least {need}"
            )


def write_benchmark(folder: str | os.PathLike[str], result: BenchmarkResult) -> None:
    """Write ``benchmark.md``, ``benchmark.csv``, ``benchmark.json`` and ``report.html``
    (the table, then per object the error map and the rejected observations of each method)
    into ``folder`` (which must exist)."""
    import html

    from ..io.atomic import write_text
    from ..io.jsonfile import write_json
    from .outputs import REPORT_STYLE, figure_html
    from .report_figures import methods_pngs

    out = Path(folder)
    write_text(out / "benchmark.md", result.markdown())
    write_text(out / "benchmark.csv", result.csv())
    write_json(out / "benchmark.json", result.json(), indent=2)
    rows = result.rows()
    table = "<table><tr>" + "".join(f"<th>{html.escape(c)}</th>" for c in rows[0]) + "</tr>"
    for r in rows[1:]:
        table += f"<tr><td>{html.escape(r[0])}</td>" + "".join(
            f"<td class=num>{c}</td>" for c in r[1:]) + "</tr>"
    table += "</table>"
    fitted = result.fitted_rows()
    if fitted:
        table += (
            "<h2>Fitted parameters</h2><p>One value for each object, ± its standard error "
            "(σ: the base's roughness in radians; α: the coat's GGX roughness; – : none "
            "fitted, e.g. no coat fits a matte object better than the bare base).</p><table><tr>"
            + "".join(f"<th>{html.escape(c)}</th>" for c in fitted[0]) + "</tr>"
        )
        for r in fitted[1:]:
            table += (f"<tr><td>{html.escape(r[0])}</td><td>{html.escape(r[1])}</td>"
                      + "".join(f"<td class=num>{c}</td>" for c in r[2:]) + "</tr>")
        table += "</table>"
    parts = [
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>roughdiffuse stereo benchmark</title><style>{REPORT_STYLE}</style></head><body>",
        "<h1>Photometric stereo benchmark (DiLiGenT protocol)</h1>",
        f"<p>{len(result.objects)} objects, {len(result.methods)} methods. Mean angular error "
        "(degrees) between each method's normals and the true ones over the object's mask "
        "(Shi et al., CVPR 2016).</p>",
        table,
    ]
    for obj, (data, truth, results) in result.details.items():
        parts.append(f"<h2>{html.escape(obj)}: {data.count} images, {int(data.mask.sum())} "
                     "pixels</h2>")
        for caption, png in methods_pngs(data.mask, results, truth, obj).items():
            parts.append(figure_html(caption, png))
    parts.append("</body></html>\n")
    write_text(out / "report.html", "".join(parts))
