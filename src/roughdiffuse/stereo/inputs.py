"""Inputs of photometric stereo: images, lights and a mask, checked against each other.

Conventions (camera frame): x to the right, y up, z towards the camera; the camera is
orthographic, so the view direction is +z at every pixel. Image row 0 is the top of the
picture (largest y). A light is a direction *towards* the light (normalised here) and an
irradiance E0 on a plane facing it, scalar or per colour channel.

``lights.json``::

    {"directions": [[x, y, z], ...], "intensities": [E0 or [R, G, B], ...]}

one entry per image, in image order. The DiLiGenT data set (Shi et al., "A Benchmark Dataset
and Evaluation Method for Non-Lambertian and Uncalibrated Photometric Stereo", CVPR 2016)
stores the same in ``light_directions.txt`` and ``light_intensities.txt`` (one row per
image, listed in ``filenames.txt``) with ``mask.png``; :func:`read_diligent` reads that layout.
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError

__all__ = ["StereoInput", "load_images", "read_diligent", "read_lights", "read_mask"]


@dataclass(frozen=True)
class StereoInput:
    """K images of one still object under K known distant lights.

    Attributes
    ----------
    images : float64 array (K, H, W, C)
        Linear radiance; C = 1 for grey images, 3 for RGB.
    valid : bool array (K, H, W)
        Observations that hold a value (finite, not saturated).
    directions : float64 array (K, 3)
        Unit vectors towards each light, camera frame.
    intensities : float64 array (K, C)
        Irradiance E0 of each light on a plane facing it, per channel.
    mask : bool array (H, W)
        Pixels of the object.
    """

    images: np.ndarray
    valid: np.ndarray
    directions: np.ndarray
    intensities: np.ndarray
    mask: np.ndarray

    def __post_init__(self) -> None:
        imgs, valid = self.images, self.valid
        if imgs.ndim != 4:
            raise ParameterError(f"images must have shape (K, H, W, C) (got {imgs.shape})")
        k, h, w, c = imgs.shape
        if k < 3:
            raise ParameterError(f"photometric stereo needs at least 3 images (got {k})")
        if valid.shape != (k, h, w):
            raise ParameterError(f"valid must have shape {(k, h, w)} (got {valid.shape})")
        if self.directions.shape != (k, 3):
            raise ParameterError(
                f"lights do not match the images: {k} images but "
                f"{self.directions.shape[0] if self.directions.ndim == 2 else '?'} light directions"
            )
        if self.intensities.shape != (k, c):
            raise ParameterError(
                f"light intensities must have shape ({k}, {c}) for {k} images with {c} "
                f"channel(s) (got {self.intensities.shape})"
            )
        if self.mask.shape != (h, w):
            raise ParameterError(
                f"mask must have shape {(h, w)} like the images (got {self.mask.shape})"
            )
        if not self.mask.any():
            raise ParameterError("mask selects no pixel")
        if not np.all(self.directions[:, 2] > 0):
            bad = int(np.argmin(self.directions[:, 2]))
            raise ParameterError(
                f"light {bad} lies below the horizon of every pixel that the camera sees "
                f"(direction z = {self.directions[bad, 2]:g} must be > 0)"
            )

    @property
    def count(self) -> int:
        """Number of images K."""
        return int(self.images.shape[0])

    @property
    def channels(self) -> int:
        """Colour channels C of the images."""
        return int(self.images.shape[3])

    @cached_property
    def observations(self) -> np.ndarray:
        """The object pixels' values, (K, P, C) in mask order, read-only: gathered once (the
        input is frozen), as every solver reads them several times."""
        obs = self.images[:, self.mask, :]
        obs.setflags(write=False)
        return obs

    @cached_property
    def observed(self) -> np.ndarray:
        """Which of :attr:`observations` hold a value (:attr:`valid` of the object pixels):
        (K, P), read-only, gathered once."""
        valid = self.valid[:, self.mask]
        valid.setflags(write=False)
        return valid

    @cached_property
    def grey(self) -> np.ndarray:
        """The object pixels' values over each light's irradiance, averaged over the
        channels: (K, P), read-only, computed once."""
        grey = (self.observations / self.intensities[:, None, :]).mean(axis=-1)
        grey.setflags(write=False)
        return grey

    @classmethod
    def from_arrays(
        cls,
        images: Any,
        directions: Any,
        intensities: Any = 1.0,
        mask: Any = None,
        valid: Any = None,
    ) -> StereoInput:
        """Build an input from arrays, normalising the light directions.

        Parameters
        ----------
        images : array (K, H, W) or (K, H, W, C)
            Linear radiance images.
        directions : array (K, 3)
            Directions towards the lights (any length > 0).
        intensities : float, array (K,) or (K, C)
            Irradiance of each light.
        mask : bool array (H, W), optional
            Object pixels (default: every pixel with a positive value in some image).
        valid : bool array (K, H, W), optional
            Usable observations (default: the finite ones).
        """
        imgs = np.asarray(images, dtype=np.float64)
        if imgs.ndim == 3:
            imgs = imgs[..., None]
        if imgs.ndim != 4 or imgs.shape[3] not in (1, 3):
            raise ParameterError(
                f"images must have shape (K, H, W) or (K, H, W, 3) (got {imgs.shape})"
            )
        finite = np.all(np.isfinite(imgs), axis=-1)
        if np.any(imgs[np.isfinite(imgs)] < 0):
            raise ParameterError("images must hold non-negative radiance")
        imgs = np.where(np.isfinite(imgs), imgs, 0.0)
        dirs = _unit_directions(directions)
        k, c = imgs.shape[0], imgs.shape[3]
        e0 = _intensities(intensities, k, c)
        vmask = finite if valid is None else (np.asarray(valid, dtype=bool) & finite)
        if mask is None:
            mask = np.any(imgs.sum(axis=-1) > 0, axis=0)
        return cls(imgs, vmask, dirs, e0, np.asarray(mask, dtype=bool))


def _unit_directions(directions: Any) -> np.ndarray:
    d = np.asarray(directions, dtype=np.float64)
    if d.ndim != 2 or d.shape[1] != 3:
        raise ParameterError(f"light directions must have shape (K, 3) (got {d.shape})")
    bad = ~np.all(np.isfinite(d), axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise ParameterError(f"light direction {k + 1} is not finite (got {d[k].tolist()})")
    # scaled by its largest component first: a tiny direction (1e-170, 1e-170, 0) is a
    # direction, though the sum of its squares underflows to 0
    scale = np.max(np.abs(d), axis=1)
    if np.any(scale == 0):
        k = int(np.argmax(scale == 0))
        raise ParameterError(f"light direction {k + 1} is the zero vector; give its direction")
    d = d / scale[:, None]
    return d / np.linalg.norm(d, axis=1)[:, None]


def _intensities(intensities: Any, k: int, c: int) -> np.ndarray:
    e = np.asarray(intensities, dtype=np.float64)
    if e.ndim == 0:
        e = np.full((k, c), float(e))
    elif e.ndim == 1:
        if e.shape[0] != k:
            raise ParameterError(f"{k} images but {e.shape[0]} light intensities")
        e = np.repeat(e[:, None], c, axis=1)
    elif e.ndim == 2:
        if e.shape[0] != k:
            raise ParameterError(f"{k} images but {e.shape[0]} light intensities")
        if e.shape[1] == 3 and c == 1:
            e = e.mean(axis=1, keepdims=True)
        elif e.shape[1] != c:
            raise ParameterError(f"light intensities have {e.shape[1]} channels, images have {c}")
    else:
        raise ParameterError(
            f"light intensities must be scalars or [R, G, B] (got shape {e.shape})"
        )
    if not np.all(np.isfinite(e)) or np.any(e <= 0):
        raise ParameterError("light intensities must be finite and > 0")
    return e


def read_lights(path: str | os.PathLike[str]) -> tuple[np.ndarray, np.ndarray]:
    """Read ``lights.json``: ``{"directions": [[x, y, z], ...], "intensities": [...]}``.

    Returns the raw directions (K, 3) and intensities (K,) or (K, 3); a missing
    ``intensities`` means 1 for every light.
    """
    from ..io.reading import read_json

    name = os.fspath(path)
    spec = read_json(name, "lights file")
    if not isinstance(spec, dict) or "directions" not in spec:
        raise ParameterError(f"{os.path.basename(name)}: expected an object with 'directions'")
    try:
        d = np.asarray(spec["directions"], dtype=np.float64)
        e = np.asarray(spec.get("intensities", [1.0] * len(spec["directions"])), dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ParameterError(
            f"{os.path.basename(name)}: directions and intensities must be numbers ({exc})"
        ) from None
    return _unit_directions(d), e


def read_mask(path: str | os.PathLike[str]) -> np.ndarray:
    """A mask image (PNG or ``.npy``): non-zero pixels belong to the object."""
    from ..io.reading import check_regular

    name = os.fspath(path)
    check_regular(name, "mask file")
    if name.lower().endswith(".npy"):
        from ..io.reading import load_npy

        m = load_npy(name, "mask file", bool_ok=True)
    else:
        from PIL import Image, UnidentifiedImageError

        try:
            with Image.open(name) as im:
                m = np.asarray(im)
        except (OSError, UnidentifiedImageError) as exc:
            raise ParameterError(
                f"{os.path.basename(name)}: not a readable mask image ({exc})"
            ) from None
    m = np.asarray(m)
    if m.ndim == 3:
        m = m[..., :3].max(axis=-1) if m.shape[2] >= 3 else m[..., 0]
    if m.ndim != 2:
        raise ParameterError(
            f"{os.path.basename(name)}: a mask must be a 2-D image (got {m.shape})"
        )
    return m > 0


def load_images(
    paths: Sequence[str | os.PathLike[str]], *, exposure: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Read K linear images (``.npy``, ``.exr`` or ``.png`` with its exposure).

    Returns
    -------
    images : float64 array (K, H, W, C)
    valid : bool array (K, H, W)
        Finite, unsaturated pixels.
    """
    from ..fit.images import read_image

    if len(paths) < 3:
        raise ParameterError(f"photometric stereo needs at least 3 images (got {len(paths)})")
    imgs, valid = [], []
    for p in paths:
        img, ok = read_image(p, exposure=exposure)
        if img.ndim == 2:
            img = img[..., None]
        if imgs and img.shape != imgs[0].shape:
            raise ParameterError(
                f"images differ in size: {Path(p).name} is {img.shape[1]}x{img.shape[0]}, "
                f"{Path(paths[0]).name} is {imgs[0].shape[1]}x{imgs[0].shape[0]} "
                f"(or in channels: {img.shape[2]} against {imgs[0].shape[2]})"
            )
        imgs.append(img)
        valid.append(ok)
    return np.stack(imgs), np.stack(valid)


def read_diligent(folder: str | os.PathLike[str]) -> StereoInput:
    """Read one object of the DiLiGenT layout.

    The folder holds ``filenames.txt`` (one image name a line, PNG, 16 bit), the
    ``light_directions.txt`` and ``light_intensities.txt`` matrices (one row per image:
    x y z, and R G B) and ``mask.png``. DiLiGenT's directions are in the camera frame with
    x right, y up and z towards the camera, the same as here; its PNGs are linear 16-bit,
    read with exposure 0 and the identity transfer curve.
    """
    from ..fit.images import read_image
    from ..io.reading import MAX_LIST_BYTES, read_text, short

    root = Path(folder)
    need = ["filenames.txt", "light_directions.txt", "light_intensities.txt", "mask.png"]
    missing = [n for n in need if not (root / n).exists()]
    if missing:
        raise ParameterError(f"{root}: not a DiLiGenT object folder (missing {', '.join(missing)})")
    text = read_text(root / "filenames.txt", MAX_LIST_BYTES, "DiLiGenT list")
    names = [s.strip() for s in text.splitlines() if s.strip()]
    for n in names:  # image names stay inside the object's folder
        inside = os.path.normpath(n)
        if os.path.isabs(n) or inside == ".." or inside.startswith(".." + os.sep):
            raise ParameterError(
                f"{root}/filenames.txt names {short(n)}, outside the object's folder: refused"
            )
    try:
        dirs = np.loadtxt(
            io.StringIO(read_text(root / "light_directions.txt", MAX_LIST_BYTES)), ndmin=2
        )
        ints = np.loadtxt(
            io.StringIO(read_text(root / "light_intensities.txt", MAX_LIST_BYTES)), ndmin=2
        )
    except ValueError as exc:
        raise ParameterError(f"{root}: unreadable light file ({exc})") from None
    if len(names) != dirs.shape[0] or len(names) != ints.shape[0]:
        raise ParameterError(
            f"{root}: {len(names)} images but {dirs.shape[0]} light directions and "
            f"{ints.shape[0]} intensities"
        )
    imgs, valid = [], []
    for n in names:
        img, ok = read_image(root / n, exposure=0.0, encoding="linear")
        imgs.append(img if img.ndim == 3 else img[..., None])
        valid.append(ok)
        if imgs[-1].shape != imgs[0].shape:
            raise ParameterError(f"{root}: image {n} differs in size from {names[0]}")
    mask = read_mask(root / "mask.png")
    if mask.shape != imgs[0].shape[:2]:
        (h, w), (mh, mw) = imgs[0].shape[:2], mask.shape
        raise ParameterError(f"{root}/mask.png is {mw}x{mh} pixels, the images are {w}x{h}")
    return StereoInput.from_arrays(np.stack(imgs), dirs, ints, mask=mask, valid=np.stack(valid))
