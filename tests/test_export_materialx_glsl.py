"""MaterialX's own shader code for the exported ``.mtlx``, run on the GPU path and compared
with roughdiffuse's MaterialX variants.

MaterialX's ESSL generator (``EsslShaderGenerator``, GLSL ES 3.0 for WebGL 2) turns the
exported document into a fragment shader; its uniforms get the values MaterialX's own shader
reflection gives them (the document's inputs). The shader's ``main`` is replaced by one that
calls the BSDF exactly as the generated light loop does (the same line, cut from it) for a
texture of (L, V) pairs with N = +z, and writes ``bsdf.response`` = f(L, V) · N·L to an
RGBA32F target, read back in headless Chromium (WebGL 2 through SwiftShader: float32).

Compared with ``materialx-eon`` (``energy_compensation`` true) and ``materialx-oren-nayar``
(false) evaluated in float64 at the float32 directions, times N·L clamped to [1e-8, 1] as the
node clamps it. Tolerance 1e-4 relative + 1e-7: float32 arithmetic, as for the explorer's own
GLSL (tests/test_explorer_glsl.py). Measured largest relative differences: 1.3e-5 (EON node,
r = 0.6), 2.7e-5 (white, r = 1: MaterialX's Fujii albedo computes (S/μ)(1 − S³) directly,
which loses S³'s last bits in float32 near grazing), 2e-7 (qualitative Oren–Nayar).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from explorer_browser import PageWithLog
from materialx_setup import load_document
from roughdiffuse import registry
from roughdiffuse.exporters import export

RTOL = 1e-4
ATOL = 1e-7

PAGE_JS = """
([frag, uniforms, lights, views]) => {
  const canvas = document.createElement("canvas");
  const gl = canvas.getContext("webgl2");
  if (!gl || !gl.getExtension("EXT_color_buffer_float")) return "no WebGL2 float targets";
  const compile = (type, src) => {
    const s = gl.createShader(type); gl.shaderSource(s, src); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  const vert = "#version 300 es\\nvoid main() { vec2 p = vec2((gl_VertexID << 1) & 2, " +
    "gl_VertexID & 2); gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0); }";
  const prog = gl.createProgram();
  gl.attachShader(prog, compile(gl.VERTEX_SHADER, vert));
  gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, frag));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  gl.useProgram(prog);
  const n = lights.length / 3;
  const texture = (unit, data) => {
    const rgba = new Float32Array(4 * n);
    for (let k = 0; k < n; k++) for (let j = 0; j < 3; j++) rgba[4 * k + j] = data[3 * k + j];
    const t = gl.createTexture(); gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, n, 1, 0, gl.RGBA, gl.FLOAT, rgba);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  };
  texture(0, lights); texture(1, views);
  gl.uniform1i(gl.getUniformLocation(prog, "rd_light"), 0);
  gl.uniform1i(gl.getUniformLocation(prog, "rd_view"), 1);
  for (const [name, type, value] of uniforms) {
    const loc = gl.getUniformLocation(prog, name);
    if (type === "float") gl.uniform1f(loc, value);
    else if (type === "boolean" || type === "integer") gl.uniform1i(loc, value);
    else gl.uniform3fv(loc, value);
  }
  const target = gl.createTexture(); gl.activeTexture(gl.TEXTURE2);
  gl.bindTexture(gl.TEXTURE_2D, target); gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, n, 1);
  const fb = gl.createFramebuffer(); gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  gl.viewport(0, 0, n, 1); gl.drawArrays(gl.TRIANGLES, 0, 3);
  const out = new Float32Array(4 * n); gl.readPixels(0, 0, n, 1, gl.RGBA, gl.FLOAT, out);
  return Array.from(out);
}
"""

MAIN = """
uniform highp sampler2D rd_light;
uniform highp sampler2D rd_view;
void main()
{
    ivec2 texel = ivec2(gl_FragCoord.xy);
    vec3 N = vec3(0.0, 0.0, 1.0);
    vec3 geomprop_Nworld_out1 = N;
    vec3 L = texelFetch(rd_light, texel, 0).xyz;
    vec3 V = texelFetch(rd_view, texel, 0).xyz;
    ClosureData closureData = makeClosureData(CLOSURE_TYPE_REFLECTION, L, V, N, vec3(0.0), 1.0);
    BSDF diffuse_bsdf_out = BSDF(vec3(0.0), vec3(1.0));
    CALL
    out1 = vec4(diffuse_bsdf_out.response, 1.0);
}
"""


def _shader(mtlx) -> tuple[str, list]:
    """MaterialX's ESSL for the document, its main replaced, and its uniforms' values."""
    mx, doc, search = load_document(mtlx)
    import MaterialX.PyMaterialXGenGlsl as mgl
    import MaterialX.PyMaterialXGenShader as mgs

    (elem,) = mgs.findRenderableElements(doc)
    gen = mgl.EsslShaderGenerator.create()
    ctx = mgs.GenContext(gen)
    ctx.registerSourceCodeSearchPath(search)
    shader = gen.generate("roughdiffuse", elem, ctx)
    code = shader.getSourceCode(mgs.PIXEL_STAGE)
    head, main = code.split("void main()", 1)
    (call,) = set(re.findall(r"mx_oren_nayar_diffuse_bsdf\(closureData, [^;]*\);", main))
    uniforms = []
    block = shader.getStage(mgs.PIXEL_STAGE).getUniformBlock(mgs.HW_PUBLIC_UNIFORMS)
    for k in range(block.size()):
        port = block[k]
        value = port.getValue()
        if value is None or port.getVariable() not in call:
            continue
        v = value.getData()
        uniforms.append(
            [port.getVariable(), value.getTypeString(), list(v) if hasattr(v, "__len__") else v]
        )
    return head + MAIN.replace("CALL", call), uniforms


def _directions() -> tuple[np.ndarray, np.ndarray]:
    """(L, V) unit vectors in float32, N = +z: a grid from near grazing to normal over Δφ in
    [0°, 180°], and random pairs."""
    mus = np.array([1e-3, 0.01, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 0.95, 0.99, 1.0])
    dphi = np.radians([0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0])
    mi, mo, dp = (a.ravel() for a in np.meshgrid(mus, mus, dphi, indexing="ij"))
    rng = np.random.default_rng(5)
    mi = np.concatenate([mi, rng.uniform(0.01, 1.0, 200)])
    mo = np.concatenate([mo, rng.uniform(0.01, 1.0, 200)])
    dp = np.concatenate([dp, rng.uniform(0.0, math.pi, 200)])
    si, so = np.sqrt(1 - mi**2), np.sqrt(1 - mo**2)
    light = np.stack([si, np.zeros_like(si), mi], -1)
    view = np.stack([so * np.cos(dp), so * np.sin(dp), mo], -1)
    return light.astype(np.float32), view.astype(np.float32)


@pytest.fixture(scope="module")
def page(browser):
    """A blank page of the session's Chromium (the explorer is not needed: the shader is
    MaterialX's)."""
    log = PageWithLog(browser.new_page())
    yield log
    log.page.close()


@pytest.mark.parametrize(
    "model_id, params",
    [
        ("materialx-eon", {"albedo": [0.8, 0.5, 0.2], "roughness": 0.6}),
        ("materialx-eon", {"albedo": [1.0, 1.0, 1.0], "roughness": 1.0}),
        ("materialx-oren-nayar", {"albedo": [0.8, 0.5, 0.2], "roughness": 0.4}),
    ],
    ids=["eon-0.6", "eon-white-1", "oren-nayar-0.4"],
)
def test_materialx_generated_glsl_equals_the_materialx_variant(page, tmp_path, model_id, params):
    model = registry.create(model_id, **params)
    result = export(model, "materialx", tmp_path / "m.mtlx")
    assert result.conversion is None  # exact: the node is the model
    frag, uniforms = _shader(tmp_path / "m.mtlx")
    assert {u[0].rsplit("_", 1)[-1] for u in uniforms} >= {"color", "roughness"}
    light, view = _directions()
    got = page.page.evaluate(
        PAGE_JS, [frag, uniforms, light.ravel().tolist(), view.ravel().tolist()]
    )
    assert not isinstance(got, str), got
    got = np.asarray(got, dtype=np.float64).reshape(-1, 4)[:, :3]
    l64, v64 = light.astype(np.float64), view.astype(np.float64)
    l64 /= np.linalg.norm(l64, axis=-1, keepdims=True)
    v64 /= np.linalg.norm(v64, axis=-1, keepdims=True)
    mu_i, mu_o, cos_io = l64[:, 2], v64[:, 2], np.sum(l64 * v64, axis=-1)
    f = np.asarray(model.brdf_cosines(mu_i, mu_o, cos_io)).reshape(len(mu_i), -1)
    expected = f * np.clip(mu_i, 1e-8, 1.0)[:, None]
    err = np.abs(got - expected)
    worst = float(np.max(err / (np.abs(expected) + ATOL / RTOL)))
    assert np.all(err <= RTOL * np.abs(expected) + ATOL), f"largest relative difference {worst:.3g}"
    assert not page.errors, page.errors
