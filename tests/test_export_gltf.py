"""roughdiffuse export --to gltf: a sphere whose material carries EON's roughness.

The files are read back here by the glTF 2.0 specification's own layout (the GLB header and
chunks of its section 4.4, the accessors' component types), not by the writer's code, and
checked by the Khronos glTF validator (npm ``gltf-validator``, ``tests/js/validate.mjs``,
installed by ``npm ci`` in ``tests/js``).
"""

from __future__ import annotations

import base64
import json
import math
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.cli import main
from roughdiffuse.exporters import TARGETS, export

JS_DIR = Path(__file__).resolve().parent / "js"
VALIDATOR = JS_DIR / "node_modules" / "gltf-validator" / "package.json"


def _read(path: Path) -> tuple[dict, bytes]:
    """The JSON and the buffer of a .gltf (buffer a base64 data URI) or .glb file."""
    data = path.read_bytes()
    if path.suffix.lower() == ".glb":
        magic, version, length = struct.unpack_from("<III", data, 0)
        assert (magic, version, length) == (0x46546C67, 2, len(data))
        json_len, json_type = struct.unpack_from("<II", data, 12)
        assert json_type == 0x4E4F534A and json_len % 4 == 0
        doc = json.loads(data[20 : 20 + json_len])
        bin_len, bin_type = struct.unpack_from("<II", data, 20 + json_len)
        assert bin_type == 0x004E4942 and 28 + json_len + bin_len == len(data)
        return doc, data[28 + json_len :]
    doc = json.loads(data)
    head, _, b64 = doc["buffers"][0]["uri"].partition(",")
    assert head == "data:application/octet-stream;base64"
    return doc, base64.b64decode(b64)


def _accessor(doc: dict, blob: bytes, index: int) -> np.ndarray:
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    dtype = {5126: "<f4", 5123: "<u2", 5125: "<u4"}[acc["componentType"]]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[acc["type"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    arr = np.frombuffer(blob, dtype=dtype, count=acc["count"] * width, offset=start)
    return arr.reshape(acc["count"], width) if width > 1 else arr


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_the_file_holds_an_outward_unit_sphere_and_the_eon_material(tmp_path, suffix):
    model = registry.create("eon", albedo=[0.8, 0.5, 0.2], roughness=0.6)
    result = export(model, "gltf", tmp_path / f"s{suffix}")
    assert result.paths == (tmp_path / f"s{suffix}",) and result.conversion is None
    doc, blob = _read(result.paths[0])
    assert doc["asset"]["version"] == "2.0" and len(blob) == doc["buffers"][0]["byteLength"]
    prim = doc["meshes"][0]["primitives"][0]
    pos = _accessor(doc, blob, prim["attributes"]["POSITION"]).astype(np.float64)
    nrm = _accessor(doc, blob, prim["attributes"]["NORMAL"]).astype(np.float64)
    tri = _accessor(doc, blob, prim["indices"]).astype(np.int64).reshape(-1, 3)
    assert np.allclose(np.linalg.norm(pos, axis=1), 1.0, atol=1e-6) and np.allclose(nrm, pos)
    a, b, c = pos[tri[:, 0]], pos[tri[:, 1]], pos[tri[:, 2]]
    normal = np.cross(b - a, c - a)
    assert np.all(np.einsum("ij,ij->i", normal, a + b + c) > 0)  # counter-clockwise outside
    # one orientation: no directed edge belongs to two triangles
    edges = {tuple(e) for t in tri for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    seam = {tuple(np.round(p, 6)) for p in pos}
    assert len(edges) == 3 * len(tri) and len(seam) < len(pos)  # the seam's vertices repeat
    # the surface area of the triangles approaches 4π
    assert 0.99 * 4 * math.pi < 0.5 * np.linalg.norm(normal, axis=1).sum() < 4 * math.pi
    mat = doc["materials"][prim["material"]]
    assert mat["pbrMetallicRoughness"]["baseColorFactor"] == pytest.approx([0.8, 0.5, 0.2, 1])
    assert mat["pbrMetallicRoughness"]["metallicFactor"] == 0
    ext = mat["extensions"]
    assert ext["KHR_materials_diffuse_roughness"]["diffuseRoughnessFactor"] == pytest.approx(0.6)
    assert ext["KHR_materials_specular"]["specularFactor"] == 0
    assert set(doc["extensionsUsed"]) == set(ext) and "extensionsRequired" not in doc


def test_openpbr_diffuse_is_written_exactly_and_lambert_with_roughness_zero(tmp_path):
    openpbr = registry.create("openpbr-diffuse", albedo=0.4, roughness=0.25)
    result = export(openpbr, "gltf", tmp_path / "o.gltf")
    assert result.conversion is None
    assert result.params == {"albedo": 0.4, "roughness": 0.25}
    lam = export(registry.create("lambert", albedo=0.7), "gltf", tmp_path / "l.gltf")
    assert lam.params["roughness"] == pytest.approx(0.0, abs=1e-3)  # EON at r = 0 is Lambert
    assert lam.params["albedo"] == pytest.approx(0.7, abs=1e-3)


def test_a_converted_model_carries_its_error_in_the_file_and_the_summary(tmp_path, capsys):
    out = tmp_path / "on.glb"
    argv = ["export", "--model", "oren-nayar-full", "--param", "sigma=20", "--to", "gltf",
            "-o", str(out)]  # fmt: skip
    assert main(argv) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"gltf: {out}\n") and "converted from oren-nayar-full" in said
    extras = _read(out)[0]["asset"]["extras"]["roughdiffuse"]
    assert extras["model"] == "oren-nayar-full" and extras["as"] == "eon"
    assert 0 < extras["rms_f"] < extras["max_f"]
    assert f"{100 * extras['rms_f']:.3g} % RMS" in said and "% RMS" in extras["conversion"]
    albedo = _read(out)[0]["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
    assert albedo[:3] == pytest.approx([extras["params"]["albedo"]] * 3)


@pytest.fixture(scope="module")
def node():
    exe = shutil.which("node")
    if exe is None:
        pytest.skip("node is not installed")
    if not VALIDATOR.is_file():
        raise FileNotFoundError(f"{VALIDATOR} missing: run `make install-js` (npm ci in tests/js)")
    return exe


@pytest.mark.parametrize("suffix", [".gltf", ".glb"])
def test_the_khronos_validator_finds_no_error_and_no_warning(tmp_path, node, suffix):
    """The validator's report: no errors or warnings; its one information is that it does not
    know ``KHR_materials_diffuse_roughness`` (a draft), whose one value is checked here
    against the extension's schema (a number in [0, 1])."""
    model = registry.create("burley", albedo=[0.9, 0.6, 0.3], roughness=0.7)
    path = export(model, "gltf", tmp_path / f"b{suffix}").paths[0]
    run = subprocess.run([node, str(JS_DIR / "validate.mjs"), str(path)], capture_output=True,
                         text=True, cwd=JS_DIR, check=True)  # fmt: skip
    issues = json.loads(run.stdout)["issues"]
    assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, issues["messages"]
    assert [(m["code"], m["pointer"]) for m in issues["messages"]] == [
        ("UNSUPPORTED_EXTENSION", "/extensionsUsed/0")
    ]
    doc, _ = _read(path)
    assert doc["extensionsUsed"][0] == "KHR_materials_diffuse_roughness"
    factor = doc["materials"][0]["extensions"]["KHR_materials_diffuse_roughness"]
    assert set(factor) == {"diffuseRoughnessFactor"}
    assert 0.0 <= factor["diffuseRoughnessFactor"] <= 1.0


def test_a_broken_file_is_caught_by_the_validator(tmp_path, node):
    """The check can fail: an index past the last vertex is an error."""
    path = export(registry.create("eon"), "gltf", tmp_path / "e.gltf").paths[0]
    doc = json.loads(path.read_text())
    doc["accessors"][0]["count"] = 3  # three vertices, indices up to 2000
    path.write_text(json.dumps(doc))
    run = subprocess.run([node, str(JS_DIR / "validate.mjs"), str(path)], capture_output=True,
                         text=True, cwd=JS_DIR, check=True)  # fmt: skip
    assert json.loads(run.stdout)["issues"]["numErrors"] > 0


@pytest.mark.parametrize(
    ("model", "target", "says"),
    [
        ("hapke", "gltf", "hapke, a planetary photometric function"),
        ("lommel-seeliger", "gltf", "a planetary photometric function"),
        ("minnaert", "materialx", "a planetary photometric function"),
        ("hapke-2012", "blender", "a planetary photometric function"),
        ("torrance-sparrow", "gltf", "torrance-sparrow, a glossy model"),
        ("coated", "gltf", "coated, a specular coat over a base"),
        ("coated", "materialx", "coated, a specular coat over a base"),
    ],
)
def test_a_model_the_target_cannot_represent_is_refused_in_one_line(
    tmp_path, capsys, model, target, says
):
    out = tmp_path / f"m{TARGETS[target][0]}"
    assert main(["export", "--model", model, "--to", target, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err, err
    exact = "glsl writes" if model == "coated" else "mitsuba and glsl write"
    assert f"{target} takes rough-diffuse BRDFs" in err and exact in err
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(ValueError, match="cannot represent"):
        export(registry.get(model).create(), target, out)
    assert list(tmp_path.iterdir()) == []


def test_the_refusal_is_one_line_without_a_traceback_from_the_shell(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "export", "--model", "hapke", "--to", "gltf",
         "-o", str(tmp_path / "h.glb")],
        capture_output=True, text=True,
    )  # fmt: skip
    assert run.returncode == 2 and run.stdout == ""
    assert len(run.stderr.strip().splitlines()) == 1 and "Traceback" not in run.stderr
    assert "cannot represent hapke" in run.stderr


def _misspelt(name: str) -> str:
    """``name`` with its second and third letters swapped (``gltf`` -> ``gtlf``)."""
    return name[0] + name[2] + name[1] + name[3:]


@pytest.mark.parametrize("target", list(TARGETS))
def test_a_misspelt_target_gets_did_you_mean(tmp_path, capsys, target):
    wrong = _misspelt(target)
    assert wrong != target
    assert main(["export", "--model", "eon", "--to", wrong, "-o", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and f"did you mean {target}" in err, err
    assert list(tmp_path.iterdir()) == []


def test_fit_export_suggests_the_target_too():
    from roughdiffuse.commands import UsageError
    from roughdiffuse.commands._export_targets import parse_targets

    with pytest.raises(UsageError, match="did you mean gltf"):
        parse_targets("mitsuba,gtlf")
    assert parse_targets("gltf") == ["gltf"]


def test_a_glb_or_gltf_name_is_taken_and_anything_else_refused(tmp_path, capsys):
    base = ["export", "--model", "eon", "--to", "gltf", "-o"]
    assert main([*base, str(tmp_path / "a.GLB")]) == 0
    assert _read(tmp_path / "a.GLB")[0]["asset"]["version"] == "2.0"  # binary
    assert main([*base, str(tmp_path / "a.obj")]) == 2
    assert ".gltf" in capsys.readouterr().err
