"""A glTF 2.0 asset of a model: a UV sphere whose material is EON (``.gltf`` or ``.glb``).

The material is glTF's metallic-roughness material with the extension
``KHR_materials_diffuse_roughness`` (Khronos, draft, glTF pull request 2481:
``extensions/2.0/Khronos/KHR_materials_diffuse_roughness`` of KhronosGroup/glTF), whose
``diffuseRoughnessFactor`` is OpenPBR's ``base_diffuse_roughness``, the roughness r of EON
(J. Portsmouth, P. Kutz, S. Hill, JCGT 2025; the extension's informative implementation
section names EON through OpenPBR):

* ``pbrMetallicRoughness.baseColorFactor`` = the albedo ρ (linear RGB, opacity 1),
  ``metallicFactor`` 0;
* ``KHR_materials_diffuse_roughness.diffuseRoughnessFactor`` = r (written even at 0: the
  extension's text and its schema disagree on the default, 0 against 1);
* ``KHR_materials_specular.specularFactor`` = 0: glTF's dielectric adds a specular lobe (F0
  from ``ior``) and gives the diffuse lobe only 1 − F of the light (its ``fresnel_mix``);
  ``specularFactor`` scales both F0 and F90, so 0 turns that lobe off and leaves the diffuse
  lobe alone. ``roughnessFactor`` (the specular lobe's) is then unused; it is written as 1.

The model is written as roughdiffuse's ``eon`` (exact for ``eon`` and ``openpbr-diffuse``);
any other rough-diffuse model is converted (:func:`roughdiffuse.fit.between_models.convert`)
and the conversion error is written in ``asset.extras.roughdiffuse`` and returned. A viewer
that does not know the extension renders Lambert (the extensions are used, not required).

The sphere (radius 1, centre at the origin, +y its pole) carries positions and unit normals
in one buffer (no texture coordinates: the material has no texture): embedded as base64 in a
``.gltf``, the binary chunk of a ``.glb`` (glTF 2.0 specification, section 4.4 "GLB File
Format Specification").
"""

from __future__ import annotations

import base64
import json
import math
import struct
from pathlib import Path
from typing import Any

import numpy as np

from .._version import version
from ..io.atomic import write_bytes
from ..models.base import Model
from .common import Export, error_lines, material_for, rgb_of

__all__ = ["TARGET_MODEL", "asset", "sphere", "write"]

TARGET_MODEL = "eon"
"""The registry model a glTF viewer with ``KHR_materials_diffuse_roughness`` renders."""

SEGMENTS = (64, 32)
"""The sphere's segments around its axis and from pole to pole."""

_FLOAT, _USHORT, _UINT = 5126, 5123, 5125  # componentType (glTF 2.0, accessor)
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963  # bufferView.target
_GLB_MAGIC, _JSON_CHUNK, _BIN_CHUNK = 0x46546C67, 0x4E4F534A, 0x004E4942  # "glTF", "JSON", "BIN"


def sphere(around: int = SEGMENTS[0], down: int = SEGMENTS[1]) -> dict[str, np.ndarray]:
    """A UV sphere of radius 1: ``position`` and ``normal`` (equal, float32 (V, 3)) and
    counter-clockwise ``indices`` (uint32 (T, 3)) seen from outside. Each row of vertices
    repeats its first one at φ = 2π; the rows at the poles have one triangle per segment (no
    degenerate triangles)."""
    theta = np.linspace(0.0, math.pi, down + 1)  # from the +y pole
    phi = np.linspace(0.0, 2.0 * math.pi, around + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    pos = np.stack([np.sin(t) * np.sin(p), np.cos(t), np.sin(t) * np.cos(p)], axis=-1)
    pos = pos.reshape(-1, 3)
    pos /= np.linalg.norm(pos, axis=1, keepdims=True)
    row = around + 1
    quads = []
    for i in range(down):
        for j in range(around):
            a, b = i * row + j, i * row + j + 1
            c, d = a + row, b + row
            if i > 0:
                quads.append((a, c, b))
            if i < down - 1:
                quads.append((b, c, d))
    pos32 = pos.astype(np.float32)
    return {
        "position": pos32,
        "normal": pos32.copy(),
        "indices": np.asarray(quads, dtype=np.uint32),
    }


def _pad(data: bytes, fill: bytes = b"\0") -> bytes:
    return data + fill * (-len(data) % 4)


def asset(
    params: dict[str, Any], record: dict[str, Any], *, binary: bool = False
) -> tuple[dict[str, Any], bytes]:
    """The glTF JSON and its buffer for EON's ``params`` (``albedo``, ``roughness``);
    ``record`` goes into ``asset.extras.roughdiffuse``. Without ``binary`` the buffer is
    embedded in the JSON as a base64 data URI (and also returned)."""
    mesh = sphere()
    idx = mesh["indices"]
    idx = idx.astype(np.uint16) if len(mesh["position"]) < 65536 else idx
    arrays = [mesh["position"], mesh["normal"], idx]
    views, blob = [], b""
    for k, arr in enumerate(arrays):
        raw = np.ascontiguousarray(arr).astype(arr.dtype.newbyteorder("<")).tobytes()
        target = _ELEMENT_ARRAY_BUFFER if k == 2 else _ARRAY_BUFFER
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(raw),
                      "target": target})  # fmt: skip
        blob = _pad(blob + raw)
    count = len(mesh["position"])
    pos = mesh["position"]
    accessors = [
        {"bufferView": 0, "componentType": _FLOAT, "count": count, "type": "VEC3",
         "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
        {"bufferView": 1, "componentType": _FLOAT, "count": count, "type": "VEC3"},
        {"bufferView": 2, "componentType": _USHORT if idx.dtype == np.uint16 else _UINT,
         "count": int(idx.size), "type": "SCALAR"},
    ]  # fmt: skip
    buffer: dict[str, Any] = {"byteLength": len(blob)}
    if not binary:
        buffer["uri"] = "data:application/octet-stream;base64," + base64.b64encode(blob).decode()
    colour = rgb_of(params.get("albedo", 1.0))
    material = {
        "name": "roughdiffuse",
        "pbrMetallicRoughness": {
            "baseColorFactor": [*colour, 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 1.0,
        },
        "extensions": {
            "KHR_materials_diffuse_roughness": {
                "diffuseRoughnessFactor": float(params["roughness"])
            },
            "KHR_materials_specular": {"specularFactor": 0.0},
        },
    }
    doc = {
        "asset": {
            "version": "2.0",
            "generator": f"roughdiffuse {version()}",
            "extras": {"roughdiffuse": record},
        },
        "extensionsUsed": ["KHR_materials_diffuse_roughness", "KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "sphere", "mesh": 0}],
        "meshes": [{"name": "sphere", "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
        "materials": [material],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [buffer],
    }  # fmt: skip
    return doc, blob


def glb(doc: dict[str, Any], blob: bytes) -> bytes:
    """The GLB container of ``doc`` and its binary buffer (glTF 2.0, section 4.4): a 12-byte
    header, a JSON chunk padded with spaces, a BIN chunk padded with zeros."""
    text = _pad(json.dumps(doc, separators=(",", ":")).encode("utf-8"), b" ")
    body = _pad(blob)
    chunks = struct.pack("<II", len(text), _JSON_CHUNK) + text
    chunks += struct.pack("<II", len(body), _BIN_CHUNK) + body
    return struct.pack("<III", _GLB_MAGIC, 2, 12 + len(chunks)) + chunks


def write(model: Model, path: Path) -> Export:
    """Write ``model`` as a glTF sphere to ``path`` (``.glb``: binary, else ``.gltf``), whole
    or not at all; converted to EON where it is another model.

    Raises
    ------
    ValueError
        If the model cannot be converted (see :func:`roughdiffuse.fit.between_models.convert`)
        or its albedo is not 1 or 3 channels.
    """
    from .. import registry

    params, conversion = material_for(model, TARGET_MODEL)
    lines = error_lines(conversion)
    record = {
        "model": registry.id_of(model),
        "as": TARGET_MODEL,
        "params": params,
        "conversion": " ".join(lines),
    }
    if conversion is not None:
        record.update(
            rms_f=conversion.rms_f, max_f=conversion.max_f,
            rms_albedo=conversion.rms_albedo, max_albedo=conversion.max_albedo,
        )  # fmt: skip
    binary = Path(path).suffix.lower() == ".glb"
    doc, blob = asset(params, record, binary=binary)
    data = glb(doc, blob) if binary else (json.dumps(doc, indent=1) + "\n").encode("utf-8")
    write_bytes(path, data)
    notes = (
        "KHR_materials_diffuse_roughness: diffuseRoughnessFactor = EON's r; specular lobe "
        "off (KHR_materials_specular specularFactor 0); viewers without the extension "
        "render Lambert",
    )
    return Export("gltf", (Path(path),), TARGET_MODEL, params, conversion, notes)
