"""Sample data that ships with the package, so the documentation's snippets run as written.

Every file is made from a known model by ``scripts/make_sample_data.py`` (run it to remake
them; the truth is recorded in ``sphere.json`` and in each file's header):

``samples.csv``
    BRDF samples of Oren–Nayar (full), ρ = 0.7, σ = 0.35 rad, at θi, θr ∈ {0°, 10°, …, 80°}
    and Δφ ∈ {0°, 90°, 180°}, each multiplied by 1 + 0.01 N(0, 1) (seed 0); the format of
    :func:`roughdiffuse.fit.read_csv`.
``sphere.npy``, ``sphere_normals.npy``, ``sphere.json``
    A 64 × 64 linear radiance image of a sphere of Oren–Nayar (full), ρ = 0.6, σ = 0.5 rad,
    lit by a distant light at θ = 30°, φ = 0 (E0 = 1), one sample per pixel at its centre;
    its normal map (zero vectors off the sphere); the light and the model in JSON.
``lights.json``
    Eight distant lights on a 35° ring around the view axis, in the format
    ``roughdiffuse stereo --lights`` and ``roughdiffuse render --lights`` read
    (:func:`roughdiffuse.stereo.default_lights`).
``oren-nayar.binary``
    A MERL-format file (Matusik et al. 2003) tabulating Oren–Nayar (full), ρ = (0.6, 0.45,
    0.3), σ = 0.3 rad. A MERL file is 33 MB and the reader takes only full files, so it is not
    shipped: :func:`path` writes it on first use into :func:`cache_dir` (about 10 s) and
    returns that path afterwards.

``coat_interface.npz``, ``coat_lobe.npz``
    A model's tables, not sample data, so not listed by :func:`names`: the rough coat's
    reflectance from above and below by the layered walk's exact interface, and its
    reflection by two or more facet events resolved in direction, to which
    :class:`~roughdiffuse.models.coated.Coated`'s multiple scattering is fitted (the
    latter holds the fitted lobe's coefficients too); made by
    ``scripts/coat_interface_tables.py`` and ``scripts/coat_lobe_tables.py``.

Real measured BRDFs (the MERL database, "A data-driven reflectance model", Matusik, Pfister,
Brand and McMillan, SIGGRAPH 2003) are not redistributed here: see the documentation's
"Getting started" page for where they come from.

>>> from roughdiffuse import data
>>> data.names()  # doctest: +NORMALIZE_WHITESPACE
['lights.json', 'oren-nayar.binary', 'samples.csv', 'sphere.json', 'sphere.npy',
 'sphere_normals.npy']
>>> data.path("samples.csv").name
'samples.csv'
"""

from __future__ import annotations

import os
from pathlib import Path

from .._validate import ParameterError

__all__ = ["MERL_MODEL", "cache_dir", "names", "path"]

_HERE = Path(__file__).resolve().parent
_SHIPPED = ("lights.json", "samples.csv", "sphere.json", "sphere.npy", "sphere_normals.npy")
_GENERATED = ("oren-nayar.binary",)

MERL_MODEL = "OrenNayar(albedo=(0.6, 0.45, 0.3), sigma=0.3, variant='full')"
"""The model ``oren-nayar.binary`` tabulates (its ``repr``)."""


def names() -> list[str]:
    """The names :func:`path` accepts, sorted."""
    return sorted(_SHIPPED + _GENERATED)


def cache_dir() -> Path:
    """Where generated sample files go: ``$ROUGHDIFFUSE_DATA_DIR``, else
    ``$XDG_CACHE_HOME/roughdiffuse/data`` (``~/.cache/roughdiffuse/data``).

    Raises
    ------
    ValueError
        If that path, or the nearest of its parents that exists, is not a folder.
    """
    env = os.environ.get("ROUGHDIFFUSE_DATA_DIR")
    if env:
        folder, what = Path(env), "ROUGHDIFFUSE_DATA_DIR"
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        folder, what = Path(base) / "roughdiffuse" / "data", "the data cache"
    for parent in (folder, *folder.parents):
        if parent.exists():
            if not parent.is_dir():
                raise ParameterError(f"{what} {str(folder)!r}: {str(parent)!r} is not a folder")
            break
    return folder


def _make_merl(target: Path) -> None:
    from ..fit.merl import MERLBRDF, write_merl
    from ..models import OrenNayar

    model = OrenNayar(albedo=(0.6, 0.45, 0.3), sigma=0.3, variant="full")
    target.parent.mkdir(parents=True, exist_ok=True)
    write_merl(target, MERLBRDF.from_model(model))  # atomic: temporary file, then rename


def path(name: str) -> Path:
    """The path of the sample file ``name`` (one of :func:`names`).

    Raises
    ------
    ValueError
        If ``name`` is not a sample file, naming the accepted ones, or if a generated one
        cannot be written into the cache folder (naming it and ``ROUGHDIFFUSE_DATA_DIR``).
    """
    if name in _SHIPPED:
        return _HERE / name
    if name in _GENERATED:
        target = cache_dir() / name
        if not target.is_file():
            try:
                _make_merl(target)
            except OSError as exc:  # an unwritable cache: one line naming it, not a traceback
                raise ParameterError(
                    f"cannot write the sample file {name} into {str(target.parent)!r} "
                    f"({exc.strerror or exc}); set ROUGHDIFFUSE_DATA_DIR to a folder you can "
                    "write"
                ) from None
        return target
    raise ParameterError(f"name must be one of {', '.join(names())} (got {name!r})")
