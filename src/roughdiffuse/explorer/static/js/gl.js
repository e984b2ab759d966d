// WebGL2 plumbing: shader sources (fetched from ../glsl/), the BRDF evaluator that renders
// geometries to a float texture and reads them back, and the lit-sphere renderer.

const HEADER = "#version 300 es\nprecision highp float;\nprecision highp int;\n";

/** Fetch the GLSL sources the page needs (relative to this module). */
export async function loadSources() {
  const names = ["brdf.glsl", "fullscreen.vert", "evaluate.frag", "sphere.frag"];
  const texts = await Promise.all(
    names.map(async (n) => {
      const r = await fetch(new URL(`../glsl/${n}`, import.meta.url));
      if (!r.ok) throw new Error(`cannot load glsl/${n}: HTTP ${r.status}`);
      return r.text();
    }),
  );
  return Object.fromEntries(names.map((n, k) => [n, texts[k]]));
}

function compile(gl, type, source, label) {
  const sh = gl.createShader(type);
  gl.shaderSource(sh, source);
  gl.compileShader(sh);
  if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) {
    throw new Error(`GLSL ${label}: ${gl.getShaderInfoLog(sh)}`);
  }
  return sh;
}

/**
 * The program of `fragName` over brdf.glsl holding the models numbered `models` alone (their
 * GLSL ids: RD_MODEL_A and RD_MODEL_B, see brdf.glsl). A software renderer compiles a program
 * for one or two models in a fraction of the time it takes for all of them.
 */
function program(gl, src, fragName, models) {
  const p = gl.createProgram();
  gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, HEADER + src["fullscreen.vert"], "fullscreen.vert"));
  const [a, b = a] = models;
  const select = `#define RD_MODEL_A ${a}\n#define RD_MODEL_B ${b}\n`;
  const frag = HEADER + select + src["brdf.glsl"] + "\n" + src[fragName];
  gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, frag, fragName));
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
    throw new Error(`GLSL link ${fragName}: ${gl.getProgramInfoLog(p)}`);
  }
  return p;
}

/** Programs of one fragment shader, compiled on first use for each set of models and kept. */
class Programs {
  constructor(gl, src, fragName) {
    Object.assign(this, { gl, src, fragName, byKey: new Map() });
  }

  for(...models) {
    const key = models.join(",");
    let p = this.byKey.get(key);
    if (!p) {
      p = program(this.gl, this.src, this.fragName, models);
      this.byKey.set(key, p);
    }
    return p;
  }
}

const ZERO3 = new Float32Array(3);

/** Set the uniform struct `name` (RDParams) from a GPU parameter record (see models.js). */
function setParams(gl, prog, name, g) {
  const loc = (f) => gl.getUniformLocation(prog, `${name}.${f}`);
  gl.uniform1i(loc("model"), g.model);
  gl.uniform3fv(loc("albedo"), g.albedo);
  gl.uniform1f(loc("sigma"), g.sigma);
  gl.uniform1f(loc("roughness"), g.roughness);
  gl.uniform1f(loc("eta"), g.eta);
  gl.uniform1f(loc("weight"), g.weight);
  gl.uniform1f(loc("limb"), g.limb);
  gl.uniform1i(loc("distribution"), g.distribution);
  gl.uniform1f(loc("alpha"), g.alpha);
  gl.uniform1i(loc("variant"), g.variant);
  gl.uniform1f(loc("k"), g.k);
  gl.uniform1f(loc("b0"), g.b0);
  gl.uniform1f(loc("h"), g.h);
  gl.uniform1f(loc("g"), g.g);
  gl.uniform1f(loc("theta_bar"), g.theta_bar);
  gl.uniform1f(loc("hg2"), g.hg2);
  gl.uniform3fv(loc("absorption"), g.absorption);
  gl.uniform3fv(loc("coat_k"), g.coat_k ?? ZERO3);
  gl.uniform3fv(loc("coat_ak"), g.coat_ak ?? ZERO3);
  gl.uniform1i(loc("base"), g.base ?? 2);
  gl.uniform1f(loc("base_roughness"), g.base_roughness ?? 0);
}

/**
 * Evaluates the GLSL BRDF on arrays of local cosines, off screen.
 * evaluate(params, cosines) with cosines a Float32Array of (mu_i, mu_o, cos_io) triples
 * returns a Float32Array of (r, g, b) BRDF values, one triple per geometry.
 */
export class Evaluator {
  constructor(src) {
    const canvas = document.createElement("canvas");
    canvas.width = canvas.height = 1;
    const gl = canvas.getContext("webgl2");
    if (!gl) throw new Error("WebGL2 is not available in this browser");
    if (!gl.getExtension("EXT_color_buffer_float")) {
      throw new Error("WebGL2 float render targets (EXT_color_buffer_float) are not available");
    }
    this.gl = gl;
    this.programs = new Programs(gl, src, "evaluate.frag");
    this.width = 256;
  }

  evaluate(params, cosines) {
    const n = cosines.length / 3;
    const w = Math.min(this.width, Math.max(n, 1));
    const h = Math.max(1, Math.ceil(n / w));
    const input = new Float32Array(w * h * 4);
    for (let k = 0; k < n; k++) {
      input[4 * k] = cosines[3 * k];
      input[4 * k + 1] = cosines[3 * k + 1];
      input[4 * k + 2] = cosines[3 * k + 2];
    }
    const out = this.run(this.withSums(params), input, w, h);
    const rgb = new Float32Array(3 * n);
    for (let k = 0; k < n; k++) {
      rgb[3 * k] = out[4 * k];
      rgb[3 * k + 1] = out[4 * k + 1];
      rgb[3 * k + 2] = out[4 * k + 2];
    }
    return rgb;
  }

  /** `params` with Coated's parameter-only sums K and a-bar K filled in (brdf.glsl rd_ct_sums,
   * run by the GLSL on two texels, kept for the last parameter set); other models as given. */
  withSums(params) {
    if (!params.sums) return params;
    const key = JSON.stringify(params, (k, v) => (ArrayBuffer.isView(v) ? Array.from(v) : v));
    if (this.sumsKey !== key) {
      const out = this.run(params, new Float32Array([0, 0, 0, 1, 0, 0, 0, 2]), 2, 1);
      this.sums = [out.slice(0, 3), out.slice(4, 7)];
      this.sumsKey = key;
    }
    return { ...params, coat_k: this.sums[0], coat_ak: this.sums[1] };
  }

  /** Draw evaluate.frag over a w x h texture of texels; the RGBA result. */
  run(params, input, w, h) {
    const gl = this.gl;
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, w, h, 0, gl.RGBA, gl.FLOAT, input);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    const target = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, target);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, w, h);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
    gl.viewport(0, 0, w, h);
    const prog = this.programs.for(params.model);
    gl.useProgram(prog);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.uniform1i(gl.getUniformLocation(prog, "u_geometry"), 0);
    setParams(gl, prog, "u_p", params);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = new Float32Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, out);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteFramebuffer(fb);
    gl.deleteTexture(tex);
    gl.deleteTexture(target);
    return out;
  }
}

/** The lit sphere(s) on a visible canvas. */
export class SphereView {
  constructor(canvas, src) {
    const gl = canvas.getContext("webgl2", { preserveDrawingBuffer: true, antialias: false });
    if (!gl) throw new Error("WebGL2 is not available in this browser");
    this.canvas = canvas;
    this.gl = gl;
    this.programs = new Programs(gl, src, "sphere.frag");
  }

  /** mode: 0 A only, 1 A | B, 2 A - B; light: unit vector; exposure: multiplier. */
  draw(a, b, mode, light, exposure) {
    const gl = this.gl;
    const c = this.canvas;
    gl.viewport(0, 0, c.width, c.height);
    const prog = this.programs.for(a.model, b.model);
    gl.useProgram(prog);
    setParams(gl, prog, "u_a", a);
    setParams(gl, prog, "u_b", b);
    gl.uniform1i(gl.getUniformLocation(prog, "u_mode"), mode);
    gl.uniform3fv(gl.getUniformLocation(prog, "u_light"), light);
    gl.uniform1f(gl.getUniformLocation(prog, "u_exposure"), exposure);
    gl.uniform2f(gl.getUniformLocation(prog, "u_size"), c.width, c.height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }
}
