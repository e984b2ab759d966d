// The explorer page: two model slots (A, B), a lit sphere, plane-of-incidence plots, presets,
// measured data with fits (data.js, fitpanel.js) and (when the server has one) ground truth.

import { channelValue, dataSeries, drawScatterOf, onLight, selection, setSelection, setupData, sliceCosines, sliceLabel } from "./data.js";
import { setupFit } from "./fitpanel.js";
import { Evaluator, SphereView, loadSources } from "./gl.js";
import { BY_KEY, LEFT_OUT, MODELS, PARAMS, applies, baseState, choicesOf, defaultState, gpuParams, loadModels } from "./models.js";
import { drawCartesian, drawPolar, drawScatter } from "./plot.js";
import { canvasBlob, download, toCsv } from "./export.js";
import { svgCanvas } from "./svgcanvas.js";
import { decodeState, encodeState } from "./urlstate.js";
import { VIEWS, drawAlbedo, drawLobe, drawSlice, rereadHover, setupHover, setupLobeDrag } from "./views.js";

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
  // the 3-D lobe's turn (radians); the θh/θd map has its own log scale, on at first (its
  // linear scale is swamped by the grazing peak)
  view: { tab: "plane", log: false, gt: false, bounces: "all", yaw: -0.5, pitch: 0.35, sliceLog: true },
};
let lastPlots = null; // what drawPlots drew: the plane and polar series and options, for export
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
  const aliasNote = document.createElement("p");
  aliasNote.id = `${p}alias-note`;
  aliasNote.className = "alias-note";
  root.append(aliasNote);
  const f3 = (v) => v.toFixed(3);
  const ctl = { model: sel, sliders: {}, selects: {}, colours: {} };
  for (const [k, q] of Object.entries(PARAMS)) {
    if (q.channels) {
      // one colour group per channel parameter (albedo; Coated's absorption): a grey box and
      // R, G, B sliders; albedo keeps the ids a-grey / a-grey-row of the first version
      const gid = k === "albedo" ? `${p}grey` : `${p}${k}-grey`;
      const grey = document.createElement("label");
      grey.innerHTML = `<input type="checkbox" id="${gid}" checked> grey ${k} (R = G = B)`;
      grey.id = `${gid}-row`;
      root.append(grey);
      const sliders = ["r", "g", "b"].map((c, j) => slider(root, `${p}${k}-${c}`, `${k} ${c.toUpperCase()}`, q.lo, q.hi, 0.005, s[k][j], f3));
      ctl.colours[k] = { grey: grey.querySelector("input"), row: grey, sliders };
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
    note.textContent = "Not in the menus (computed by simulation or from a table, not a formula the GLSL is printed from): " +
      LEFT_OUT.map((m) => m.key).join(", ") + ". `roughdiffuse render --model ID` renders them.";
    root.append(note);
  }
  panels[slot] = ctl;
  const onInput = (ev) => {
    for (const g of Object.values(ctl.colours)) {
      if (!g.grey.checked || !ev || !g.sliders.includes(ev.target)) continue;
      for (const a of g.sliders) if (a !== ev.target) { a.value = ev.target.value; a.dispatchEvent(new Event("change")); }
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
  for (const [k, g] of Object.entries(c.colours)) s[k] = g.sliders.map((a) => Number(a.value));
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
  for (const [k, g] of Object.entries(c.colours)) {
    const v = s[k];
    g.sliders.forEach((a, j) => (a.value = v[j]));
    g.grey.checked = v[0] === v[1] && v[1] === v[2];
  }
  for (const [k, el] of Object.entries(c.sliders)) el.value = PARAMS[k].unit === "radians" ? s[`${k}Deg`] : s[k];
  for (const [k, el] of Object.entries(c.selects)) el.value = s[k];
  const colourSliders = Object.values(c.colours).flatMap((g) => g.sliders);
  for (const el of [...colourSliders, ...Object.values(c.sliders)]) el.dispatchEvent(new Event("input"));
  showUsed(slot);
}

/** "= EON (qualitative Oren–Nayar …) with sigma = sigma_deg * 0.0174533": what an alias is
 *  drawn as (its base model's GLSL) and its conversion, as the server recorded it. */
function aliasText(m) {
  const a = m.alias;
  const changed = Object.entries(a.text).filter(([k, t]) => k !== t).map(([k, t]) => `${k} = ${t.replace(/^\((.*)\)$/, "$1")}`);
  const fixed = Object.entries(a.fixed).map(([k, v]) => `${k} = ${v}`);
  const rest = [...changed, ...fixed];
  return `= ${BY_KEY[a.base].label}` + (rest.length ? ` with ${rest.join(", ")}` : "");
}

/** Show the controls of the parameters the slot's model declares, hide the others. */
function showUsed(slot) {
  const c = panels[slot];
  const m = BY_KEY[state[slot].model];
  const uses = m.uses.filter((k) => applies(m.params[k], state[slot]));  // Coated: its base's
  const p = `${slot}-`;
  $(`${p}alias-note`).hidden = !m.alias;
  $(`${p}alias-note`).textContent = m.alias ? aliasText(m) : "";
  for (const k of [...Object.keys(c.sliders), ...Object.keys(c.selects)]) $(`${p}${k}-row`).hidden = !uses.includes(k);
  const own = BY_KEY[state[slot].model].params;
  for (const [k, q] of Object.entries(own)) {  // a control several models share: this model's words
    const label = $(`${p}${k}-row`)?.firstChild;
    if (label && label.nodeType === Node.TEXT_NODE) label.textContent = c.selects[k] ? `${q.description} ` : q.description;
  }
  for (const [k, el] of Object.entries(c.selects)) {
    if (!own[k]) continue;  // a menu several models share: this model's choices only
    for (const opt of el.options) opt.hidden = !own[k].choices.includes(opt.value);
    if (!own[k].choices.includes(el.value)) {
      el.value = own[k].default;
      state[slot][k] = own[k].default;
    }
  }
  for (const [k, g] of Object.entries(c.colours)) {
    for (const ch of ["r", "g", "b"]) $(`${p}${k}-${ch}-row`).hidden = !uses.includes(k);
    g.row.hidden = !uses.includes(k);
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

/** Size the sphere canvas to its column: as wide as the column (two spheres side by side in
 *  the A | B mode), no taller than the window leaves beside the rows below it (but at least
 *  240 px, if the column is as wide); drawn at the screen's pixel density. Returns whether the size changed. */
function fitSphere() {
  const c = $("sphere"), n = state.mode === 1 ? 2 : 1;
  const side = Math.floor(Math.min($("view").clientWidth / n, Math.max(240, window.innerHeight - 430)));
  const dpr = window.devicePixelRatio || 1;
  const w = Math.round(n * side * dpr), h = Math.round(side * dpr);
  c.style.width = `${n * side}px`;
  c.style.height = `${side}px`;
  if (c.width === w && c.height === h) return false;
  c.width = w;
  c.height = h;
  return true;
}

function draw() {
  if (!state.a || !state.b) return; // a resize before /api/models is read: start() draws later
  fitSphere();
  const a = gpuParams(state.a), b = gpuParams(state.b);
  sphere.draw(a, b, state.mode, lightVector(), Math.pow(2, state.exposure));
  $("light-readout").textContent = `light θ = ${state.light.theta.toFixed(1)}°, φ = ${state.light.phi.toFixed(1)}°`;
  $("panel-b").classList.toggle("disabled", state.mode === 0);
  $("label-a").hidden = $("label-b").hidden = state.mode !== 1;
  $("diff-legend").hidden = state.mode !== 2;
  if (state.mode === 2) drawDiffLegend();
  drawPlots(a, b);
  drawView(a, b);
  rereadHover();
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

/** "A: Oren–Nayar full", and when A and B are one model, what tells them apart
 *  ("A: Oren–Nayar full, σ = 30°" / "B: Oren–Nayar full, σ = 10°"). */
function slotLabel(slot) {
  const s = state[slot];
  let text = `${slot.toUpperCase()}: ${BY_KEY[s.model].short}`;
  const other = state[slot === "a" ? "b" : "a"];
  if (state.mode !== 0 && other.model === s.model) {
    const diff = [];
    for (const k of BY_KEY[s.model].uses) {
      const q = PARAMS[k];
      const key = q.unit === "radians" && !q.channels ? `${k}Deg` : k;
      if (JSON.stringify(s[key]) === JSON.stringify(other[key])) continue;
      const v = s[key];
      const shown = Array.isArray(v) ? v.map((x) => x.toFixed(2)).join("/") : typeof v === "number" ? (q.unit === "radians" ? `${v.toFixed(1)}°` : v.toFixed(3)) : v;
      diff.push(`${k === "sigma" ? "σ" : k} = ${shown}`);
    }
    if (diff.length) text += `, ${diff.join(", ")}`;
  }
  return text;
}

/** The slots the extra views draw: A, and B unless the page shows A only. */
function viewSlots(a, b) {
  const slots = [{ label: slotLabel("a"), color: "#1f5fa8", params: a }];
  if (state.mode !== 0) slots.push({ label: slotLabel("b"), color: "#d35400", dash: true, params: b });
  return slots;
}

/** Draw the current view into `target` (a canvas, a 2x canvas or an SVG canvas), as the
 *  page draws it on screen: what the PNG and SVG exports write. */
function drawViewInto(target) {
  const tab = state.view.tab;
  const a = gpuParams(state.a), b = gpuParams(state.b);
  const slots = viewSlots(a, b);
  if (tab === "plane") drawCartesian(target, lastPlots.series, lastPlots.cartesian);
  else if (tab === "polar") drawPolar(target, lastPlots.series, lastPlots.polar);
  else if (tab === "lobe") drawLobe(target, evaluator, slots, lightVector(), state.view);
  else if (tab === "albedo") drawAlbedo(target, evaluator, slots, state.view.log);
  else if (tab === "slice") drawSlice(target, evaluator, slots, state.view.sliceLog);
  else if (tab === "scatter") drawScatterOf((_, ...rest) => drawScatter(target, ...rest));
}

/** Size every plot canvas to the plots column: as wide as the column, 0.66 as high (at least
 *  300 px, and short enough to leave the rows below it, the data panel with its slice
 *  controls and fit buttons, in view: 380 px with the header). */
function fitPlots() {
  const w = Math.max(320, Math.floor($("plots").clientWidth));
  const h = Math.round(Math.max(300, Math.min(0.66 * w, window.innerHeight - 380)));
  let changed = false;
  for (const v of VIEWS) {
    const c = $(`plot-${v === "plane" ? "cartesian" : v}`);
    // a change below 24 px is left alone: a scroll bar that comes and goes with the page's
    // height (about 15 px) must not resize the plots back and forth for ever
    if (Math.abs(c.width - w) >= 24 || Math.abs(c.height - h) >= 24) { c.width = w; c.height = h; changed = true; }
  }
  if (changed && evaluator) refresh();
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
  else if (tab === "slice") tables.slice = drawSlice($("plot-slice"), evaluator, slots, state.view.sliceLog);
  $("log-scale").checked = state.view[logKey()];
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
  const label = slotLabel;
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
  const cartesian = { title, ylabel: `L (E0 = π, ${slice.channel})`, log: state.view.log };
  const polar = { title: "polar: radius L, angle θr", lightDeg: lit ? thetaI : null, log: state.view.log };
  lastPlots = { series, cartesian, polar };
  const drawn = drawCartesian($("plot-cartesian"), series, cartesian);
  const rows = [];
  for (const s of series) s.x.forEach((x, k) => rows.push([s.label, x, s.y[k]]));
  tables.plane = tables.polar = { columns: ["series", "theta_r_deg", "radiance"], rows };
  drawPolar($("plot-polar"), series, polar);
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
    base: s.base, base_roughness: String(s.base_roughness),
    light_theta: String(state.light.theta), light_phi: String(state.light.phi), exposure: String(state.exposure),
  });
  for (const k of BY_KEY[s.model].uses) {  // a model's own numbers (an alias's sigma_deg, ...)
    const p = PARAMS[k];
    if (!q.has(k) && p.choices === null && !p.channels && p.unit !== "radians") q.set(k, String(s[k]));
  }
  return q.toString();
}

function loadVase() {
  $("vase-status").textContent = "rendering…";
  let left = 2;
  let done;
  track(new Promise((r) => (done = r)));
  for (const slot of ["a", "b"]) {
    const img = $(`vase-${slot}`);
    img.onload = img.onerror = (ev) => {
      left -= 1;
      if (left === 0) done();
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
/** A slot's state, or for an alias its base model's (σ in degrees as on the sliders). */
function baseOf(s) {
  if (!BY_KEY[s.model].alias) return s;
  const b = baseState(s);
  return b.sigma === undefined ? b : { ...b, sigmaDeg: b.sigma / DEG };
}
/** Ground truth from the server's V-cavity solver for model A's σ, ρ (green) and the light's θ. */
async function loadGroundTruth() {
  const status = $("gt-status");
  if (gtController) gtController.abort();
  gtController = null;
  const s = baseOf(state.a);  // an alias of Oren–Nayar (pbrt-v3's, Mitsuba 0.6's) has its σ
  const coated = s.model === "coated";  // its truth: the layered walk
  const reason = !info.groundtruth ? "this server has no V-cavity solver"
    : !state.view.gt ? ""
    : !coated && !["oren-nayar", "oren-nayar-full"].includes(s.model) ? "ground truth is shown for the Oren–Nayar models of A (a σ and Lambertian facets) and for Coated (the layered walk)"
    : !coated && !(s.sigmaDeg > 0) ? "σ = 0 is Lambert: nothing to compare"
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
  status.textContent = coated ? "computing the layered truth…" : "computing the V-cavity ground truth…";
  const url = coated
    ? `api/layeredtruth.json?${queryFor("a")}&absorption=${[s.absorption ?? 0].flat().join(",")}&theta_i=${state.light.theta}`
    : `api/groundtruth.json?${q}`;
  let gt;
  try {
    const r = await fetch(url, { signal: controller.signal });
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
  const label = coated ? "layered truth (Monte Carlo)" : `V-cavity, ${bounces} (σ = ${(gt.sigma / DEG).toFixed(1)}°)`;
  gtSeries = { label, color: "#1e8449", points: false, dash: true, x: gt.theta_r, y: gt.radiance };
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
  if (typeof v.sliceLog === "boolean") view.sliceLog = v.sliceLog;
  if (typeof v.gt === "boolean") view.gt = v.gt;
  if (["1", "all"].includes(v.bounces)) view.bounces = v.bounces;
  for (const k of ["yaw", "pitch"]) if (Number.isFinite(v[k])) view[k] = v[k];
  view.pitch = Math.min(Math.PI / 2, Math.max(0, view.pitch));
}

function setupViews() {
  for (const el of document.querySelectorAll("#view-tabs button")) {
    el.addEventListener("click", () => { state.view.tab = el.dataset.view; refresh(); });
  }
  $("log-scale").checked = state.view[logKey()];
  $("log-scale").addEventListener("change", (ev) => { state.view[logKey()] = ev.target.checked; refresh(); });
  $("gt-show").checked = state.view.gt;
  $("gt-show").addEventListener("change", (ev) => { state.view.gt = ev.target.checked; });
  $(`gt-bounces-${state.view.bounces}`).checked = true;
  for (const b of ["1", "all"]) $(`gt-bounces-${b}`).addEventListener("change", (ev) => { if (ev.target.checked) state.view.bounces = b; });
  setupHover(VIEWS.map((v) => $(`plot-${v === "plane" ? "cartesian" : v}`)), $("readout"));
  setupLobeDrag($("plot-lobe"), state.view, refresh);
  // file names say which models A and B are: roughdiffuse-plane-A-oren-nayar-full-B-lambert
  const base = () => `roughdiffuse-${state.view.tab}-A-${state.a.model}` + (state.mode !== 0 ? `-B-${state.b.model}` : "");
  $("export-png").addEventListener("click", () => exportPng().then((b) => download(b, `${base()}.png`)).catch(showError));
  $("export-svg").addEventListener("click", () => {
    download(new Blob([exportSvg()], { type: "image/svg+xml" }), `${base()}.svg`);
  });
  $("export-csv").addEventListener("click", () => {
    const t = tables[state.view.tab];
    if (t) download(new Blob([toCsv(t)], { type: "text/csv" }), `${base()}.csv`);
  });
}

/** The current view as PNG at twice the on-screen resolution. */
function exportPng() {
  const shown = $(`plot-${state.view.tab === "plane" ? "cartesian" : state.view.tab}`);
  const c = document.createElement("canvas");
  c.width = 2 * shown.width;
  c.height = 2 * shown.height;
  c.rdScale = 2;
  drawViewInto(c);
  return canvasBlob(c);
}

/** The current view as SVG text (the same drawing, recorded by svgcanvas.js). */
function exportSvg() {
  const shown = $(`plot-${state.view.tab === "plane" ? "cartesian" : state.view.tab}`);
  const c = svgCanvas(shown.width, shown.height);
  drawViewInto(c);
  return c.svg();
}

/** Which view option the log-scale box sets: the θh/θd map keeps its own. */
function logKey() {
  return state.view.tab === "slice" ? "sliceLog" : "log";
}

// ------------------------------------------------------------------ busy indicator
let busy = 0;
/** Count a server request (or the page's start) as running while `promise` is pending. */
function track(promise) {
  busy++;
  showBusy();
  return promise.finally(() => { busy--; showBusy(); });
}
function showBusy() {
  const on = busy > 0 || document.body.dataset.ready !== "1";
  $("busy").hidden = !on;
  document.body.dataset.busy = on ? "1" : "0";
}
const rawFetch = window.fetch.bind(window);
window.fetch = (...args) => track(rawFetch(...args)); // every request of every module

// ------------------------------------------------------------------ start
function showError(err) {
  console.error(err);
  const el = $("error");
  el.hidden = false;
  el.textContent = String(err.message || err);
}

async function start() {
  showBusy();
  fitPlots();
  new ResizeObserver(fitPlots).observe($("plots"));
  new ResizeObserver(() => { if (evaluator && fitSphere()) refresh(); }).observe($("view"));
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
    choicesA: () => choicesOf(BY_KEY[state.a.model], state.a),
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
  showBusy();
  window.rdExplorer.exportPng = exportPng;
  window.rdExplorer.exportSvg = exportSvg;
  window.rdExplorer.encodeHash = () => encodeState(sharedState());
}

start().catch(showError);
