"""Ground-truth tables: the V-cavity BRDF on a grid (θi, θr, Δφ, σ), in one ``.npz`` file.

Long tables are computed in chunks (one σ and a block of θi rows each). Every finished chunk
is written atomically (temporary file + ``os.replace``) into ``FILE.chunks/``, next to a
``manifest.json`` holding every parameter and solver setting: an interrupted run resumes
where it stopped (no finished chunk recomputed, no half-written chunk kept), and a run with
different settings refuses to reuse the chunks. Chunks run in this process (``workers=1``),
on a local Dask cluster (``workers=N``), or on a Dask distributed cluster (``scheduler``).
When all chunks are done the table is assembled into ``FILE`` and the chunk folder removed.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import tempfile
import zipfile
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .cavity import Bounces, check_bounces
from .surface import Settings, brdf

__all__ = ["FORMAT", "FORMAT_VERSION", "GroundTruth", "compute_table", "load_table"]

FORMAT = "roughdiffuse.GroundTruth"
FORMAT_VERSION = 1


def _package_version() -> str:
    from .. import __version__

    return __version__


@dataclass
class GroundTruth:
    """Exact V-cavity BRDF values f[θi, θr, Δφ, σ] (1/sr) with what produced them.

    Attributes
    ----------
    theta_i, theta_r, delta_phi, sigma : ndarray (1-D)
        Grid axes, radians.
    values : ndarray (nθi, nθr, nΔφ, nσ)
        f_r in 1/sr.
    k_difference : ndarray, same shape
        f(K) − f(2K) of the interreflected part (0 for one bounce): the element error
        before Richardson extrapolation, an upper bound of the error after it.
    albedo : float
    bounces : int or "all"
    settings : Settings
    meta : dict
        Format, package version, and anything else recorded.
    """

    theta_i: np.ndarray
    theta_r: np.ndarray
    delta_phi: np.ndarray
    sigma: np.ndarray
    values: np.ndarray
    k_difference: np.ndarray
    albedo: float
    bounces: Bounces
    settings: Settings
    meta: dict[str, Any] = field(default_factory=dict)

    def save(self, path: str | os.PathLike) -> Path:
        """Write the table to ``path`` (``.npz``) atomically; returns the path."""
        path = Path(path)
        meta = {
            **self.meta,
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "package_version": _package_version(),
            "albedo": self.albedo,
            "bounces": self.bounces,
            "settings": asdict(self.settings),
            "units": "f_r in 1/sr; angles in radians",
        }
        _atomic_savez(
            path,
            theta_i=self.theta_i,
            theta_r=self.theta_r,
            delta_phi=self.delta_phi,
            sigma=self.sigma,
            values=self.values,
            k_difference=self.k_difference,
            meta=np.array(json.dumps(meta)),
        )
        return path

    @classmethod
    def load(cls, path: str | os.PathLike) -> GroundTruth:
        """Read a table written by :meth:`save` (ValueError if it is not one, or corrupt)."""
        return load_table(path)


def _atomic_savez(path: Path, **arrays: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            np.savez(fh, **arrays)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def load_table(path: str | os.PathLike) -> GroundTruth:
    """Read a ground-truth table (see :class:`GroundTruth`)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        meta = json.loads(str(data["meta"]))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, json.JSONDecodeError) as exc:
        raise ValueError(
            f"{path}: not a readable roughdiffuse ground-truth table ({exc})"
        ) from None
    if meta.get("format") != FORMAT:
        raise ValueError(f"{path}: not a roughdiffuse ground-truth table")
    if meta.get("format_version") != FORMAT_VERSION:
        raise ValueError(
            f"{path}: table format version {meta.get('format_version')!r}; this roughdiffuse "
            f"reads version {FORMAT_VERSION} (recompute the table)"
        )
    try:
        settings = Settings(**meta["settings"])
        axes = [
            np.asarray(data[k], dtype=float) for k in ("theta_i", "theta_r", "delta_phi", "sigma")
        ]
        shape = tuple(a.size for a in axes)
        values = np.asarray(data["values"], dtype=float)
        kdiff = np.asarray(data["k_difference"], dtype=float)
    except (KeyError, TypeError) as exc:
        raise ValueError(f"{path}: corrupt ground-truth table ({exc})") from None
    if values.shape != shape or kdiff.shape != shape:
        raise ValueError(
            f"{path}: corrupt ground-truth table (values shape {values.shape} != {shape})"
        )
    return GroundTruth(*axes, values, kdiff, float(meta["albedo"]), meta["bounces"], settings, meta)


# --------------------------------------------------------------------------- chunked runs


BACKENDS: tuple[str, ...] = ("auto", "jax", "numpy")


def compute_chunk(spec: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """Values and K differences of one chunk: one σ, rows ``theta_i`` × all θr × all Δφ.

    A plain function of plain data, so that Dask workers can run it.
    """
    grid = np.meshgrid(spec["theta_i"], spec["theta_r"], spec["delta_phi"], indexing="ij")
    settings = Settings(**spec["settings"])
    if spec.get("backend", "numpy") == "jax":
        import jax
        import jax.numpy as jnp

        with jax.enable_x64(True):
            grid = [jnp.asarray(a, dtype=jnp.float64) for a in grid]
    f, d = brdf(
        *grid, spec["sigma"], spec["albedo"], spec["bounces"], settings, return_difference=True
    )
    return np.asarray(f), np.asarray(d)


def _grid(name: str, values: Any, lo: float, hi: float | None) -> np.ndarray:
    a = np.atleast_1d(np.asarray(values, dtype=float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a non-empty 1-D array of finite angles (radians)")
    if np.any(a < lo) or (hi is not None and np.any(a > hi)):
        raise ValueError(f"{name} must lie in [{lo:g}, {hi:g}] radians")
    return a


def compute_table(
    path: str | os.PathLike,
    theta_i: Any,
    theta_r: Any,
    delta_phi: Any,
    sigma: Any,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    settings: Settings | None = None,
    *,
    rows_per_chunk: int = 4,
    workers: int = 1,
    scheduler: str | None = None,
    progress: bool = True,
    backend: str = "auto",
) -> GroundTruth:
    """Compute a :class:`GroundTruth` table into ``path``, resumably (module docstring).

    Parameters
    ----------
    path : path
        The ``.npz`` file to write; chunks go to ``path.chunks/`` until it is done.
    theta_i, theta_r : array_like
        Angles in [0, π/2] radians.
    delta_phi : array_like
        Azimuth differences, radians.
    sigma : array_like
        Roughness values in [0, π/2] radians.
    albedo, bounces, settings
        As for :func:`roughdiffuse.simulate.brdf`.
    rows_per_chunk : int
        θi rows per chunk.
    workers : int
        1: compute here; N > 1: a local Dask cluster of N single-threaded processes.
    scheduler : str, optional
        Address of a Dask distributed scheduler (e.g. ``tcp://127.0.0.1:8786``).
    progress : bool
        Show a tqdm progress bar of chunks.
    backend : {"auto", "jax", "numpy"}
        Array namespace of :func:`~roughdiffuse.simulate.brdf` in each chunk: the compiled
        JAX path (all bounces about 1.5× NumPy in one process, where XLA uses every core;
        1.4× per core; a compilation of a few seconds per σ and process) or NumPy (one core
        per process: several workers). "auto": JAX in this process (``workers=1``, no
        scheduler), else NumPy (bench/RESULTS.md: on 2 cores two NumPy workers beat one JAX
        process). Both give the same values to 1e-9 relative, so a resumed run may switch.
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS} (got {backend!r})")
    if backend == "auto":
        backend = "jax" if workers == 1 and scheduler is None else "numpy"
    if albedo is None or not 0.0 <= float(albedo) <= 1.0:
        raise ValueError(f"albedo must be in [0, 1] (got {albedo!r})")
    bounces = check_bounces(bounces)
    settings = settings or Settings()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ValueError(f"workers must be an integer >= 1 (got {workers!r})")
    if not isinstance(rows_per_chunk, int) or rows_per_chunk < 1:
        raise ValueError(f"rows_per_chunk must be an integer >= 1 (got {rows_per_chunk!r})")
    axes = {
        "theta_i": _grid("theta_i", theta_i, 0.0, math.pi / 2),
        "theta_r": _grid("theta_r", theta_r, 0.0, math.pi / 2),
        "delta_phi": _grid("delta_phi", delta_phi, -math.inf, None),
        "sigma": _grid("sigma", sigma, 0.0, math.pi / 2),
    }
    path = Path(path)
    chunk_dir = path.with_name(path.name + ".chunks")
    manifest = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "package_version": _package_version(),
        "albedo": float(albedo),
        "bounces": bounces,
        "settings": asdict(settings),
        "rows_per_chunk": rows_per_chunk,
        **{k: v.tolist() for k, v in axes.items()},
    }
    _prepare_chunk_dir(chunk_dir, manifest)
    specs = []
    for s_idx, s in enumerate(axes["sigma"]):
        for r0 in range(0, axes["theta_i"].size, rows_per_chunk):
            rows = axes["theta_i"][r0 : r0 + rows_per_chunk]
            specs.append(
                {
                    "name": f"s{s_idx:03d}_r{r0:04d}.npz",
                    "sigma_index": s_idx,
                    "row": r0,
                    "sigma": float(s),
                    "theta_i": rows,
                    "theta_r": axes["theta_r"],
                    "delta_phi": axes["delta_phi"],
                    "albedo": float(albedo),
                    "bounces": bounces,
                    "settings": asdict(settings),
                    "backend": backend,
                }
            )
    todo = [s for s in specs if not _chunk_ok(chunk_dir / s["name"])]
    _run_chunks(todo, chunk_dir, workers, scheduler, progress, len(specs))
    shape = tuple(axes[k].size for k in ("theta_i", "theta_r", "delta_phi", "sigma"))
    values = np.empty(shape)
    kdiff = np.empty(shape)
    for s in specs:
        with np.load(chunk_dir / s["name"]) as z:
            rows = slice(s["row"], s["row"] + len(s["theta_i"]))
            values[rows, :, :, s["sigma_index"]] = z["values"]
            kdiff[rows, :, :, s["sigma_index"]] = z["k_difference"]
    table = GroundTruth(
        axes["theta_i"],
        axes["theta_r"],
        axes["delta_phi"],
        axes["sigma"],
        values,
        kdiff,
        float(albedo),
        bounces,
        settings,
    )
    table.save(path)
    shutil.rmtree(chunk_dir, ignore_errors=True)
    return table


def _prepare_chunk_dir(chunk_dir: Path, manifest: dict[str, Any]) -> None:
    mpath = chunk_dir / "manifest.json"
    if mpath.exists():
        try:
            old = json.loads(mpath.read_text())
        except (OSError, json.JSONDecodeError):
            old = None
        if old != json.loads(json.dumps(manifest)):
            raise ValueError(
                f"{chunk_dir} holds chunks computed with other settings or grids; refusing to "
                "mix them (delete that folder to start again)"
            )
        return
    chunk_dir.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=chunk_dir, suffix=".tmp")
    with os.fdopen(fd, "w") as fh:
        json.dump(manifest, fh, indent=1)
    os.replace(tmp, mpath)


def _chunk_ok(p: Path) -> bool:
    if not p.exists():
        return False
    try:
        with np.load(p) as z:
            return "values" in z.files and "k_difference" in z.files
    except (OSError, ValueError, zipfile.BadZipFile):
        p.unlink(missing_ok=True)  # a corrupt chunk is recomputed
        return False


def _write_chunk(chunk_dir: Path, spec: dict[str, Any], result) -> None:
    values, kdiff = result
    _atomic_savez(chunk_dir / spec["name"], values=values, k_difference=kdiff)


def _run_chunks(todo, chunk_dir: Path, workers: int, scheduler, progress: bool, total: int) -> None:
    from tqdm.auto import tqdm

    bar = tqdm(total=total, initial=total - len(todo), unit="chunk", disable=not progress)
    try:
        if not todo:
            return
        if workers == 1 and scheduler is None:
            for spec in todo:
                _write_chunk(chunk_dir, spec, compute_chunk(spec))
                bar.update()
            return
        from distributed import Client, LocalCluster, as_completed

        cluster = None
        if scheduler is None:
            cluster = LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
            )
            client = Client(cluster)
        else:
            client = Client(scheduler)
        try:
            futures = {client.submit(compute_chunk, s, pure=False): s for s in todo}
            for fut in as_completed(futures):
                _write_chunk(chunk_dir, futures[fut], fut.result())
                bar.update()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    finally:
        bar.close()
