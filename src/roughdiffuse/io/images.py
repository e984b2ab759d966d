"""Image files: PNG (exposure + sRGB, 8 or 16 bit), .npy and OpenEXR (linear float32).

Every file is written by the one atomic writer, :func:`roughdiffuse.io.atomic.atomic_write`:
whole or not at all, with the mode the umask gives. Reading and writing images lives here, not
under :mod:`roughdiffuse.render`, because the renderer, the fit, the figures, the energy
report and the explorer all use it.

PNG stores display values: v = sRGB(clip(2^exposure · L, 0, 1)) with the sRGB transfer curve
of IEC 61966-2-1 (linear segment 12.92 x below 0.0031308, else 1.055 x^(1/2.4) − 0.055). The
file's text chunks say so (``roughdiffuse:encoding``, ``roughdiffuse:scale``), so the linear
value of a pixel can be recovered from it. The PNG encoder is written here (zlib and the PNG
specification, ISO/IEC 15948) because Pillow does not write 16-bit colour PNGs.
"""

from __future__ import annotations

import math
import os
import struct
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from .atomic import atomic_write

__all__ = [
    "exposure_scale",
    "linear_to_srgb",
    "read_png",
    "srgb_to_linear",
    "write_exr",
    "write_image",
    "write_npy",
    "write_png",
]

SUFFIXES = (".png", ".npy", ".exr")


def linear_to_srgb(x: np.ndarray) -> np.ndarray:
    """The sRGB transfer curve (IEC 61966-2-1) on values clipped to [0, 1]."""
    x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def srgb_to_linear(v: np.ndarray) -> np.ndarray:
    """Inverse of :func:`linear_to_srgb`."""
    v = np.asarray(v, dtype=np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def exposure_scale(image: np.ndarray, exposure: float | str = "auto", mask: Any = None) -> float:
    """The factor 2^exposure, or for ``"auto"`` the factor that maps the 99.9th percentile of
    the (masked) radiance to 1 (1 for an all-black image).
    """
    if isinstance(exposure, str):
        if exposure != "auto":
            raise ParameterError(f"exposure must be a number of stops or 'auto' (got {exposure!r})")
        vals = np.asarray(image, dtype=np.float64)
        if mask is not None:
            m = np.asarray(mask) > 0
            vals = vals[m] if vals.ndim == m.ndim else vals[m, :]
        vals = vals[np.isfinite(vals)]
        top = float(np.percentile(vals, 99.9)) if vals.size else 0.0
        return 1.0 / top if top > 0 else 1.0
    if not (isinstance(exposure, int | float) and math.isfinite(exposure)):
        raise ParameterError(f"exposure must be a finite number of stops (got {exposure!r})")
    return float(2.0**exposure)


def _check_image(image: Any) -> np.ndarray:
    img = np.asarray(image)
    if img.ndim not in (2, 3) or (img.ndim == 3 and img.shape[2] not in (1, 3)):
        raise ParameterError(
            f"image must have shape (H, W), (H, W, 1) or (H, W, 3) (got {img.shape})"
        )
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[..., 0]
    return img


def _png_bytes(data: np.ndarray, bits: int, text: Mapping[str, str]) -> bytes:
    """Encode uint8/uint16 pixels (H, W) or (H, W, C), C in 1..4, as a PNG file."""
    h, w = data.shape[:2]
    c = 1 if data.ndim == 2 else data.shape[2]
    color_type = {1: 0, 2: 4, 3: 2, 4: 6}[c]

    def chunk(kind: bytes, payload: bytes) -> bytes:
        crc = zlib.crc32(kind + payload) & 0xFFFFFFFF
        return struct.pack(">I", len(payload)) + kind + payload + struct.pack(">I", crc)

    dtype = ">u2" if bits == 16 else "u1"
    rows = np.ascontiguousarray(data.reshape(h, w * c).astype(dtype))
    raw = np.concatenate([np.zeros((h, 1), np.uint8), rows.view(np.uint8).reshape(h, -1)], axis=1)
    out = [
        b"\x89PNG\r\n\x1a\n",
        chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, bits, color_type, 0, 0, 0)),
    ]
    for key, value in text.items():
        out.append(chunk(b"iTXt", key.encode("latin-1") + b"\0\0\0\0\0" + value.encode("utf-8")))
    out.append(chunk(b"IDAT", zlib.compress(raw.tobytes(), 6)))
    out.append(chunk(b"IEND", b""))
    return b"".join(out)


def write_png(
    path: str | os.PathLike[str],
    image: Any,
    *,
    exposure: float | str = "auto",
    bits: int = 8,
    mask: Any = None,
    metadata: Mapping[str, str] | None = None,
) -> Path:
    """Write linear radiance as an sRGB PNG (atomically).

    Parameters
    ----------
    image : array (H, W) or (H, W, 3)
        Linear radiance.
    exposure : float or "auto"
        Stops: the radiance is multiplied by 2^exposure before the sRGB curve; "auto" maps
        the 99.9th percentile of the covered pixels to white.
    bits : {8, 16}
    mask : array (H, W), optional
        Coverage in [0, 1], written as the alpha channel (the colour is divided by it, so
        the PNG holds straight, not premultiplied, alpha).
    metadata : mapping, optional
        Extra text chunks.
    """
    if bits not in (8, 16):
        raise ParameterError(f"bits must be 8 or 16 (got {bits!r})")
    img = _check_image(image).astype(np.float64)
    scale = exposure_scale(img, exposure, mask)
    lin = img * scale
    if mask is not None:
        m = np.clip(np.asarray(mask, dtype=np.float64), 0.0, 1.0)
        if m.shape != img.shape[:2]:
            raise ParameterError(f"mask must have shape {img.shape[:2]} (got {m.shape})")
        mm = m if lin.ndim == 2 else m[..., None]
        lin = np.where(mm > 0, lin / np.where(mm > 0, mm, 1.0), 0.0)
    top = (1 << bits) - 1
    enc = np.rint(linear_to_srgb(lin) * top)
    if mask is not None:
        alpha = np.rint(m * top)
        enc = np.concatenate([enc.reshape(*m.shape, -1), alpha[..., None]], axis=-1)
    text = {
        "Software": "roughdiffuse",
        "roughdiffuse:encoding": "sRGB(clip(scale * linear radiance, 0, 1)) (IEC 61966-2-1)",
        "roughdiffuse:scale": f"{scale:.9g}",
        "roughdiffuse:exposure": f"{math.log2(scale):.6g} stops" if scale > 0 else "0",
    }
    text.update(metadata or {})
    payload = _png_bytes(enc, bits, text)
    return atomic_write(path, lambda tmp: tmp.write_bytes(payload))


def write_npy(path: str | os.PathLike[str], image: Any) -> Path:
    """Write the linear float32 image as a NumPy ``.npy`` file (atomically)."""
    arr = np.asarray(image, dtype=np.float32)

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            np.save(fh, arr)

    return atomic_write(path, write)


def write_exr(
    path: str | os.PathLike[str], image: Any, metadata: Mapping[str, str] | None = None
) -> Path:
    """Write the linear image as a float32 OpenEXR file (atomically), through the ``OpenEXR``
    package (the Academy Software Foundation's bindings).

    Channels: Y for a grey image, R, G, B for colour.
    """
    import OpenEXR

    img = np.ascontiguousarray(_check_image(image), dtype=np.float32)
    channels = {"Y": img} if img.ndim == 2 else {"RGB": img}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    for key, value in (metadata or {}).items():
        header[key] = str(value)

    def write(tmp: Path) -> None:
        with OpenEXR.File(header, channels) as f:
            f.write(str(tmp))

    return atomic_write(path, write)


def write_image(
    path: str | os.PathLike[str],
    image: Any,
    *,
    mask: Any = None,
    exposure: float | str = "auto",
    bits: int = 8,
    metadata: Mapping[str, str] | None = None,
) -> Path:
    """Write an image with the format its suffix names: .png, .npy or .exr."""
    suffix = Path(path).suffix.lower()
    if suffix == ".png":
        return write_png(path, image, exposure=exposure, bits=bits, mask=mask, metadata=metadata)
    if suffix == ".npy":
        return write_npy(path, image)
    if suffix == ".exr":
        return write_exr(path, image, metadata=metadata)
    raise ParameterError(
        f"output file must end in one of {', '.join(SUFFIXES)} (got {str(path)!r})"
    )


# --------------------------------------------------------------------------- PNG reading
def _paeth(a: int, b: int, c: int) -> int:
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def _unfilter(raw: np.ndarray, h: int, stride: int, bpp: int) -> np.ndarray:
    """Undo the PNG scanline filters (ISO/IEC 15948 §9); rows of ``stride`` bytes."""
    data = raw.reshape(h, stride + 1)
    out = np.zeros((h, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.int64)
    for y in range(h):
        kind = int(data[y, 0])
        row = data[y, 1:].astype(np.int64)
        if kind == 0:
            cur = row
        elif kind == 1:  # Sub: running sum along each byte lane
            lanes = np.zeros(stride + (-stride) % bpp, dtype=np.int64)
            lanes[:stride] = row
            cur = (np.cumsum(lanes.reshape(-1, bpp), axis=0).ravel()[:stride]) % 256
        elif kind == 2:  # Up
            cur = (row + prev) % 256
        elif kind in (3, 4):  # Average, Paeth: sequential along the row
            cur = np.zeros(stride, dtype=np.int64)
            r, p = row.tolist(), prev.tolist()
            c = [0] * stride
            for x in range(stride):
                left = c[x - bpp] if x >= bpp else 0
                if kind == 3:
                    c[x] = (r[x] + (left + p[x]) // 2) % 256
                else:
                    ul = p[x - bpp] if x >= bpp else 0
                    c[x] = (r[x] + _paeth(left, p[x], ul)) % 256
            cur = np.asarray(c, dtype=np.int64)
        else:
            raise ParameterError(f"PNG row {y}: unknown filter type {kind}")
        out[y] = cur
        prev = cur
    return out


def read_png(path: str | os.PathLike[str]) -> tuple[np.ndarray, int, dict[str, str]]:
    """(pixels (H, W, C) uint32, bit depth, text chunks) of a non-interlaced 8/16-bit PNG.

    Written here for the same reason as the encoder: Pillow reads 16-bit colour PNGs as
    8-bit. Raises ``ValueError`` naming the file for anything it cannot read.
    """
    from .reading import MAX_IMAGE_BYTES, read_bytes

    path = os.fspath(path)
    name = os.path.basename(path)
    blob = read_bytes(path, MAX_IMAGE_BYTES, "PNG file")
    if blob[:8] != b"\x89PNG\r\n\x1a\n":
        raise ParameterError(f"{name}: not a PNG file")
    pos, idat, text = 8, [], {}
    header = None
    while pos + 8 <= len(blob):
        (length,) = struct.unpack(">I", blob[pos : pos + 4])
        kind = blob[pos + 4 : pos + 8]
        payload = blob[pos + 8 : pos + 8 + length]
        if len(payload) < length:
            raise ParameterError(f"{name}: truncated PNG file")
        pos += 12 + length
        if kind == b"IHDR":
            if len(payload) != 13:  # ISO/IEC 15948 §11.2.2: IHDR holds 13 bytes
                raise ParameterError(f"{name}: corrupt PNG header ({len(payload)}-byte IHDR)")
            header = struct.unpack(">IIBBBBB", payload)
        elif kind == b"IDAT":
            idat.append(payload)
        elif kind in (b"tEXt", b"iTXt"):
            key, _, rest = payload.partition(b"\0")
            if kind == b"iTXt":
                rest = rest[2:].split(b"\0", 2)[-1]
            text[key.decode("latin-1")] = rest.decode("utf-8", "replace")
        elif kind == b"IEND":
            break
    if header is None:
        raise ParameterError(f"{name}: PNG without IHDR")
    w, h, bits, color, _, _, interlace = header
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(color)
    if channels is None or bits not in (8, 16) or interlace:
        raise ParameterError(
            f"{name}: only non-interlaced 8- or 16-bit grey/RGB(A) PNG is supported "
            f"(colour type {color}, {bits} bits, interlace {interlace})"
        )
    try:
        raw = np.frombuffer(zlib.decompress(b"".join(idat)), dtype=np.uint8)
    except zlib.error as exc:
        raise ParameterError(f"{name}: corrupt PNG data ({exc})") from None
    bpp = channels * bits // 8
    stride = w * bpp
    if raw.size != h * (stride + 1):
        raise ParameterError(f"{name}: truncated PNG data")
    rows = _unfilter(raw, h, stride, bpp)
    dtype = ">u2" if bits == 16 else "u1"
    pix = rows.reshape(h, -1).view(dtype).reshape(h, w, channels).astype(np.uint32)
    return pix, bits, text
