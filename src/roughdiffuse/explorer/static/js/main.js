// The explorer page: two model slots (A, B), a lit sphere, plane-of-incidence plots, presets,
// measured data with fits (data.js, fitpanel.js) and (when the server has one) ground truth.

import { channelValue, dataSeries, drawScatterOf, onLight, selection, setSelection, setupData, sliceCosines, sliceLabel } from "./data.js";
import { setupFit } from "./fitpanel.js";
import { Evaluator, SphereView, loadSources } from "./gl.js";
import { BY_KEY, LEFT_OUT, MODELS, PARAMS, defaultState, gpuParams, loadModels } from "./models.js";
import { drawCartesian, drawPolar, drawScatter } from "./plot.js";
import { canvasBlob, download, toCsv } from "./export.js";
import { decodeState, encodeState } from "./urlstate.js";
import { VIEWS, drawAlbedo, drawLobe, drawSlice, setupHover, setupLobeDrag } from "./views.js";

const $ = (id) => document.getElementById(id);
const DEG = Math.PI / 180;
const E0 = Math.PI; // irradiance, as in sphere.frag

const state = {
  a: null, // defaultState("oren-nayar") once /api/models has been read
  b: null,
  mode: 0,
  light: { theta: 0, phi: 0 }, // degrees
  exposure: 0, // EV
  // view options: the plots column's view, log scale, ground truth shown and its bounces,
  // the 3-D lobe's turn (radians)
  view: { tab: "plane", log: false, gt: false, bounces: "all", yaw: -0.5, pitch: 0.35 },
};
let tables = {}; // the data each view plots, for the CSV export
let presetShown = null; // the state the chosen preset set, to tell when it becomes "custom"

let evaluator, sphere, info = { vase: false, groundtruth: false };
const panels = {};

// ------------------------------------------------------------------ model panels
function slider(parent, id, label, min, max, step, value, format) {
  const wrap = document.createElement("label");
  wrap.id = `${id}-row`;
  wrap.textContent = label;
  const out = document.createElement("output");
  out.id = `${id}-out`;
  const input = document.createElement("input");
  Object.assign(input, { type: "range", id, min, max, step, value });
  wrap.append(out, input);
  parent.append(wrap);
  const show = () => (out.textContent = format(Number(input.value)));
  input.addEventListener("input", show);
  show();
  return input;
}

/** The sliders and selects of one slot, built from the declarations of /api/models. */
function buildPanel(slot) {
  const root = $(`panel-${slot}`);
  const s = state[slot];
  const p = `${slot}-`;
  const sel = document.createElement("select");
  sel.id = `${p}model`;
  for (const m of MODELS) sel.append(new Option(m.label, m.key));
  root.append(sel);
  const f3 = (v) => v.toFixed(3);
  const ctl = { model: sel, sliders: {}, selects: {} };
  for (const [k, q] of Object.entries(PARAMS)) {
    if (q.channels) {
      const grey = document.createElement("label");
      grey.innerHTML = `<input type="checkbox" id="${p}grey" checked> grey ${k} (R = G = B)`;
      grey.id = `${p}grey-row`;
      root.append(grey);
      ctl.grey = grey.querySelector("input");
      ctl.channels = k;
      ctl.albedo = ["r", "g", "b"].map((c, j) => slider(root, `${p}${k}-${c}`, `${k} ${c.toUpperCase()}`, q.lo, q.hi, 0.005, s[k][j], f3));
    } else if (q.choices !== null) {
      const row = document.createElement("label");
      row.id = `${p}${k}-row`;
      row.textContent = `${q.description} `;
      const select = document.createElement("select");
      select.id = `${p}${k}`;
      for (const c of q.choices) select.append(new Option(c, c));
      row.append(select);
      root.append(row);
      ctl.selects[k] = select;
    } else if (q.unit === "radians") {
      const fmt = (v) => `${v.toFixed(1)}° = ${(v * DEG).toFixed(3)} rad`;
      ctl.sliders[k] = slider(root, `${p}${k}`, q.description, q.lo / DEG, q.hi / DEG, 0.5, s[`${k}Deg`], fmt);
    } else {
      const fmt = q.hi - q.lo > 1.5 ? (v) => v.toFixed(2) : f3;
      ctl.sliders[k] = slider(root, `${p}${k}`, q.description, q.lo, q.hi, 0.01, s[k], fmt);
    }
  }
  if (slot === "a" && LEFT_OUT.length) {
    const note = document.createElement("p");
    note.id = "models-left-out";
    note.textContent = "Not in the menus (no GLSL copy of the formula): " +
      LEFT_OUT.map((m) => m.key).join(", ") + ". `roughdiffuse render --model ID` renders them.";
    root.append(note);
  }
  panels[slot] = ctl;
  const onInput = (ev) => {
    if (ctl.grey && ctl.grey.checked && ev && ctl.albedo.includes(ev.target)) {
      for (const a of ctl.albedo) if (a !== ev.target) { a.value = ev.target.value; a.dispatchEvent(new Event("change")); }
    }
    readPanel(slot);
    refresh();
  };
  root.addEventListener("input", onInput);
  root.addEventListener("change", (ev) => { if (ev.isTrusted) onInput(ev); });
  writePanel(slot);
}

function readPanel(slot) {
  const c = panels[slot], s = state[slot];
  s.model = c.model.value;
  if (c.channels) s[c.channels] = c.albedo.map((a) => Number(a.value));
  for (const [k, el] of Object.entries(c.sliders)) {
    if (PARAMS[k].unit === "radians") s[`${k}Deg`] = Number(el.value);
    else s[k] = Number(el.value);
  }
  for (const [k, el] of Object.entries(c.selects)) s[k] = el.value;
  Object.assign(s, BY_KEY[s.model].fixed); // a choice the id fixes (Torrance–Sparrow's D)
  showUsed(slot);
}

function writePanel(slot) {
  const c = panels[slot], s = state[slot];
  c.model.value = s.model;
  if (c.channels) {
    const v = s[c.channels];
    c.albedo.forEach((a, k) => (a.value = v[k]));
    c.grey.checked = v[0] === v[1] && v[1] === v[2];
  }
  for (const [k, el] of Object.entries(c.sliders)) el.value = PARAMS[k].unit === "radians" ? s[`${k}Deg`] : s[k];
  for (const [k, el] of Object.entries(c.selects)) el.value = s[k];
  for (const el of [...(c.albedo ?? []), ...Object.values(c.sliders)]) el.dispatchEvent(new Event("input"));
  showUsed(slot);
}

/** Show the controls of the parameters the slot's model declares, hide the others. */
function showUsed(slot) {
  const c = panels[slot];
  const uses = BY_KEY[state[slot].model].uses;
  const p = `${slot}-`;
  for (const k of [...Object.keys(c.sliders), ...Object.keys(c.selects)]) $(`${p}${k}-row`).hidden = !uses.includes(k);
  if (c.channels) {
    for (const ch of ["r", "g", "b"]) $(`${p}${c.channels}-${ch}-row`).hidden = !uses.includes(c.channels);
    $(`${p}grey-row`).hidden = !uses.includes(c.channels);
  }
}

// ------------------------------------------------------------------ light
function lightVector() {
  const t = state.light.theta * DEG, f = state.light.phi * DEG;
  return [Math.sin(t) * Math.cos(f), Math.sin(t) * Math.sin(f), Math.cos(t)];
}

function setLight(theta, phi) {
  state.light.theta = Math.min(180, Math.max(0, theta));
  state.light.phi = phi;
  $("light-theta").value = state.light.theta;
  $("light-phi").value = phi;
  onLight(state.light.theta);
  refresh();
  gtSoon();
}

/** Drag on the sphere: inside the rim the light goes to the point under the pointer (that
 *  point is lit head-on); from the rim to twice its radius it moves on behind the sphere. */
function pointerToLight(ev) {
  const c = $("sphere"), rect = c.getBoundingClientRect();
  const sx = c.width / rect.width, sy = c.height / rect.height;
  let x = (ev.clientX - rect.left) * sx, y = c.height - (ev.clientY - rect.top) * sy;
  const w = state.mode === 1 ? c.width / 2 : c.width;
  if (state.mode === 1 && x >= w) x -= w;
  const radius = 0.46 * Math.min(w, c.height);
  const u = (x - w / 2) / radius, v = (y - c.height / 2) / radius;
  const r = Math.hypot(u, v);
  const theta = r <= 1 ? Math.asin(r) / DEG : Math.min(180, 90 + (r - 1) * 90);
  const phi = r > 0 ? Math.atan2(v, u) / DEG : state.light.phi;
  setLight(theta, Math.round(phi * 10) / 10);
}

// ------------------------------------------------------------------ drawing
let pending = false;
function refresh() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    try {
      draw();
    } catch (err) {
      showError(err);
    }
  });
}

function draw() {
  const c = $("sphere");
  const width = state.mode === 1 ? 960 : 480;
  if (c.width !== width) c.width = width;
  const a = gpuParams(state.a), b = gpuParams(state.b);
  sphere.draw(a, b, state.mode, lightVector(), Math.pow(2, state.exposure));
  $("light-readout").textContent = `light θ = ${state.light.theta.toFixed(1)}°, φ = ${state.light.phi.toFixed(1)}°`;
  $("panel-b").classList.toggle("disabled", state.mode === 0);
  $("label-a").hidden = $("label-b").hidden = state.mode !== 1;
  $("diff-legend").hidden = state.mode !== 2;
  if (state.mode === 2) drawDiffLegend();
  drawPlots(a, b);
  drawView(a, b);
  const shared = sharedState();
  if (presetShown !== null && JSON.stringify(shared.model) !== presetShown) {
    presetShown = null;
    $("preset").value = "custom";
  }
  const hash = encodeState(shared);
  if (location.hash !== hash) history.replaceState(null, "", hash);
}

/** What the URL keeps and a preset sets. */
function sharedState() {
  const model = { a: state.a, b: state.b, mode: state.mode, light: state.light, exposure: state.exposure };
  // the data slice's Δφ and channel (data.js) belong to the view as well
  return { ...model, view: { ...state.view, deltaPhi: selection.deltaPhi, channel: selection.channel }, model };
}

/** The slots the extra views draw: A, and B unless the page shows A only. */
function viewSlots(a, b) {
  const label = (slot) => `${slot.toUpperCase()}: ${BY_KEY[state[slot].model].short}`;
  const slots = [{ label: label("a"), color: "#1f5fa8", params: a }];
  if (state.mode !== 0) slots.push({ label: label("b"), color: "#d35400", dash: true, params: b });
  return slots;
}

/** Draw the plots column's current view (the plane views are drawn by drawPlots). */
function drawView(a, b) {
  if (state.view.tab === "scatter" && $("tab-scatter").hidden) state.view.tab = "plane"; // no CSV data
  const tab = state.view.tab;
  for (const v of VIEWS) $(`plot-${v === "plane" ? "cartesian" : v}`).hidden = v !== tab;
  for (const el of document.querySelectorAll("#view-tabs button")) el.setAttribute("aria-selected", String(el.dataset.view === tab));
  const slots = viewSlots(a, b);
  if (tab === "lobe") tables.lobe = drawLobe($("plot-lobe"), evaluator, slots, lightVector(), state.view);
  else if (tab === "albedo") tables.albedo = drawAlbedo($("plot-albedo"), evaluator, slots, state.view.log);
  else if (tab === "slice") tables.slice = drawSlice($("plot-slice"), evaluator, slots, state.view.log);
  document.body.dataset.view = tab;
}

/** The colour scale of the difference view, as sphere.frag maps A − B (after the exposure). */
function drawDiffLegend() {
  const c = $("diff-scale");
  const ctx = c.getContext("2d");
  const srgb = (v) => { v = Math.min(Math.max(v, 0), 1); return 255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(v, 1 / 2.4) - 0.055); };
  for (let x = 0; x < c.width; x++) {
    const s = (2 * (x + 0.5)) / c.width - 1; // -1 .. 1 after the exposure
    const rgb = s > 0 ? [s, 0.25 * s, 0] : [0, -0.4 * s, -s];
    ctx.fillStyle = `rgb(${rgb.map(srgb).join(",")})`;
    ctx.fillRect(x, 0, 1, c.height);
  }
  const m = 1 / Math.pow(2, state.exposure);
  $("diff-lo").textContent = `−${m.toPrecision(2)} (B brighter)`;
  $("diff-hi").textContent = `+${m.toPrecision(2)} (A brighter)`;
}

/** Radiance L = f E0 cos θi in the slice of data.js (Δφ = 0: the plane of incidence), θr from
 *  -90° to 90° (> 0: at Δφ, the light's side), in the channel data.js selects (or the mean). */
function planeCurve(params, thetaIDeg, thetaRDeg) {
  const f = evaluator.evaluate(params, sliceCosines(thetaIDeg, thetaRDeg));
  const lum = Math.max(Math.cos(thetaIDeg * DEG), 0) * E0;
  return thetaRDeg.map((_, k) => channelValue(f, k) * lum);
}

function drawPlots(a, b) {
  const thetaI = state.light.theta;
  const xs = Array.from({ length: 181 }, (_, k) => k - 90);
  const series = [];
  const label = (slot) => `${slot.toUpperCase()}: ${BY_KEY[state[slot].model].short}`;
  const lit = thetaI <= 90;
  series.push({ label: label("a"), color: "#1f5fa8", x: xs, y: lit ? planeCurve(a, thetaI, xs) : xs.map(() => 0) });
  if (state.mode !== 0) {
    series.push({ label: label("b"), color: "#d35400", dash: true, x: xs, y: lit ? planeCurve(b, thetaI, xs) : xs.map(() => 0) });
  }
  if (gtSeries && lit && selection.deltaPhi === 0) series.push(gtSeries); // solved in the plane only
  const data = lit ? dataSeries(thetaI) : null;
  if (data) series.push(data);
  const slice = sliceLabel();
  const title = lit ? `radiance ${slice.where}, θi = ${thetaI.toFixed(1)}°` : "light below the horizon";
  const drawn = drawCartesian($("plot-cartesian"), series, { title, ylabel: `L (E0 = π, ${slice.channel})`, log: state.view.log });
  const rows = [];
  for (const s of series) s.x.forEach((x, k) => rows.push([s.label, x, s.y[k]]));
  tables.plane = tables.polar = { columns: ["series", "theta_r_deg", "radiance"], rows };
  drawPolar($("plot-polar"), series, { title: "polar: radius L, angle θr", lightDeg: lit ? thetaI : null, log: state.view.log });
  document.body.dataset.csvPoints = String(data ? drawn : 0);
  tables.scatter = drawScatterOf(drawScatter);
}

// ------------------------------------------------------------------ presets, vase, ground truth
const PRESETS = {
  "on-vs-lambert": () => ({ a: { ...defaultState("oren-nayar"), sigmaDeg: 30 }, b: defaultState("lambert"), mode: 1, light: [0, 0] }),
  "full-moon": () => ({
    a: { ...defaultState("oren-nayar-full"), albedo: [0.12, 0.12, 0.12], sigmaDeg: 40 },
    b: { ...defaultState("lambert"), albedo: [0.12, 0.12, 0.12] },
    mode: 1, light: [0, 0], exposure: 2.5,
  }),
  highlights: () => ({
    a: { ...defaultState("mix"), albedo: [0.7, 0.25, 0.15], sigmaDeg: 4, weight: 0.5, eta: 2.5 },
    b: { ...defaultState("mix"), albedo: [0.7, 0.25, 0.15], sigmaDeg: 12, weight: 0.5, eta: 2.5 },
    mode: 1, light: [45, 30],
  }),
  "eon-vs-on": () => ({
    a: { ...defaultState("eon"), roughness: 1 },
    b: { ...defaultState("oren-nayar"), sigmaDeg: 40 },
    mode: 1, light: [75, 0],
  }),
  vase: () => ({ a: { ...defaultState("oren-nayar"), albedo: [0.75, 0.55, 0.4], sigmaDeg: 30 }, b: { ...defaultState("lambert"), albedo: [0.75, 0.55, 0.4] }, mode: 1, light: [0, 0] }),
};

function applyPreset(name) {
  const p = PRESETS[name]();
  state.a = p.a;
  state.b = p.b;
  state.mode = p.mode;
  state.exposure = p.exposure ?? 0;
  $("mode").value = String(p.mode);
  $("exposure").value = state.exposure;
  $("exposure").dispatchEvent(new Event("input"));
  writePanel("a");
  writePanel("b");
  setLight(p.light[0], p.light[1]);
  presetShown = JSON.stringify(sharedState().model);
  $("vase").hidden = name !== "vase";
  if (name === "vase") loadVase();
}

function queryFor(slot) {
  const s = state[slot];
  const q = new URLSearchParams({
    model: s.model, albedo: s.albedo.join(","), sigma: String(s.sigmaDeg * DEG), roughness: String(s.roughness),
    eta: String(s.eta), weight: String(s.weight), limb: String(s.limb), alpha: String(s.alpha), distribution: s.distribution,
    light_theta: String(state.light.theta), light_phi: String(state.light.phi), exposure: String(state.exposure),
  });
  return q.toString();
}

function loadVase() {
  $("vase-status").textContent = "rendering…";
  let left = 2;
  for (const slot of ["a", "b"]) {
    const img = $(`vase-${slot}`);
    img.onload = img.onerror = (ev) => {
      left -= 1;
      if (ev.type === "error") $("vase-status").textContent = "the server could not render the vase";
      else if (left === 0) $("vase-status").textContent = "";
    };
    img.src = `api/vase.png?${queryFor(slot)}`;
  }
}

let gtSeries = null;
let gtController = null;
let gtTimer = null;
/** Ask for ground truth once the inputs have been still for 300 ms. */
function gtSoon() {
  clearTimeout(gtTimer);
  gtTimer = setTimeout(() => loadGroundTruth().catch(showError), 300);
}
/** Ground truth from the server's V-cavity solver for model A's σ, ρ (green) and the light's θ. */
async function loadGroundTruth() {
  const status = $("gt-status");
  if (gtController) gtController.abort();
  gtController = null;
  const s = state.a;
  const reason = !info.groundtruth ? "this server has no V-cavity solver"
    : !state.view.gt ? ""
    : !["oren-nayar", "oren-nayar-full"].includes(s.model) ? "ground truth is shown for the Oren–Nayar models of A (a σ and Lambertian facets)"
    : !(s.sigmaDeg > 0) ? "σ = 0 is Lambert: nothing to compare"
    : !(state.light.theta < 90) ? "the light is below the horizon" : null;
  if (reason !== null) {
    status.textContent = reason;
    if (gtSeries) { gtSeries = null; refresh(); }
    return;
  }
  const q = new URLSearchParams({
    sigma: String(s.sigmaDeg * DEG), theta_i: String(state.light.theta), albedo: String(s.albedo[1]), bounces: state.view.bounces,
  });
  const controller = (gtController = new AbortController());
  status.textContent = "computing the V-cavity ground truth…";
  let gt;
  try {
    const r = await fetch(`api/groundtruth.json?${q}`, { signal: controller.signal });
    gt = await r.json();
    if (!r.ok) throw new Error(gt.error ?? `HTTP ${r.status}`);
  } catch (err) {
    if (err.name === "AbortError") return;
    gtSeries = null;
    status.textContent = `no ground truth: ${err.message}`;
    refresh();
    return;
  }
  if (controller !== gtController) return;
  const bounces = gt.bounces === "all" ? "all bounces" : "one bounce";
  gtSeries = { label: `V-cavity, ${bounces} (σ = ${(gt.sigma / DEG).toFixed(1)}°)`, color: "#1e8449", points: false, dash: true, x: gt.theta_r, y: gt.radiance };
  status.textContent = gt.note;
  document.body.dataset.gtPoints = String(gt.theta_r.length);
  refresh();
}

// ------------------------------------------------------------------ views, export, URL
/** View options from a shared URL, each checked. */
function restoreView(v) {
  const view = state.view;
  if (VIEWS.includes(v.tab)) view.tab = v.tab;
  if (typeof v.log === "boolean") view.log = v.log;
  if (typeof v.gt === "boolean") view.gt = v.gt;
  if (["1", "all"].includes(v.bounces)) view.bounces = v.bounces;
  for (const k of ["yaw", "pitch"]) if (Number.isFinite(v[k])) view[k] = v[k];
  view.pitch = Math.min(Math.PI / 2, Math.max(0, view.pitch));
}

function setupViews() {
  for (const el of document.querySelectorAll("#view-tabs button")) {
    el.addEventListener("click", () => { state.view.tab = el.dataset.view; refresh(); });
  }
  $("log-scale").checked = state.view.log;
  $("log-scale").addEventListener("change", (ev) => { state.view.log = ev.target.checked; refresh(); });
  $("gt-show").checked = state.view.gt;
  $("gt-show").addEventListener("change", (ev) => { state.view.gt = ev.target.checked; });
  $(`gt-bounces-${state.view.bounces}`).checked = true;
  for (const b of ["1", "all"]) $(`gt-bounces-${b}`).addEventListener("change", (ev) => { if (ev.target.checked) state.view.bounces = b; });
  setupHover(VIEWS.map((v) => $(`plot-${v === "plane" ? "cartesian" : v}`)), $("readout"));
  setupLobeDrag($("plot-lobe"), state.view, refresh);
  const base = () => `roughdiffuse-${state.view.tab}-${state.a.model}`;
  $("export-png").addEventListener("click", async () => {
    const tab = state.view.tab;
    download(await canvasBlob($(`plot-${tab === "plane" ? "cartesian" : tab}`)), `${base()}.png`);
  });
  $("export-csv").addEventListener("click", () => {
    const t = tables[state.view.tab];
    if (t) download(new Blob([toCsv(t)], { type: "text/csv" }), `${base()}.csv`);
  });
}

// ------------------------------------------------------------------ start
function showError(err) {
  console.error(err);
  const el = $("error");
  el.hidden = false;
  el.textContent = String(err.message || err);
}

async function start() {
  const src = await loadSources();
  evaluator = new Evaluator(src);
  sphere = new SphereView($("sphere"), src);
  try {
    const r = await fetch("api/info.json");
    if (r.ok) info = await r.json();
  } catch { /* a static copy of the page without the server: no vase, no ground truth */ }
  $("preset-vase").hidden = !info.vase;
  await loadModels();
  // the full Oren–Nayar model (with its interreflection term) by default: the fair comparison
  // with the V-cavity ground truth, which has every bounce
  state.a = defaultState("oren-nayar-full");
  state.b = defaultState("lambert");
  const restored = decodeState(location.hash);
  if (restored) {
    for (const k of ["a", "b", "mode", "exposure"]) if (k in restored) state[k] = restored[k];
    if (restored.view) restoreView(restored.view);
  }
  buildPanel("a");
  buildPanel("b");
  $("mode").value = String(state.mode);
  $("exposure").value = state.exposure;
  $("exposure-out").textContent = `${state.exposure.toFixed(1)} EV`;
  setupViews();
  if (restored?.light) setLight(restored.light.theta, restored.light.phi);
  $("mode").addEventListener("change", (ev) => { state.mode = Number(ev.target.value); refresh(); });
  $("exposure").addEventListener("input", (ev) => {
    state.exposure = Number(ev.target.value);
    $("exposure-out").textContent = `${state.exposure.toFixed(1)} EV`;
    refresh();
  });
  $("vase-render").addEventListener("click", loadVase);
  $("preset").addEventListener("change", (ev) => { if (ev.target.value in PRESETS) applyPreset(ev.target.value); });
  $("light-theta").addEventListener("input", (ev) => setLight(Number(ev.target.value), state.light.phi));
  $("light-phi").addEventListener("input", (ev) => setLight(state.light.theta, Number(ev.target.value)));
  const c = $("sphere");
  c.addEventListener("pointerdown", (ev) => { c.setPointerCapture(ev.pointerId); pointerToLight(ev); });
  c.addEventListener("pointermove", (ev) => { if (ev.buttons & 1) pointerToLight(ev); });
  setupData({
    setLight: (theta) => setLight(theta, state.light.phi),
    refresh,
    lightTheta: () => state.light.theta,
    evaluateA: (cos) => evaluator.evaluate(gpuParams(state.a), cos),
  }, info);
  // links made before the rename keep their Δφ under the old key `dphi`
  if (restored?.view) setSelection({ deltaPhi: restored.view.deltaPhi ?? restored.view.dphi, channel: restored.view.channel });
  setupFit({
    modelA: () => state.a.model,
    applyToA: (updates) => { Object.assign(state.a, updates); writePanel("a"); refresh(); gtSoon(); },
  });
  document.addEventListener("input", gtSoon);
  document.addEventListener("change", gtSoon);
  $("gt-row").hidden = !info.groundtruth;
  await loadGroundTruth();
  refresh();
  window.rdExplorer = {
    state,
    /** GLSL BRDF: params as in models.gpuParams (sigma in radians), cosines flat (mu_i, mu_o, cos_io). */
    evaluate: (params, cosines) => Array.from(evaluator.evaluate(gpuParams(params), Float32Array.from(cosines))),
    setLight,
    refresh,
    tables: () => tables,
  };
  await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
  document.body.dataset.ready = "1";
}

start().catch(showError);
