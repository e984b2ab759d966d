"""Ground-truth tables: the V-cavity BRDF on a grid (θi, θr, Δφ, σ), in one ``.npz`` file.

Long tables are computed in chunks (one σ and a block of θi rows each). Every finished chunk
is written whole or not at all (:mod:`roughdiffuse.io.atomic`) into ``FILE.chunks/``, next to
a ``manifest.json`` holding every parameter and solver setting: an interrupted run resumes
where it stopped (no finished chunk recomputed, no half-written chunk kept), and a run with
different settings refuses to reuse the chunks. Chunks run in this process (``workers=1``),
on a local Dask cluster (``workers=N``), or on a Dask distributed cluster (``scheduler``).
When all chunks are done the table is assembled into ``FILE`` and the chunk folder removed.

Nothing is lost or adopted by mistake:

- a finished ``FILE`` is kept: a run with the same grid and settings returns it without
  computing anything, one with others is refused unless ``force=True`` (``--force``);
- each chunk records the digest of the table's settings and grid, its σ index and θi rows,
  and a SHA-256 checksum of its values; a chunk that cannot be read (a flipped bit), belongs
  to another table or another slice, has the wrong shape, fails its checksum or holds NaN is
  recomputed (with a warning naming it), never used;
- one run at a time: a run holds an exclusive lock on ``FILE.lock`` (which names its process),
  and a second run on the same table is refused with :class:`TableBusyError`.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import socket
import warnings
import zipfile
import zlib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.atomic import atomic_open, beside, check_output_path, write_text
from .cavity import Bounces, check_bounces
from .surface import Settings, brdf

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "GroundTruth",
    "TableBusyError",
    "compute_table",
    "load_table",
    "read_chunk",
]

FORMAT = "roughdiffuse.GroundTruth"
FORMAT_VERSION = 1


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
            **{k: v for k, v in self.meta.items() if k != "reused"},
            "format": FORMAT,
            "format_version": FORMAT_VERSION,
            "package_version": self.meta.get("package_version", "unknown"),
            "albedo": self.albedo,
            "bounces": self.bounces,
            "settings": asdict(self.settings),
            "units": "f_r in 1/sr; angles in radians",
        }
        arrays = {
            "theta_i": self.theta_i,
            "theta_r": self.theta_r,
            "delta_phi": self.delta_phi,
            "sigma": self.sigma,
            "values": self.values,
            "k_difference": self.k_difference,
            "meta": np.array(json.dumps(meta)),
        }
        with atomic_open(path, "wb") as fh:
            np.savez(fh, **arrays)
        return path

    @classmethod
    def load(cls, path: str | os.PathLike) -> GroundTruth:
        """Read a table written by :meth:`save` (ValueError if it is not one, or corrupt)."""
        return load_table(path)


def load_table(path: str | os.PathLike) -> GroundTruth:
    """Read a ground-truth table (see :class:`GroundTruth`)."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        meta = json.loads(str(data["meta"]))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, json.JSONDecodeError) as exc:
        raise ParameterError(
            f"{path}: not a readable roughdiffuse ground-truth table ({exc})"
        ) from None
    if meta.get("format") != FORMAT:
        raise ParameterError(f"{path}: not a roughdiffuse ground-truth table")
    if meta.get("format_version") != FORMAT_VERSION:
        raise ParameterError(
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
        raise ParameterError(f"{path}: corrupt ground-truth table ({exc})") from None
    if values.shape != shape or kdiff.shape != shape:
        raise ParameterError(
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
        raise ParameterError(f"{name} must be a non-empty 1-D array of finite angles (radians)")
    if np.any(a < lo) or (hi is not None and np.any(a > hi)):
        raise ParameterError(f"{name} must lie in [{lo:g}, {hi:g}] radians")
    values, counts = np.unique(a, return_counts=True)
    if np.any(counts > 1):
        raise ParameterError(
            f"{name} holds {values[counts > 1][0]:.6g} more than once: a table axis takes each "
            "value once"
        )
    return a


class TableBusyError(ParameterError):
    """Another run holds the lock of the table (a :class:`ParameterError`, a ``ValueError``:
    the command line prints it as one line, exit 2, as every refusal)."""


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
    force: bool = False,
    package_version: str = "unknown",
) -> GroundTruth:
    """Compute a :class:`GroundTruth` table into ``path``, resumably (module docstring).

    Parameters
    ----------
    path : path
        The ``.npz`` file to write; chunks go to ``path.chunks/`` until it is done. Its
        folder must exist.
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
    package_version : str
        The version of the code computing it, recorded in the table's metadata (the command
        line passes ``roughdiffuse.__version__``; this module does not import the package).
    force : bool
        Recompute and replace a finished table at ``path`` (and discard chunks of other
        settings in ``path.chunks/``). Without it a finished table with the same grid and
        settings is returned as it is (``meta["reused"]`` is True), and one with others is
        refused.

    Raises
    ------
    ValueError
        Bad parameters; ``path`` unusable (a folder, no such folder); ``path`` holding a
        finished table of other settings, or ``path.chunks/`` holding chunks of other
        settings, without ``force``.
    TableBusyError
        Another run is computing the same table (its lock file names its process id).
    """
    backend, bounces, settings, axes = _check_arguments(
        theta_i, theta_r, delta_phi, sigma, albedo, bounces, settings, rows_per_chunk, workers,
        scheduler, backend,
    )
    path = check_output_path(path, "table")
    chunk_dir = beside(path, ".chunks")
    if chunk_dir.exists() and not chunk_dir.is_dir():
        raise ParameterError(f"table {str(path)!r}: {str(chunk_dir)!r} is not a folder")
    identity = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "albedo": float(albedo),
        "bounces": bounces,
        "settings": asdict(settings),
        "rows_per_chunk": rows_per_chunk,
        **{k: v.tolist() for k, v in axes.items()},
    }
    key = _digest(json.dumps(identity, sort_keys=True).encode())
    manifest = {**identity, "package_version": package_version, "key": key}
    with _TableLock(path):
        if path.exists():
            kept = _finished_table(path, axes, float(albedo), bounces, settings, force)
            if kept is not None:
                return kept
        fresh = not chunk_dir.exists()
        try:
            return _compute_chunks(
                path, chunk_dir, manifest, axes, key, albedo, bounces, settings, workers,
                scheduler, progress, backend, force, rows_per_chunk, package_version,
            )
        except BaseException:
            # a run refused or failed before its first chunk leaves no folder that would
            # make the next run (with other settings) refuse
            if fresh:
                _remove_if_no_chunks(chunk_dir)
            raise


def _remove_if_no_chunks(chunk_dir: Path) -> None:
    """Remove ``chunk_dir`` if it holds no computed chunk (at most its manifest)."""
    try:
        entries = list(chunk_dir.iterdir())
    except OSError:
        return
    if all(e.name == "manifest.json" or e.name.startswith(".") for e in entries):
        shutil.rmtree(chunk_dir, ignore_errors=True)


def _compute_chunks(
    path,
    chunk_dir,
    manifest,
    axes,
    key,
    albedo,
    bounces,
    settings,
    workers,
    scheduler,
    progress,
    backend,
    force,
    rows_per_chunk,
    package_version,
):  # noqa: ANN001, ANN202
    """The body of :func:`compute_table` once the lock is held and no finished table is kept."""
    _prepare_chunk_dir(chunk_dir, manifest, force)
    common = {
        "key": key,
        "albedo": float(albedo),
        "bounces": bounces,
        "settings": asdict(settings),
        "backend": backend,
    }
    specs = _chunk_specs(axes, rows_per_chunk, common)
    todo = _chunks_to_do(specs, chunk_dir)
    _run_chunks(todo, chunk_dir, workers, scheduler, progress, len(specs))
    table = _assemble(specs, chunk_dir, axes, float(albedo), bounces, settings, package_version)
    table.save(path)
    shutil.rmtree(chunk_dir, ignore_errors=True)
    return table


def _check_arguments(
    theta_i: Any,
    theta_r: Any,
    delta_phi: Any,
    sigma: Any,
    albedo: float,
    bounces: Bounces,
    settings: Settings | None,
    rows_per_chunk: int,
    workers: int,
    scheduler: str | None,
    backend: str,
) -> tuple[str, Bounces, Settings, dict[str, np.ndarray]]:
    """Refuse bad arguments of :func:`compute_table`; the backend ("auto" resolved), bounces,
    settings and the four axes."""
    if backend not in BACKENDS:
        raise ParameterError(f"backend must be one of {BACKENDS} (got {backend!r})")
    if backend == "auto":
        backend = "jax" if workers == 1 and scheduler is None else "numpy"
    if albedo is None or not 0.0 <= float(albedo) <= 1.0:
        raise ParameterError(f"albedo must be in [0, 1] (got {albedo!r})")
    bounces = check_bounces(bounces)
    settings = settings or Settings()
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ParameterError(f"workers must be an integer >= 1 (got {workers!r})")
    if not isinstance(rows_per_chunk, int) or rows_per_chunk < 1:
        raise ParameterError(f"rows_per_chunk must be an integer >= 1 (got {rows_per_chunk!r})")
    axes = {
        "theta_i": _grid("theta_i", theta_i, 0.0, math.pi / 2),
        "theta_r": _grid("theta_r", theta_r, 0.0, math.pi / 2),
        "delta_phi": _grid("delta_phi", delta_phi, -math.inf, None),
        "sigma": _grid("sigma", sigma, 0.0, math.pi / 2),
    }
    return backend, bounces, settings, axes


def _chunk_specs(
    axes: dict[str, np.ndarray], rows_per_chunk: int, common: dict[str, Any]
) -> list[dict[str, Any]]:
    """One chunk per (σ, block of ``rows_per_chunk`` θi rows): its file name, place in the
    table and what it computes (``common``: key, albedo, bounces, settings, backend)."""
    specs = []
    for s_idx, s in enumerate(axes["sigma"]):
        for r0 in range(0, axes["theta_i"].size, rows_per_chunk):
            rows = axes["theta_i"][r0 : r0 + rows_per_chunk]
            specs.append(
                {
                    "name": f"s{s_idx:03d}_r{r0:04d}.npz",
                    "key": common["key"],
                    "sigma_index": s_idx,
                    "row": r0,
                    "sigma": float(s),
                    "theta_i": rows,
                    "theta_r": axes["theta_r"],
                    "delta_phi": axes["delta_phi"],
                    "albedo": common["albedo"],
                    "bounces": common["bounces"],
                    "settings": common["settings"],
                    "backend": common["backend"],
                }
            )
    return specs


def _chunks_to_do(specs: list[dict[str, Any]], chunk_dir: Path) -> list[dict[str, Any]]:
    """The chunks not on disk yet, and those on disk that fail their checks (removed, with a
    warning)."""
    todo = []
    for spec in specs:
        p = chunk_dir / spec["name"]
        if not p.exists():
            todo.append(spec)
            continue
        try:
            read_chunk(p, spec)
        except ValueError as exc:
            warnings.warn(f"{exc}; recomputing it", RuntimeWarning, stacklevel=3)
            p.unlink(missing_ok=True)
            todo.append(spec)
    return todo


def _assemble(
    specs: list[dict[str, Any]],
    chunk_dir: Path,
    axes: dict[str, np.ndarray],
    albedo: float,
    bounces: Bounces,
    settings: Settings,
    package_version: str,
) -> GroundTruth:
    """The table from its chunks, each checked again as it is read (never adopted blindly)."""
    shape = tuple(axes[k].size for k in ("theta_i", "theta_r", "delta_phi", "sigma"))
    values = np.empty(shape)
    kdiff = np.empty(shape)
    for spec in specs:
        v, d = read_chunk(chunk_dir / spec["name"], spec)
        rows = slice(spec["row"], spec["row"] + len(spec["theta_i"]))
        values[rows, :, :, spec["sigma_index"]] = v
        kdiff[rows, :, :, spec["sigma_index"]] = d
    return GroundTruth(
        axes["theta_i"],
        axes["theta_r"],
        axes["delta_phi"],
        axes["sigma"],
        values,
        kdiff,
        albedo,
        bounces,
        settings,
        {"package_version": package_version},
    )


def _digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def _finished_table(
    path: Path,
    axes: dict[str, np.ndarray],
    albedo: float,
    bounces: Bounces,
    settings: Settings,
    force: bool,
) -> GroundTruth | None:
    """The finished table at ``path`` if it has these settings; None if it is to be replaced."""
    try:
        old = load_table(path)
    except ValueError as exc:
        if force:
            return None
        raise ParameterError(
            f"table {str(path)!r} exists and is not a readable table ({exc}); "
            "use --force (force=True) to replace it"
        ) from None
    differ = [
        name
        for name, same in (
            ("albedo", old.albedo == albedo),
            ("bounces", old.bounces == bounces),
            ("settings", old.settings == settings),
            *((k, np.array_equal(getattr(old, k), v)) for k, v in axes.items()),
        )
        if not same
    ]
    if force:
        return None
    if differ:
        raise ParameterError(
            f"table {str(path)!r} already holds a finished table with another "
            f"{', '.join(differ)}; use --force (force=True) to replace it"
        )
    old.meta["reused"] = True
    return old


def _prepare_chunk_dir(chunk_dir: Path, manifest: dict[str, Any], force: bool) -> None:
    mpath = chunk_dir / "manifest.json"
    if mpath.exists():
        try:
            old = json.loads(mpath.read_text())
        except (OSError, json.JSONDecodeError, UnicodeDecodeError):
            old = None
        if isinstance(old, dict) and old.get("key") == manifest["key"]:
            return
        if not force and not any(p.suffix == ".npz" for p in chunk_dir.iterdir()):
            force = True  # only a manifest, no chunk: nothing is lost by starting anew
        if not force:
            raise ParameterError(
                f"{chunk_dir} holds chunks computed with other settings or grids; refusing to "
                "mix them (use --force (force=True) to discard them, or delete that folder)"
            )
        shutil.rmtree(chunk_dir)
    chunk_dir.mkdir(exist_ok=True)
    # Chunks found without a manifest (e.g. left by a crashed run) are each checked against
    # their own identity record before use, so writing the manifest now adopts none of them.
    write_text(mpath, json.dumps(manifest, indent=1))


def _chunk_checksum(values: np.ndarray, kdiff: np.ndarray) -> str:
    return _digest(
        np.ascontiguousarray(values, "<f8").tobytes() + np.ascontiguousarray(kdiff, "<f8").tobytes()
    )


def _chunk_identity(spec: dict[str, Any]) -> dict[str, Any]:
    return {
        "key": spec["key"],
        "sigma_index": spec["sigma_index"],
        "sigma": spec["sigma"],
        "row": spec["row"],
        "rows": len(spec["theta_i"]),
    }


def read_chunk(path: Path, spec: dict[str, Any]) -> tuple[np.ndarray, np.ndarray]:
    """The values and K differences of a finished chunk, checked against ``spec``.

    A chunk records its identity (the digest of the table's settings and grid, its σ index
    and its θi rows) and a SHA-256 checksum of its values.

    Raises
    ------
    ValueError
        Naming the file, if it cannot be read (a flipped bit: bad CRC), records another
        table or another slice of the grid, has the wrong shape, fails its checksum, or
        holds non-finite values.
    """
    try:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            values = np.asarray(z["values"], dtype=np.float64)
            kdiff = np.asarray(z["k_difference"], dtype=np.float64)
    except KeyError as exc:
        raise ParameterError(
            f"chunk {path}: no {exc} record (not written by this version)"
        ) from None
    except (
        OSError,
        ValueError,
        EOFError,
        zipfile.BadZipFile,
        zlib.error,
        json.JSONDecodeError,
    ) as exc:
        raise ParameterError(f"chunk {path} is unreadable ({exc})") from None
    want = _chunk_identity(spec)
    got = {k: meta.get(k) for k in want} if isinstance(meta, dict) else {}
    if got.get("key") != want["key"]:
        raise ParameterError(f"chunk {path} belongs to a table with other settings or grid")
    if got != want:
        raise ParameterError(
            f"chunk {path} holds another slice of the grid "
            f"(σ index {got.get('sigma_index')}, rows from {got.get('row')})"
        )
    shape = (len(spec["theta_i"]), len(spec["theta_r"]), len(spec["delta_phi"]))
    if values.shape != shape or kdiff.shape != shape:
        raise ParameterError(f"chunk {path} has shape {values.shape}, expected {shape}")
    if meta.get("sha256") != _chunk_checksum(values, kdiff):
        raise ParameterError(f"chunk {path} fails its checksum")
    if not (np.all(np.isfinite(values)) and np.all(np.isfinite(kdiff))):
        raise ParameterError(f"chunk {path} holds non-finite values")
    return values, kdiff


def _write_chunk(chunk_dir: Path, spec: dict[str, Any], result) -> None:
    values, kdiff = (np.asarray(a, dtype=np.float64) for a in result)
    meta = {**_chunk_identity(spec), "sha256": _chunk_checksum(values, kdiff)}
    with atomic_open(chunk_dir / spec["name"], "wb") as fh:
        np.savez(fh, values=values, k_difference=kdiff, meta=np.array(json.dumps(meta)))


class _TableLock:
    """An exclusive ``fcntl.flock`` on ``FILE.lock`` for the duration of a run.

    The lock file records the process id and host of its holder, which a refused run names.
    The kernel releases the lock when its holder dies, however it dies, so a lock file left
    by a killed run does not block the next one.
    """

    def __init__(self, path: Path) -> None:
        self.table = path
        self.path = beside(path, ".lock")
        self.fd: int | None = None

    def __enter__(self) -> _TableLock:
        try:
            import fcntl
        except ImportError:  # pragma: no cover - not POSIX: no lock
            return self
        while True:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.read(fd, 200).decode("utf-8", "replace").strip() or "unknown"
                os.close(fd)
                raise TableBusyError(
                    f"table {str(self.table)!r} is being computed by another "
                    f"run (process {holder}, lock file {self.path}); wait for it to finish"
                ) from None
            # The holder before us may have removed the file after we opened it: lock the
            # file that is at the path now.
            try:
                same = os.fstat(fd).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)
        try:
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()} on {socket.gethostname()}\n".encode())
        except OSError:  # e.g. a full disk: leave no empty lock file behind
            self.path.unlink(missing_ok=True)
            os.close(fd)
            raise
        self.fd = fd
        return self

    def __exit__(self, *exc: Any) -> None:
        if self.fd is not None:
            self.path.unlink(missing_ok=True)
            os.close(self.fd)
            self.fd = None


LOCAL_WORKER_CONFIG: dict[str, Any] = {
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
    "distributed.worker.profile.enabled": False,
}
"""Dask settings of the local cluster (``workers > 1``). Dask's nanny sets
``MALLOC_TRIM_THRESHOLD_=65536`` in its workers, so glibc hands every freed NumPy temporary
back to the kernel and faults it in again: the solver then spends about as long in the kernel
as in NumPy (about half the values per CPU second, bench/RESULTS.md); None leaves glibc's
default. The statistical profiler, sampling the computing thread, costs a noticeable part of
each worker's CPU time (off here). Workers of a ``scheduler`` of your own
take their settings from their own Dask configuration (set the same two keys there)."""


def _run_chunks(todo, chunk_dir: Path, workers: int, scheduler, progress: bool, total: int) -> None:
    from ..progress import progress as progress_bar

    bar = progress_bar(
        total, "V-cavity table", unit="chunk", enabled=progress, initial=total - len(todo)
    )
    try:
        if not todo:
            return
        if workers == 1 and scheduler is None:
            for spec in todo:
                _write_chunk(chunk_dir, spec, compute_chunk(spec))
                bar.update()
            return
        import dask
        from distributed import Client, LocalCluster, as_completed

        cluster = None
        if scheduler is None:
            with dask.config.set(LOCAL_WORKER_CONFIG):
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
