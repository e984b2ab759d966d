"""Measurements to fit: reflectance values with their geometry, as local cosines.

Every data source (BRDF samples from a table, a MERL file, an image with known normals)
becomes one :class:`Measurements` object: the three local cosines of each sample
(μi = cos θi, μo = cos θr, cos_io = wi·wo, see :mod:`roughdiffuse.frames`), the measured
value, and the factor that turns a BRDF into that value (1 for BRDF samples, E0 cos θi for
radiance, since L = f_r E0 cos θi). The fitter compares ``model.brdf_cosines(...) * scale``
with ``value``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from .._validate import ParameterError
from ..frames import angles_to_cosines, check_cosines, local_cosines, world_cosines

__all__ = ["Measurements"]

Kind = Literal["brdf", "radiance"]


def _as_float(name: str, x: Any) -> np.ndarray:
    arr = np.asarray(x, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        bad = int(np.sum(~np.isfinite(arr)))
        raise ParameterError(f"{name} must be finite ({bad} entries are NaN or infinite)")
    return arr


def _flat_value(value: Any, shape: tuple[int, ...]) -> Any:
    """Values given on the grid of the angles, (*shape) or (*shape, C), as (N,) or (N, C)."""
    val = np.asarray(value)
    if len(shape) != 1 and val.shape == shape:
        return val.reshape(-1)
    if len(shape) != 1 and val.ndim == len(shape) + 1 and val.shape[:-1] == shape:
        return val.reshape(-1, val.shape[-1])
    return value


@dataclass(frozen=True)
class Measurements:
    """Reflectance samples and their geometry.

    Parameters
    ----------
    mu_i, mu_o, cos_io : array (N,)
        cos θi, cos θr and wi·wo of each sample (local frame, z = normal); μ in [0, 1].
    value : array (N,) or (N, C)
        Measured BRDF (1/sr) or radiance, one column per colour channel.
    scale : array (N,)
        value = f_r · scale for a perfect model: 1 for BRDF samples, E0 cos θi for radiance.
    kind : {"brdf", "radiance"}
        What ``value`` holds.
    source : str
        Where the data came from (shown in reports).
    image_shape : tuple of int, optional
        For image data, the (H, W) shape of the image the samples came from ...
    pixels : array (N,) of int, optional
        ... and the flat pixel index of each sample (for residual images).
    """

    mu_i: np.ndarray
    mu_o: np.ndarray
    cos_io: np.ndarray
    value: np.ndarray
    scale: np.ndarray
    kind: Kind = "brdf"
    source: str = ""
    image_shape: tuple[int, int] | None = None
    pixels: np.ndarray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        names = ("mu_i", "mu_o", "cos_io", "value", "scale")
        arrs = {n: _as_float(n, getattr(self, n)) for n in names}
        for n, a in arrs.items():
            object.__setattr__(self, n, a)
        n = arrs["mu_i"].shape
        if len(n) != 1:
            raise ParameterError(f"mu_i must be a 1-D array (got shape {n})")
        for name in ("mu_o", "cos_io", "scale"):
            if arrs[name].shape != n:
                raise ParameterError(
                    f"{name} must have shape {n} like mu_i (got {arrs[name].shape})"
                )
        v = arrs["value"]
        if v.ndim not in (1, 2) or v.shape[0] != n[0]:
            raise ParameterError(f"value must have shape ({n[0]},) or ({n[0]}, C) (got {v.shape})")
        if n[0] == 0:
            raise ParameterError("measurements must contain at least one sample (got 0)")
        for name in ("mu_i", "mu_o"):
            a = arrs[name]
            if np.any(a < -1e-12) or np.any(a > 1 + 1e-12):
                raise ParameterError(f"{name} must be in [0, 1] (samples above the horizon)")
        check_cosines(arrs["mu_i"], arrs["mu_o"], arrs["cos_io"])
        if self.kind not in ("brdf", "radiance"):
            raise ParameterError(f"kind must be 'brdf' or 'radiance' (got {self.kind!r})")

    # ----------------------------------------------------------------- constructors
    @classmethod
    def from_angles(
        cls,
        theta_i: Any,
        theta_r: Any,
        delta_phi: Any,
        value: Any,
        *,
        irradiance: Any = None,
        source: str = "",
    ) -> Measurements:
        """Samples at the papers' angles (radians): θi, θr in [0, π/2], Δφ = φr − φi.

        ``value`` is a BRDF (1/sr) when ``irradiance`` is None, else a radiance measured under
        that irradiance E0 (scalar or per sample).
        """
        ti, tr, dp = (
            _as_float(n, a)
            for n, a in zip(
                ("theta_i", "theta_r", "delta_phi"), (theta_i, theta_r, delta_phi), strict=True
            )
        )
        for name, th in (("theta_i", ti), ("theta_r", tr)):
            if np.any(th < 0) or np.any(th > math.pi / 2):
                raise ParameterError(f"{name} must be in [0, π/2] radians")
        ti, tr, dp = np.broadcast_arrays(ti, tr, dp)
        mu_i, mu_o, cos_io = angles_to_cosines(np, ti.ravel(), tr.ravel(), dp.ravel())
        value = _flat_value(value, ti.shape)
        if irradiance is not None and np.ndim(irradiance) == ti.ndim and ti.ndim > 1:
            irradiance = np.ravel(irradiance)
        return cls._with_value(mu_i, mu_o, cos_io, value, irradiance, source)

    @classmethod
    def from_directions(
        cls, wi: Any, wo: Any, value: Any, *, irradiance: Any = None, source: str = ""
    ) -> Measurements:
        """Samples at local-frame directions ``wi`` (to the light), ``wo`` (to the viewer)."""
        wi, wo = np.broadcast_arrays(_as_float("wi", wi), _as_float("wo", wo))
        mu_i, mu_o, cos_io = local_cosines(np, wi.reshape(-1, 3), wo.reshape(-1, 3))
        value = _flat_value(value, wi.shape[:-1])
        return cls._with_value(mu_i, mu_o, cos_io, value, irradiance, source)

    @classmethod
    def from_image(
        cls,
        image: Any,
        normals: Any,
        light: Any,
        view: Any,
        *,
        irradiance: Any = 1.0,
        mask: Any = None,
        erode: int = 1,
        source: str = "",
    ) -> Measurements:
        """Pixels of a linear radiance image with known normals.

        Parameters
        ----------
        image : array (H, W) or (H, W, C)
            Linear radiance L = f_r E0 cos θi.
        normals : array (H, W, 3)
            Unit surface normal at each pixel (world frame); zero vectors mark background.
        light, view : array (3,) or (H, W, 3)
            Directions towards the (distant) light and the viewer, world frame.
        irradiance : float or array (C,)
            E0, the irradiance on a plane facing the light.
        mask : array (H, W) of bool, optional
            Pixels to use; by default every pixel with a normal that sees both the light
            and the viewer (n·l > 0 and n·v > 0).
        erode : int
            Drop this many pixels along every edge of the usable region (silhouette,
            terminator, cast-shadow and mask boundaries): a pixel there integrates parts
            that are lit and unlit, or on and off the object, which its centre's normal does
            not describe.
        """
        img = _as_float("image", image)
        if img.ndim not in (2, 3):
            raise ParameterError(f"image must have shape (H, W) or (H, W, C) (got {img.shape})")
        h, w = img.shape[:2]
        nrm = _as_float("normals", normals)
        if nrm.shape != (h, w, 3):
            raise ParameterError(
                f"normals must have shape ({h}, {w}, 3) like the image (got {nrm.shape})"
            )
        length = np.linalg.norm(nrm, axis=-1)
        use = length > 0.5
        if mask is not None:
            m = np.asarray(mask, dtype=bool)
            if m.shape != (h, w):
                raise ParameterError(f"mask must have shape ({h}, {w}) (got {m.shape})")
            use &= m
        l = np.broadcast_to(_as_float("light", light), (h, w, 3))
        v = np.broadcast_to(_as_float("view", view), (h, w, 3))
        if int(erode) < 0:
            raise ParameterError(f"erode must be >= 0 pixels (got {erode})")
        idx = np.flatnonzero(use)
        mu_i, mu_o, cos_io = world_cosines(
            np, nrm.reshape(-1, 3)[idx], l.reshape(-1, 3)[idx], v.reshape(-1, 3)[idx]
        )
        lit = (mu_i > 1e-6) & (mu_o > 1e-6)
        good = np.zeros(h * w, dtype=bool)
        good[idx[lit]] = True
        good = good.reshape(h, w)
        good = _erode(good, int(erode))
        keep = good.reshape(-1)[idx]
        idx, mu_i, mu_o, cos_io = idx[keep], mu_i[keep], mu_o[keep], cos_io[keep]
        if idx.size == 0:
            raise ParameterError("the image has no pixel that sees both the light and the viewer")
        value = img.reshape(h * w, -1)[idx]
        if img.ndim == 2:
            value = value[:, 0]
        e0 = _as_float("irradiance", irradiance)
        if e0.ndim == 1 and img.ndim == 3:
            value = value / e0  # per-channel E0: fit value/E0 = f cos θi
            e0 = np.asarray(1.0)
        if e0.ndim != 0 or e0 <= 0:
            raise ParameterError("irradiance must be a positive scalar, or one value per channel")
        return cls(
            mu_i,
            mu_o,
            np.clip(cos_io, -1.0, 1.0),
            value,
            float(e0) * mu_i,
            kind="radiance",
            source=source,
            image_shape=(h, w),
            pixels=idx,
        )

    @classmethod
    def _with_value(
        cls, mu_i: Any, mu_o: Any, cos_io: Any, value: Any, irradiance: Any, source: str
    ) -> Measurements:
        val = _as_float("value", value)
        n = np.shape(mu_i)[0]
        if val.ndim not in (1, 2) or val.shape[0] != n:
            raise ParameterError(f"value must have shape ({n},) or ({n}, C) (got {val.shape})")
        if np.any(val < 0):
            raise ParameterError("value must be >= 0 (a BRDF or a radiance)")
        if irradiance is None:
            return cls(mu_i, mu_o, cos_io, val, np.ones(n), kind="brdf", source=source)
        e0 = np.broadcast_to(_as_float("irradiance", irradiance), (n,))
        if np.any(e0 <= 0):
            raise ParameterError("irradiance must be > 0")
        return cls(mu_i, mu_o, cos_io, val, e0 * np.asarray(mu_i), kind="radiance", source=source)

    # ----------------------------------------------------------------- views
    @property
    def size(self) -> int:
        """Number of samples."""
        return int(self.mu_i.shape[0])

    @property
    def channels(self) -> int:
        """Number of colour channels (0 for one channel stored as a 1-D array)."""
        return 0 if self.value.ndim == 1 else int(self.value.shape[1])

    @property
    def brdf_value(self) -> np.ndarray:
        """The data as BRDF values (value / scale); samples with scale 0 give 0."""
        s = self.scale if self.value.ndim == 1 else self.scale[:, None]
        return np.where(s > 0, self.value / np.where(s > 0, s, 1.0), 0.0)

    def angles(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """θi, θr and Δφ = φr − φi in radians (Δφ in [0, π]; 0 where undefined)."""
        ti = np.arccos(np.clip(self.mu_i, -1, 1))
        tr = np.arccos(np.clip(self.mu_o, -1, 1))
        den = np.sin(ti) * np.sin(tr)
        c = np.where(
            den > 1e-12,
            (self.cos_io - self.mu_i * self.mu_o) / np.where(den > 1e-12, den, 1.0),
            1.0,
        )
        return ti, tr, np.arccos(np.clip(c, -1, 1))

    def subset(self, index: Any) -> Measurements:
        """The samples selected by ``index`` (boolean mask or integer array)."""
        return Measurements(
            self.mu_i[index],
            self.mu_o[index],
            self.cos_io[index],
            self.value[index],
            self.scale[index],
            kind=self.kind,
            source=self.source,
            image_shape=self.image_shape,
            pixels=None if self.pixels is None else self.pixels[index],
        )


def _erode(good: np.ndarray, times: int) -> np.ndarray:
    """``good`` (H, W) without ``times`` pixels along every edge of its regions (and of the
    image): a pixel stays if it and its four neighbours are good."""
    for _ in range(times):
        inner = good.copy()
        inner[1:, :] &= good[:-1, :]
        inner[:-1, :] &= good[1:, :]
        inner[:, 1:] &= good[:, :-1]
        inner[:, :-1] &= good[:, 1:]
        inner[0, :] = inner[-1, :] = False
        inner[:, 0] = inner[:, -1] = False
        good = inner
    return good
