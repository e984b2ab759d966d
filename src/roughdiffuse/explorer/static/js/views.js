// The views of the plots column, as the Disney BRDF Explorer has them: the plane of incidence
// (Cartesian and polar, drawn by main.js), a 3-D lobe for the current light, the directional
// albedo against θo (the white furnace) and the θh/θd image slice; a log-scale option and a
// hover readout of the values. Every BRDF value comes from the GLSL evaluator (gl.js, the one
// JS-side copy of the formulas); this module only chooses geometries, integrates and draws.
// Each view's drawer returns the table its CSV export writes: {columns, rows}.

import { canvasSize, drawCartesian, prepare } from "./plot.js";

const DEG = Math.PI / 180;
const E0 = Math.PI; // irradiance, as in sphere.frag and main.js
export const VIEWS = ["plane", "polar", "lobe", "albedo", "slice", "scatter"]; // scatter: data.js
const COLORS = { a: "#1f5fa8", b: "#d35400" };

const mean3 = (f, k) => (f[3 * k] + f[3 * k + 1] + f[3 * k + 2]) / 3;

/** Local cosines (mu_i, mu_o, cos_io) of unit vectors wi, wo (z is the normal). */
function pushCosines(out, wi, wo) {
  out.push(wi[2], wo[2], wi[0] * wo[0] + wi[1] * wo[1] + wi[2] * wo[2]);
}

// ------------------------------------------------------------------ 3-D lobe
export const LOBE_THETA = 5; // degrees between rings of the lobe's wireframe
export const LOBE_PHI = 10; // degrees between its meridians

/** Radiance L = f E0 cos θi towards every (θo, φo) of the lobe grid, mean of RGB. */
function lobeValues(evaluator, params, light) {
  const cos = [];
  const grid = [];
  for (let t = 0; t <= 90; t += LOBE_THETA) {
    for (let p = 0; p < 360; p += LOBE_PHI) {
      const wo = [Math.sin(t * DEG) * Math.cos(p * DEG), Math.sin(t * DEG) * Math.sin(p * DEG), Math.cos(t * DEG)];
      grid.push([t, p, wo]);
      pushCosines(cos, light, wo);
    }
  }
  const f = evaluator.evaluate(params, Float32Array.from(cos));
  const lum = Math.max(light[2], 0) * E0;
  return grid.map(([t, p, wo], k) => ({ t, p, wo, L: mean3(f, k) * lum }));
}

/** The lobe as a wireframe, orthographic, turned by view.yaw (about the normal) and tilted by
 *  view.pitch (0: seen from the side, π/2: from above). */
export function drawLobe(canvas, evaluator, slots, light, view) {
  const ctx = prepare(canvas);
  const { W, H } = canvasSize(canvas);
  const lobes = slots.map((s) => ({ ...s, v: lobeValues(evaluator, s.params, light) }));
  let lmax = 0;
  for (const l of lobes) for (const q of l.v) if (Number.isFinite(q.L)) lmax = Math.max(lmax, q.L);
  if (!(lmax > 0)) lmax = 1;
  const scale = 0.58 * Math.min(W / 2, H);
  const cy = Math.cos(view.yaw), sy = Math.sin(view.yaw), cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
  const project = ([x, y, z], r) => {
    const u = cy * x - sy * y, w = sy * x + cy * y; // turn about the normal
    const depthY = cp * w - sp * z, up = sp * w + cp * z; // tilt: the far side rises
    return [W / 2 + (u * r * scale) / lmax, H * 0.72 - (up * r * scale) / lmax, depthY];
  };
  // the surface: a disc of radius lmax, its axes and the normal
  ctx.strokeStyle = "#ccc";
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let p = 0; p <= 360; p += 5) {
    const [x, y] = project([Math.cos(p * DEG), Math.sin(p * DEG), 0], lmax);
    p ? ctx.lineTo(x, y) : ctx.moveTo(x, y);
  }
  ctx.stroke();
  for (const axis of [[1, 0, 0], [0, 1, 0], [0, 0, 1]]) {
    const [x0, y0] = project([0, 0, 0], 0);
    const [x1, y1] = project(axis, lmax);
    ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(x1, y1); ctx.stroke();
  }
  // the light's direction
  const [lx, ly] = project(light, lmax);
  const [ox, oy] = project([0, 0, 0], 0);
  ctx.strokeStyle = "#d9a400";
  ctx.setLineDash([3, 3]);
  ctx.beginPath(); ctx.moveTo(ox, oy); ctx.lineTo(lx, ly); ctx.stroke();
  ctx.setLineDash([]);
  ctx.fillStyle = "#b08000";
  ctx.fillText("light", lx + 4, ly);
  const nt = 90 / LOBE_THETA + 1, np = 360 / LOBE_PHI;
  for (const l of lobes) {
    ctx.strokeStyle = l.color;
    ctx.lineWidth = 1;
    const at = (i, j) => {
      const q = l.v[i * np + (j % np)];
      return project(q.wo, Number.isFinite(q.L) ? Math.max(q.L, 0) : 0);
    };
    for (let i = 0; i < nt; i++) { // rings
      ctx.beginPath();
      for (let j = 0; j <= np; j++) { const [x, y] = at(i, j); j ? ctx.lineTo(x, y) : ctx.moveTo(x, y); }
      ctx.stroke();
    }
    for (let j = 0; j < np; j++) { // meridians
      ctx.beginPath();
      for (let i = 0; i < nt; i++) { const [x, y] = at(i, j); i ? ctx.lineTo(x, y) : ctx.moveTo(x, y); }
      ctx.stroke();
    }
  }
  ctx.fillStyle = "#222";
  ctx.fillText(`3-D lobe: radius L(θo, φo) for the current light (E0 = π, mean of RGB); largest ${lmax.toPrecision(3)}`, 8, 16);
  ctx.fillStyle = "#666";
  ctx.fillText("drag to turn", 8, H - 8);
  const lw = Math.max(0, ...lobes.map((l) => ctx.measureText(l.label).width));
  lobes.forEach((l, k) => { ctx.fillStyle = l.color; ctx.fillText(l.label, W - lw - 8, 34 + 16 * k); });
  const rows = [];
  for (const l of lobes) for (const q of l.v) rows.push([l.label, q.t, q.p, q.L]);
  return { columns: ["series", "theta_o_deg", "phi_o_deg", "radiance"], rows };
}

// ------------------------------------------------------------------ directional albedo
export const ALBEDO_THETA = Array.from({ length: 45 }, (_, k) => 2 * k); // θo, degrees
export const ALBEDO_NODES = 48; // midpoint nodes in μi and in φi over [0, π]

/**
 * a(θo) = ∫ f(wi, wo) cos θi dωi over the hemisphere, mean of RGB: the midpoint rule in
 * μi = cos θi on [0, 1] and in φi on [0, π], doubled (f is even in φ for these isotropic
 * models). Exact for a constant f (Lambert: a = ρ); a smooth f converges as 1/N².
 */
export function albedoCurve(evaluator, params, thetas = ALBEDO_THETA, n = ALBEDO_NODES) {
  const cos = new Float32Array(3 * thetas.length * n * n);
  let k = 0;
  for (const t of thetas) {
    const wo = [Math.sin(t * DEG), 0, Math.cos(t * DEG)];
    for (let i = 0; i < n; i++) {
      const mu = (i + 0.5) / n, s = Math.sqrt(1 - mu * mu);
      for (let j = 0; j < n; j++) {
        const p = ((j + 0.5) / n) * Math.PI;
        cos[k++] = mu;
        cos[k++] = wo[2];
        cos[k++] = s * Math.cos(p) * wo[0] + mu * wo[2];
      }
    }
  }
  const f = evaluator.evaluate(params, cos);
  const w = (1 / n) * (Math.PI / n) * 2;
  return thetas.map((_, m) => {
    let a = 0;
    for (let i = 0; i < n; i++) {
      const mu = (i + 0.5) / n;
      for (let j = 0; j < n; j++) a += mean3(f, (m * n + i) * n + j) * mu;
    }
    return a * w;
  });
}

export function drawAlbedo(canvas, evaluator, slots, log) {
  const series = slots.map((s) => ({ label: s.label, color: s.color, dash: s.dash, x: ALBEDO_THETA, y: albedoCurve(evaluator, s.params) }));
  series.push({ label: "1 (energy conserved, nothing absorbed)", color: "#999", dash: true, x: [0, 88], y: [1, 1] });
  drawCartesian(canvas, series, {
    title: "directional albedo a(θo) = ∫ f cos θi dωi (white furnace)", ylabel: "a, mean of RGB", log,
    xmin: 0, xmax: 90, xstep: 15, xlabel: "θo (degrees)",
  });
  const rows = [];
  for (const s of series.slice(0, -1)) s.x.forEach((x, k) => rows.push([s.label, x, s.y[k]]));
  return { columns: ["series", "theta_o_deg", "albedo"], rows };
}

// ------------------------------------------------------------------ θh/θd slice
export const SLICE_N = 64; // pixels per axis, θh and θd from 0 to 90°

/**
 * f(θh, θd) at φd = 90° (Rusinkiewicz's half/difference angles, the Disney explorer's image
 * slice): wi = (cos θd sin θh, sin θd, cos θd cos θh), wo its mirror about h, so
 * μi = μo = cos θd cos θh and cos_io = cos 2θd. Cell centres, mean of RGB.
 */
function sliceValues(evaluator, params) {
  const n = SLICE_N;
  const cos = new Float32Array(3 * n * n);
  for (let i = 0; i < n; i++) { // θd, rows
    const td = ((i + 0.5) / n) * 90 * DEG;
    for (let j = 0; j < n; j++) { // θh, columns
      const th = ((j + 0.5) / n) * 90 * DEG;
      const k = 3 * (i * n + j);
      cos[k] = cos[k + 1] = Math.cos(td) * Math.cos(th);
      cos[k + 2] = Math.cos(2 * td);
    }
  }
  const f = evaluator.evaluate(params, cos);
  return Array.from({ length: n * n }, (_, k) => mean3(f, k));
}

/** A perceptual dark-to-bright colour map (a few stops of viridis, linearly between). */
const STOPS = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
export function colormap(t) {
  const x = Math.min(Math.max(t, 0), 1) * (STOPS.length - 1);
  const k = Math.min(Math.floor(x), STOPS.length - 2), u = x - k;
  return STOPS[k].map((c, m) => Math.round(c + u * (STOPS[k + 1][m] - c)));
}

export function drawSlice(canvas, evaluator, slots, log) {
  const ctx = prepare(canvas);
  const { W, H } = canvasSize(canvas);
  const n = SLICE_N;
  const images = slots.map((s) => ({ ...s, f: sliceValues(evaluator, s.params) }));
  let hi = 0, lo = Infinity;
  for (const im of images) for (const v of im.f) if (Number.isFinite(v)) { hi = Math.max(hi, v); if (v > 0) lo = Math.min(lo, v); }
  if (!(hi > 0)) hi = 1;
  lo = Math.max(Number.isFinite(lo) ? lo : hi / 1e4, hi / 1e4);
  const t = (v) => (log ? (Math.log10(Math.max(v, lo)) - Math.log10(lo)) / Math.max(Math.log10(hi / lo), 1e-6) : v / hi);
  const size = Math.min(H - 64, (W - 120) / images.length - 16);
  const boxes = [];
  images.forEach((im, m) => {
    const x0 = 40 + m * (size + 24), y0 = 30;
    const img = ctx.createImageData(n, n);
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        const c = colormap(t(im.f[i * n + j]));
        const o = 4 * ((n - 1 - i) * n + j); // θd grows upwards
        img.data.set([...c, 255], o);
      }
    }
    const tmp = document.createElement("canvas");
    tmp.width = tmp.height = n;
    tmp.getContext("2d").putImageData(img, 0, 0);
    ctx.imageSmoothingEnabled = false;
    ctx.drawImage(tmp, x0, y0, size, size);
    ctx.fillStyle = "#222";
    ctx.fillText(im.label, x0, y0 - 6);
    ctx.fillStyle = "#444";
    ctx.fillText("θh →", x0 + size - 30, y0 + size + 14);
    ctx.fillText("0°", x0, y0 + size + 14);
    ctx.save(); ctx.translate(x0 - 6, y0 + size); ctx.rotate(-Math.PI / 2); ctx.fillText("θd →  (0° to 90°)", 0, 0); ctx.restore();
    boxes.push({ x0, y0, size, label: im.label, f: im.f });
  });
  // the colour scale
  const bx = W - 70, by = 30, bh = size;
  for (let y = 0; y < bh; y++) {
    const c = colormap(1 - y / (bh - 1));
    ctx.fillStyle = `rgb(${c[0]},${c[1]},${c[2]})`;
    ctx.fillRect(bx, by + y, 14, 1);
  }
  ctx.fillStyle = "#222";
  for (let k = 0; k <= 4; k++) {
    const u = k / 4;
    const v = log ? lo * Math.pow(hi / lo, u) : hi * u;
    ctx.fillText(v.toPrecision(2), bx + 18, by + bh - u * (bh - 1) + 4);
  }
  ctx.fillText(log ? "f (1/sr), log" : "f (1/sr)", bx - 10, by - 6);
  ctx.fillText("θh/θd slice at φd = 90° (Rusinkiewicz angles): f, mean of RGB", 8, H - 8);
  canvas.rdSlice = { boxes, n };
  const rows = [];
  for (const b of boxes) {
    for (let i = 0; i < n; i++) for (let j = 0; j < n; j++) rows.push([b.label, ((j + 0.5) / n) * 90, ((i + 0.5) / n) * 90, b.f[i * n + j]]);
  }
  return { columns: ["series", "theta_h_deg", "theta_d_deg", "brdf"], rows };
}

// ------------------------------------------------------------------ hover readouts
const fmt = (v) => (Number.isFinite(v) ? v.toPrecision(4) : "–");

/** The text of the readout for a pointer at canvas pixel (x, y), or null outside the plot. */
export function readoutAt(canvas, x, y) {
  const p = canvas.rdPlot;
  if (p && x >= p.left && x <= p.right && y >= p.top && y <= p.bottom) {
    const xv = p.xmin + ((x - p.left) / (p.right - p.left)) * (p.xmax - p.xmin);
    const parts = [];
    for (const s of p.series) {
      if (!s.x.length || s.x.length < 2 && !s.points) continue;
      let best = 0;
      s.x.forEach((v, k) => { if (Math.abs(v - xv) < Math.abs(s.x[best] - xv)) best = k; });
      if (Math.abs(s.x[best] - xv) > (p.xmax - p.xmin) / 30) continue;
      parts.push(`${s.label.split(":")[0]} ${fmt(s.y[best])} (at ${s.x[best].toFixed(1)}°)`);
    }
    return `${p.xmin < 0 ? "θr" : "θo"} = ${xv.toFixed(1)}°: ${parts.join("; ")}`;
  }
  if (canvas.id === "plot-lobe") return "3-D lobe: drag to turn it";
  const sl = canvas.rdSlice;
  if (sl) {
    for (const b of sl.boxes) {
      if (x >= b.x0 && x < b.x0 + b.size && y >= b.y0 && y < b.y0 + b.size) {
        const j = Math.floor(((x - b.x0) / b.size) * sl.n), i = sl.n - 1 - Math.floor(((y - b.y0) / b.size) * sl.n);
        return `${b.label}: θh = ${(((j + 0.5) / sl.n) * 90).toFixed(1)}°, θd = ${(((i + 0.5) / sl.n) * 90).toFixed(1)}°, f = ${fmt(b.f[i * sl.n + j])} 1/sr`;
      }
    }
  }
  const po = canvas.rdPolar;
  if (po) {
    const dx = x - po.cx, dy = po.cy - y;
    if (dy < 0 || Math.hypot(dx, dy) > po.R * 1.1) return null;
    const ang = Math.atan2(dx, dy) / DEG;
    const parts = [];
    for (const s of po.series) {
      if (s.points || !s.x.length) continue;
      let best = 0;
      s.x.forEach((v, k) => { if (Math.abs(v - ang) < Math.abs(s.x[best] - ang)) best = k; });
      parts.push(`${s.label.split(":")[0]} ${fmt(s.y[best])}`);
    }
    return `θr = ${ang.toFixed(1)}°: ${parts.join("; ")}`;
  }
  return null;
}

let hover = null; // the last pointer position over a plot: {canvas, x, y (layout pixels), out}

/** Show the readout of whatever plot the pointer is over in `out`. */
export function setupHover(canvases, out) {
  for (const c of canvases) {
    c.addEventListener("pointermove", (ev) => {
      const r = c.getBoundingClientRect();
      const { W, H } = canvasSize(c);
      hover = { canvas: c, x: ((ev.clientX - r.left) * W) / r.width, y: ((ev.clientY - r.top) * H) / r.height, out };
      rereadHover();
    });
  }
}

/** Read the plot again at the last pointer position: called after every redraw, so that the
 *  readout follows a new light, model or dataset without moving the pointer. */
export function rereadHover() {
  if (!hover || hover.canvas.hidden) return;
  const text = readoutAt(hover.canvas, hover.x, hover.y);
  if (text !== null) hover.out.textContent = text;
}

// ------------------------------------------------------------------ lobe rotation
export function setupLobeDrag(canvas, view, redraw) {
  let last = null;
  canvas.addEventListener("pointerdown", (ev) => { canvas.setPointerCapture(ev.pointerId); last = [ev.clientX, ev.clientY]; });
  canvas.addEventListener("pointerup", () => { last = null; });
  canvas.addEventListener("pointermove", (ev) => {
    if (!last || !(ev.buttons & 1)) return;
    view.yaw += (ev.clientX - last[0]) * 0.01;
    view.pitch = Math.min(Math.PI / 2, Math.max(0, view.pitch + (ev.clientY - last[1]) * 0.01));
    last = [ev.clientX, ev.clientY];
    redraw();
  });
}

export { COLORS };
