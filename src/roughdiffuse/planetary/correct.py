"""Photometric normalisation of I/F images to a reference geometry, as ISIS's ``photomet``.

Four methods, transcribed from USGS ISIS3 (``isis/src/base/objs/Albedo/Albedo.cpp``,
``Mixed/Mixed.cpp``, ``Topo/Topo.cpp`` and ``Shade/Shade.cpp``, ``NormModelAlgorithm``), with
P(g, i, e) the model's I/F for unit albedo parameters as given and P_ref its value at the
reference geometry (g_ref, i_ref, e_ref):

* ``"albedo"``: I/F × P_ref/P — the I/F the surface would have at the reference geometry;
  pixels where P_ref > 30 P (ISIS's ``Thresh``) are masked.
* ``"mixed"``: near the limb and terminator the topographic shading dominates and is kept,
  in between the albedo is normalised (ISIS's mixed normalisation, McEwen 1991):
  A = I/F × a_ref/a + ρ̄ (P_ref − P a_ref/a), with a = √(P² + (P_m P′/P′_m)²),
  a_ref the same at the reference, P′ the topographic derivative (``PhotoModel::PhtTopder``:
  the change of P with a 0.04° tilt of the surface, by central differences in two directions),
  P_m and P′_m at the match geometry (g_m, i_m, e_m) and ρ̄ = albedo/P_ref (ISIS ``Albedo``,
  default 1); masked where a > 30 a_ref.
* ``"topo"``: the topographic shading normalised, for a DEM-free relief image
  (ISIS's Topo): A = ρ̄ [I/F × P P′_ref/P′ + P_ref − P P′_ref/P′], ρ̄ = albedo/P(0, 0, 0)
  (surge removed); masked where P P′_ref > 30 P′. ISIS's Topo takes the reference
  (g, i, e) = (i_ref, i_ref, 0).
* ``"shade"``: a shaded-relief image from the model alone, the I/F ignored (ISIS's Shade):
  A = albedo × P/P_ref, P_ref with the surge removed; ISIS's reference is (i_ref, i_ref, 0).

Reference geometry, as ISIS's defaults: i_ref = e_ref = g_ref = 0; there the opposition-surge
amplitudes (B0, B_S0, B_C0) are set to 0, as ISIS's ``ZeroB0Standard = TRUE`` (default) does,
so the normalised value is the normal albedo without the surge. Mixed's match geometry
defaults to i_m = g_m = 45°, e_m = 0 (ISIS's default 0 leaves the topographic derivative
0 and the method undefined). Pixels with i or e beyond their limits (default 90°, as
photomet's; 85° is the cautious choice near the limb and terminator), and NaN (NoData)
pixels, are NaN in the output. A pixel whose phase is outside [|i − e|, i + e] is no geometry:
refused (the check :func:`~roughdiffuse.frames.photometric_to_local` makes for
``photometry fit`` too).
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..frames import photometric_to_local

__all__ = [
    "METHODS",
    "REFERENCE",
    "normalize",
    "PixelModel",
    "phototopder",
    "read_plane",
    "write_plane",
]

METHODS = ("albedo", "mixed", "topo", "shade")
REFERENCE = (0.0, 0.0, 0.0)
"""ISIS's default reference geometry (phase, incidence, emission), radians."""
MATCH = (math.radians(45.0), math.radians(45.0), 0.0)
THRESH = 30.0
SURGE_AMPLITUDES = ("b0", "bs0", "bc0")
_EPS_DEG = 0.04  # PhtTopder's tilt
CHUNK = 1 << 18
"""Pixels normalised together: an image of more is done chunk by chunk, a progress bar
counting the chunks."""


def _psurf(model: Any, phase: Any, inc: Any, ema: Any) -> np.ndarray:
    """The model's I/F at (g, i, e) radians, 0 where i >= 90° (as ISIS's functions)."""
    from ..models.photometry import radiance_factor

    i = np.clip(np.asarray(inc, dtype=np.float64), 0.0, math.pi / 2)
    e = np.clip(np.asarray(ema, dtype=np.float64), 0.0, math.pi / 2)
    g = np.clip(np.asarray(phase, dtype=np.float64), np.abs(i - e), i + e)
    return np.asarray(radiance_factor(model, i, e, g))


@dataclasses.dataclass(frozen=True)
class PixelModel:
    """A model whose parameters ``params`` are per-pixel arrays (a parameter map's values for
    the pixels evaluated), the others its own: evaluated through its ``kernel``, which takes
    parameters as arrays, with the horizon test and clipping of ``Model.brdf_cosines``."""

    model: Any
    params: Mapping[str, np.ndarray]

    def take(self, index: Any) -> PixelModel:
        return PixelModel(self.model, {k: v[index] for k, v in self.params.items()})

    def brdf_cosines(self, mu_i: Any, mu_o: Any, cos_io: Any) -> np.ndarray:
        p = dict(self.model.parameter_arrays(np, np.float64))
        p.update(self.params)
        above = (np.asarray(mu_i) >= 0) & (np.asarray(mu_o) >= 0)
        f = self.model.kernel(
            np, np.clip(mu_i, 0.0, 1.0), np.clip(mu_o, 0.0, 1.0), np.clip(cos_io, -1.0, 1.0), **p
        )
        return np.where(above, f, 0.0)


class _PerSlice:
    """A function of a slice of pixels returning the normalisation for them."""

    def __init__(self, make: Any) -> None:
        self.make = make

    def __call__(self, part: slice) -> Any:
        return self.make(part)


def reference_model(model: Any) -> Any:
    """``model`` with its opposition-surge amplitudes at 0 (ISIS's standard conditions); for
    a :class:`PixelModel`, in its maps too."""
    if isinstance(model, PixelModel):
        maps = {
            k: (np.zeros_like(v) if k in SURGE_AMPLITUDES else v) for k, v in model.params.items()
        }
        return PixelModel(reference_model(model.model), maps)
    names = {f.name for f in dataclasses.fields(model)}
    zero = {k: 0.0 for k in SURGE_AMPLITUDES if k in names}
    return dataclasses.replace(model, **zero) if zero else model


def phototopder(model: Any, phase: Any, inc: Any, ema: Any) -> np.ndarray:
    """ISIS's ``PhotoModel::PhtTopder``: |∇P| per degree of tilt of the surface, by central
    differences over a 0.04° tilt in two directions (angles in radians)."""
    g, i, e = (np.asarray(a, dtype=np.float64) for a in (phase, inc, ema))
    xi, zi = np.sin(i), np.cos(i)
    s = np.sin(i) * np.sin(e)
    cphi = np.where(
        (i == 0) | (e == 0), 1.0, (np.cos(g) - np.cos(i) * np.cos(e)) / np.where(s == 0, 1.0, s)
    )
    phi = np.arccos(np.clip(cphi, -1.0, 1.0))
    xe, ye, ze = cphi * np.sin(e), np.sin(phi) * np.sin(e), np.cos(e)
    epsh = math.radians(_EPS_DEG * 0.5)
    xy, z = math.sin(epsh), math.cos(epsh)

    def acos(c: np.ndarray) -> np.ndarray:
        return np.arccos(np.clip(c, -1.0, 1.0))

    inc1, ema1 = acos(xy * xi + z * zi), acos(xy * xe + z * ze)
    inc2, ema2 = acos(-xy * xi + z * zi), acos(-xy * xe + z * ze)
    inc3, ema3 = acos(z * zi), acos(xy * ye + z * ze)
    inc4, ema4 = acos(z * zi), acos(-xy * ye + z * ze)
    d1 = (_psurf(model, g, inc1, ema1) - _psurf(model, g, inc2, ema2)) / _EPS_DEG
    d2 = (_psurf(model, g, inc3, ema3) - _psurf(model, g, inc4, ema4)) / _EPS_DEG
    return np.sqrt(np.maximum(1e-30, d1 * d1 + d2 * d2))


def normalize(
    iof: Any,
    incidence: Any,
    emission: Any,
    phase: Any,
    model: Any,
    *,
    method: str = "albedo",
    reference: Sequence[float] = REFERENCE,
    match: Sequence[float] = MATCH,
    albedo: float = 1.0,
    max_incidence: float = math.radians(90.0),
    max_emission: float = math.radians(90.0),
    thresh: float = THRESH,
    progress: bool | None = False,
    params: Mapping[str, Any] | None = None,
) -> np.ndarray:
    """Normalise an I/F image to the reference geometry (see the module).

    Parameters
    ----------
    iof : array (H, W)
        The image; NaN is NoData and stays NaN.
    incidence, emission, phase : array (H, W) or scalar
        Backplanes, radians (NaN: off the body).
    model : Model
        The photometric model (a registry model; :data:`.disk.PHOTOMETRIC_MODELS`).
    method : {"albedo", "mixed", "topo", "shade"}
    reference, match : (phase, incidence, emission)
        Radians.
    albedo : float
        Mixed, topo and shade: ISIS's ``Albedo`` (the normalised image's brightness scale).
    max_incidence, max_emission : float
        Pixels beyond are masked (radians); default 90°, as ISIS's ``photomet``
        (``MAXINCIDENCE``, ``MAXEMISSION``); 85° leaves out the grazing pixels whose
        correction divides by a small I/F.
    thresh : float
        ISIS's ``Thresh``.
    progress : bool or None
        A progress bar on standard error counting chunks of :data:`CHUNK` pixels (an image
        of more than one); None: only when standard error is a terminal. Default False.
    params : mapping of str to array (H, W), optional
        Parameter maps: per-pixel values of some of the model's parameters (in the model's
        units: radians for angles), replacing the model's own values; a NaN is NoData.

    Returns
    -------
    array (H, W)
        The normalised image (NaN where masked).
    """
    if method not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)} (got {method!r})")
    dn = np.asarray(iof, dtype=np.float64)
    i, e, g = (
        np.broadcast_to(np.asarray(a, dtype=np.float64), dn.shape)
        for a in (incidence, emission, phase)
    )
    ok = np.isfinite(dn) & np.isfinite(i) & np.isfinite(e) & np.isfinite(g)
    ok &= (i <= max_incidence) & (e <= max_emission)
    params = {
        k: np.broadcast_to(np.asarray(v, np.float64), dn.shape) for k, v in (params or {}).items()
    }
    for v in params.values():
        ok &= np.isfinite(v)  # a parameter map's NoData: the pixel's too
    out = np.full(dn.shape, np.nan)
    if not ok.any():
        return out
    # the one check of a geometry (photometry fit's too): g within [|i − e|, i + e]
    photometric_to_local(i[ok], e[ok], g[ok])
    if params:
        pixels = PixelModel(model, {k: np.asarray(v, np.float64)[ok] for k, v in params.items()})
        correct: Any = _PerSlice(
            lambda part: _corrector(pixels.take(part), method, reference, match, albedo, thresh)
        )
    else:
        correct = _corrector(model, method, reference, match, albedo, thresh)
    out[ok] = _in_chunks(correct, dn[ok], g[ok], i[ok], e[ok], progress)
    return out


def _corrector(
    model: Any,
    method: str,
    reference: Sequence[float],
    match: Sequence[float],
    albedo: float,
    thresh: float,
) -> Any:
    """The normalisation of ``method`` as a function of (I/F, g, i, e) arrays of pixels, its
    constants (the reference and match geometries' values) computed once."""
    ref = reference_model(model)
    p_ref = _constant(_psurf(ref, *reference))
    if method == "albedo":

        def albedo_method(dn: Any, g: Any, i: Any, e: Any) -> np.ndarray:
            psurf = _psurf(model, g, i, e)
            good = p_ref <= psurf * thresh
            res = np.full(psurf.shape, np.nan)
            res[good] = dn[good] * np.broadcast_to(p_ref, psurf.shape)[good] / psurf[good]
            return res

        return albedo_method
    if np.any(p_ref == 0.0):
        raise ParameterError("the model's I/F at the reference geometry is 0")
    if method == "shade":
        rho = albedo / p_ref

        def shade_method(dn: Any, g: Any, i: Any, e: Any) -> np.ndarray:
            return rho * _psurf(model, g, i, e)

        return shade_method
    if method == "topo":
        psurf0 = _constant(_psurf(ref, 0.0, 0.0, 0.0))
        if np.any(psurf0 == 0.0):
            raise ParameterError("the model's I/F at i = e = g = 0 is 0")
        rhobar0 = albedo / psurf0
        pp_ref0 = _constant(phototopder(ref, *reference))

        def topo_method(dn: Any, g: Any, i: Any, e: Any) -> np.ndarray:
            psurf = _psurf(model, g, i, e)
            pprime = phototopder(model, g, i, e)
            ratio = psurf * pp_ref0 / pprime
            res = dn * rhobar0 * ratio + rhobar0 * p_ref - rhobar0 * ratio
            res[psurf * pp_ref0 > pprime * thresh] = np.nan
            return res

        return topo_method
    rhobar = albedo / p_ref
    p_match = _constant(_psurf(ref, *match))
    pp_ref = _constant(phototopder(ref, *reference))
    pp_match = np.maximum(1e-30, _constant(phototopder(ref, *match)))
    anum = np.sqrt(p_ref**2 + (p_match * pp_ref / pp_match) ** 2)

    def mixed_method(dn: Any, g: Any, i: Any, e: Any) -> np.ndarray:
        psurf = _psurf(model, g, i, e)
        pprime = phototopder(model, g, i, e)
        aden = np.sqrt(np.maximum(1e-30, psurf**2 + (p_match * pprime / pp_match) ** 2))
        res = dn * anum / aden + rhobar * (p_ref - anum / aden * psurf)
        res[aden > anum * thresh] = np.nan
        return res

    return mixed_method


def _constant(value: Any) -> Any:
    """A value at a fixed geometry: a float for a model, an array of one per pixel for a
    :class:`PixelModel`."""
    arr = np.asarray(value, dtype=np.float64)
    return float(arr) if arr.ndim == 0 else arr


def _in_chunks(
    correct: Any, dn: np.ndarray, g: np.ndarray, i: np.ndarray, e: np.ndarray, progress: bool | None
) -> np.ndarray:
    """``correct`` applied to :data:`CHUNK` pixels at a time, with a progress bar; ``correct``
    is the normalisation, or a function of a slice of pixels that returns it (a
    :class:`PixelModel`'s, whose parameters are sliced too)."""
    from ..progress import progress as bar_of

    starts = range(0, dn.size, CHUNK)
    enabled = False if len(starts) == 1 or progress is False else progress
    res = np.empty(dn.shape)
    with bar_of(len(starts), "photometry correct", unit="chunk", enabled=enabled) as bar:
        for s0 in starts:
            part = slice(s0, s0 + CHUNK)
            fn = correct(part) if isinstance(correct, _PerSlice) else correct
            res[part] = fn(dn[part], g[part], i[part], e[part])
            bar.update(1)
    return res


# ------------------------------------------------------------------------- files
def read_plane(path: str | os.PathLike[str], nodata: float | None = None) -> np.ndarray:
    """A whole image plane (H, W) as float64, NaN where it holds no data (any format of
    :mod:`.rasters`; values equal to ``nodata`` are NoData too). For images that fit in
    memory; :mod:`.chunked` reads large ones by window."""
    from .rasters import open_plane

    return open_plane(path, nodata=nodata).read_all()


def write_plane(path: str | os.PathLike[str], image: np.ndarray) -> Path:
    """Write one plane (float32, NaN for NoData) atomically, in the format its name says."""
    from .rasters import encode, format_of, write_blocks

    img = np.asarray(image, dtype=np.float64)
    if img.ndim != 2:
        raise ParameterError(f"image must have shape (H, W) (got {img.shape})")
    fmt = format_of(path)
    kind = np.where(np.isfinite(img), 0, 1).astype(np.uint8)
    whole = (slice(0, img.shape[0]), slice(0, img.shape[1]), encode(img, kind, fmt))
    return write_blocks(path, img.shape, [whole], fmt=fmt)
