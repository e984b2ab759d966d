// Measured data on the page: a MERL .binary file or a CSV of BRDF samples, dropped or chosen.
//
// Both go to the server (POST api/data), which parses them with roughdiffuse.fit (the one
// reader of each format) and keeps them for fitting (fitpanel.js). A CSV is also parsed here
// (csv.js) so that its samples are drawn at once and a bad file is named line by line; a MERL
// file (35 MB) stays on the server, which answers slices of it (GET api/data/slice).
//
// The interface other modules use:
//   dataset                 the loaded dataset (null before): {id, name, kind, thetaI, ...}
//   selection               {thetaI (degrees, follows the light), deltaPhi (degrees), channel}
//   sliceCosines(ti, trs)   cosines (mu_i, mu_o, cos_io) of the current slice, for curves
//   channelValue(f, k)      the selected channel (or the mean) of the k-th RGB triple of f
//   dataSeries(thetaI)      the points to draw at the light's θi (a plot series), or null
//   onDataset(fn)           call fn(dataset) whenever a dataset is loaded or dropped
//   setSelection({deltaPhi, channel})  set the slice controls (e.g. from the URL) and redraw

import { CsvError, parseBrdfCsv } from "./csv.js";

const DEG = Math.PI / 180;
const E0 = Math.PI; // irradiance, as in sphere.frag and main.js
const $ = (id) => document.getElementById(id);

/** The loaded dataset, or null. */
export let dataset = null;
/** The slice shown: θi of the data nearest the light, Δφ, and the channel ("mean", 0, 1, 2). */
export const selection = { thetaI: 0, deltaPhi: 0, channel: "mean" };

let hooks = null; // from main.js: {setLight, refresh, evaluateA, lightTheta}
let limits = { merl: 36_000_000, csv: 4_000_000 };
let slice = null; // the last MERL slice: {theta_i, delta_phi, theta_r, brdf}
let sliceController = null;
let sliceTimer = null;
const listeners = [];

/** Register fn(dataset), called when a dataset is loaded (or null when a load failed). */
export function onDataset(fn) {
  listeners.push(fn);
}

/** The sentence that says the light was moved on loading data ("" when it stays). */
function lightMoveNote(from, to, why) {
  if (Math.abs(from - to) < 0.05) return "";
  const text = ` The light moved from θ = ${from.toFixed(1)}° to ${to.toFixed(1)}° (${why}).`;
  document.body.dataset.lightMoved = text.trim();
  return text;
}

function setStatus(text, isError) {
  const el = $("data-status");
  el.textContent = text;
  el.classList.toggle("error", isError);
}

/** Cosines of the slice for the curves: θr signed (> 0 at Δφ, < 0 at Δφ + 180°). */
export function sliceCosines(thetaIDeg, thetaRDeg) {
  const ti = thetaIDeg * DEG, c = Math.cos(selection.deltaPhi * DEG);
  const cos = new Float32Array(3 * thetaRDeg.length);
  thetaRDeg.forEach((tr, k) => {
    const a = Math.abs(tr) * DEG;
    cos[3 * k] = Math.cos(ti);
    cos[3 * k + 1] = Math.cos(a);
    cos[3 * k + 2] = Math.cos(ti) * Math.cos(a) + Math.sign(tr) * Math.sin(ti) * Math.sin(a) * c;
  });
  return cos;
}

/** The selected channel of the k-th RGB triple of f (flat), or the mean of the three. */
export function channelValue(f, k) {
  const ch = selection.channel;
  return ch === "mean" ? (f[3 * k] + f[3 * k + 1] + f[3 * k + 2]) / 3 : f[3 * k + ch];
}

/** How the plots describe the slice and the channel. */
export function sliceLabel() {
  const where = selection.deltaPhi === 0 ? "in the plane of incidence" : `at Δφ = ${selection.deltaPhi}° / ${selection.deltaPhi + 180}°`;
  const ch = selection.channel === "mean" ? "mean of RGB" : ["red", "green", "blue"][selection.channel];
  return { where, channel: ch };
}

/** Fold an azimuth difference (radians) into [0°, 180°]. */
function foldDeg(deltaPhi) {
  return Math.abs(Math.atan2(Math.sin(deltaPhi), Math.cos(deltaPhi))) / DEG;
}

/** The data at the light's θi in the current slice, as a plot series; null without data. */
export function dataSeries(thetaIDeg) {
  if (!dataset) return null;
  const x = [], y = [];
  let label;
  if (dataset.kind === "csv") {
    const s0 = selection.deltaPhi, s1 = 180 - selection.deltaPhi, tol = 5;
    for (const s of dataset.samples) {
      if (Math.abs(s.thetaI / DEG - thetaIDeg) > 2.5) continue;
      const d = foldDeg(s.deltaPhi);
      const v = channelValue(s.value, 0) * Math.cos(s.thetaI) * E0;
      if (Math.abs(d - s0) <= tol) { x.push(s.thetaR / DEG); y.push(v); }
      if (Math.abs(d - s1) <= tol && !(s1 === s0 && s.thetaR === 0)) { x.push(-s.thetaR / DEG); y.push(v); }
    }
    label = `data, θi ≈ ${thetaIDeg.toFixed(0)}° (${x.length} points)`;
  } else {
    if (!slice || Math.abs(slice.theta_i - thetaIDeg) > 0.05 || slice.delta_phi !== selection.deltaPhi) {
      sliceSoon(thetaIDeg);
      if (!slice) return null;
    }
    const lum = Math.cos(slice.theta_i * DEG) * E0;
    slice.theta_r.forEach((tr, k) => {
      const f = slice.brdf[k];
      if (f === null) return;
      x.push(tr);
      y.push(channelValue(f, 0) * lum);
    });
    label = `${dataset.name}, θi = ${slice.theta_i.toFixed(1)}° (MERL, nearest cell)`;
  }
  return { label, color: "#c0392b", points: true, x, y };
}

/** Ask the server for the MERL slice at θi (after 80 ms of stillness); redraw when it comes. */
function sliceSoon(thetaIDeg) {
  clearTimeout(sliceTimer);
  sliceTimer = setTimeout(() => loadSlice(thetaIDeg).catch((err) => setStatus(String(err.message || err), true)), 80);
}

async function loadSlice(thetaIDeg) {
  if (!dataset || dataset.kind !== "merl" || !(thetaIDeg < 90)) return;
  if (sliceController) sliceController.abort();
  const controller = (sliceController = new AbortController());
  const ti = Math.round(thetaIDeg * 10) / 10;
  const q = new URLSearchParams({ id: dataset.id, theta_i: String(ti), delta_phi: String(selection.deltaPhi) });
  let r, body;
  try {
    r = await fetch(`api/data/slice?${q}`, { signal: controller.signal });
    body = await r.json();
  } catch (err) {
    if (err.name === "AbortError") return;
    throw err;
  }
  if (controller !== sliceController) return;
  if (!r.ok) throw new Error(body.error ?? `HTTP ${r.status}`);
  slice = { ...body, theta_i: thetaIDeg };
  document.body.dataset.slicePoints = String(body.brdf.filter((v) => v !== null).length);
  hooks.refresh();
}

/** main.js calls this when the light's θ changes: the θi control follows it. */
export function onLight(thetaDeg) {
  selection.thetaI = thetaDeg;
  if (!dataset) return;
  const list = dataset.thetaI;
  let best = 0;
  list.forEach((t, k) => { if (Math.abs(t - thetaDeg) < Math.abs(list[best] - thetaDeg)) best = k; });
  const input = $("data-theta-i");
  if (Number(input.value) !== best) input.value = String(best);
  $("data-theta-i-out").textContent = `${list[best].toFixed(1)}°`;
}

/** The kind of a file: "csv" by its name or a small size, else "merl". */
function kindOf(file) {
  const name = file.name || "";
  if (/\.(csv|txt|tsv)$/i.test(name)) return "csv";
  if (/\.binary$/i.test(name)) return "merl";
  return file.size > limits.csv ? "merl" : "csv";
}

async function upload(kind, file, body) {
  const q = new URLSearchParams({ format: kind, name: file.name || `data.${kind === "merl" ? "binary" : "csv"}` });
  const r = await fetch(`api/data?${q}`, { method: "POST", body, headers: { "Content-Type": "application/octet-stream" } });
  let out;
  try {
    out = await r.json();
  } catch {
    out = { error: `the server answered HTTP ${r.status}` };
  }
  if (!r.ok) throw new UploadError(out.error ?? `HTTP ${r.status}`, r.status);
  return out;
}

class UploadError extends Error {
  constructor(message, status) {
    super(message);
    this.status = status;
  }
}

/** A file was not loaded: say why, and drop the previous dataset (its points would mislead). */
function failed(file, message) {
  if (dataset) {
    dataset = null;
    slice = null;
    $("data-controls").hidden = true;
    $("plot-scatter").hidden = true;
    document.body.dataset.csvScatter = "0";
    for (const fn of listeners) fn(null);
    hooks.refresh();
  }
  setStatus(`${file.name || "file"}: ${message.replace(new RegExp(`^${escapeRe(file.name || "")}: `), "")} The file was not loaded.`, true);
  document.body.dataset.dataLoaded = "error";
}

function escapeRe(s) {
  return s.replace(/[.*+?^${}()|[\]\\]/g, "\\$&");
}

/** Load a dropped or chosen file. */
export async function loadFile(file) {
  const kind = kindOf(file);
  document.body.dataset.dataLoaded = "loading";
  if (file.size > limits[kind]) {
    failed(file, `too large for ${kind === "merl" ? "a MERL file" : "a CSV file"}: ${file.size} bytes, at most ${limits[kind]} are accepted.`);
    return;
  }
  if (kind === "csv") {
    const text = await file.text();
    let samples;
    try {
      samples = parseBrdfCsv(text).samples;
    } catch (err) {
      if (!(err instanceof CsvError)) throw err;
      failed(file, `${err.message}.`);
      return;
    }
    let summary = null, note = "";
    try {
      summary = await upload("csv", file, text);
    } catch (err) {
      note = ` Not fitted: ${err.message}`;
    }
    const thetaI = [...new Set(samples.map((s) => Math.round((s.thetaI / DEG) * 10) / 10))].sort((a, b) => a - b);
    const to = samples[0].thetaI / DEG;
    note += lightMoveNote(hooks.lightTheta(), to, "the data's first θi, to show its slice");
    setDataset({ ...(summary ?? {}), name: file.name || "data.csv", kind: "csv", samples, thetaI, total: samples.length, note });
    hooks.setLight(to);
  } else {
    setStatus(`${file.name}: uploading ${(file.size / 1e6).toFixed(1)} MB to the server…`, false);
    let summary;
    try {
      summary = await upload("merl", file, file);
    } catch (err) {
      if (!(err instanceof UploadError) && !(err instanceof TypeError)) throw err;
      failed(file, `${err.message}.`);
      return;
    }
    const t = hooks.lightTheta();
    const note = lightMoveNote(t, t < 90 ? t : 30, "above the horizon, where the data are");
    setDataset({ ...summary, kind: "merl", thetaI: summary.theta_i, total: summary.samples, note });
    hooks.setLight(t < 90 ? t : 30);
  }
}

function setDataset(ds) {
  dataset = ds;
  slice = null;
  const input = $("data-theta-i");
  input.max = String(ds.thetaI.length - 1);
  $("data-controls").hidden = false;
  $("tab-scatter").hidden = ds.kind !== "csv"; // a view of the plots column (views.js)
  if (ds.kind === "merl") {
    setStatus(`${ds.name}: MERL BRDF, ${ds.total} cells present; drawn from the nearest cell at each θr, fitted on ${ds.fit_samples} random cells.${ds.note}`, false);
  }
  document.body.dataset.dataLoaded = ds.kind;
  for (const fn of listeners) fn(ds);
  onLight(selection.thetaI);
  hooks.refresh();
}

/** A CSV dataset: its samples against model A, all of them (main.js calls this after drawing).
 * Returns the plotted table {columns, rows} for the CSV export, or null without CSV data. */
export function drawScatterOf(drawScatter) {
  if (!dataset || dataset.kind !== "csv") return null;
  const smp = dataset.samples;
  const cos = new Float32Array(3 * smp.length);
  smp.forEach((s, k) => {
    cos[3 * k] = Math.cos(s.thetaI);
    cos[3 * k + 1] = Math.cos(s.thetaR);
    cos[3 * k + 2] = Math.cos(s.thetaI) * Math.cos(s.thetaR) + Math.sin(s.thetaI) * Math.sin(s.thetaR) * Math.cos(s.deltaPhi);
  });
  const f = hooks.evaluateA(cos);
  const model = smp.map((_, k) => channelValue(f, k));
  const measured = smp.map((s) => channelValue(s.value, 0));
  let se = 0, n = 0;
  model.forEach((m, k) => { if (m > 0) { se += ((measured[k] - m) / m) ** 2; n++; } });
  const drawn = drawScatter($("plot-scatter"), model, measured, { title: `${dataset.name}: measured (vertical) against model A (all ${smp.length} samples)` });
  document.body.dataset.csvScatter = String(drawn);
  const rms = n ? Math.sqrt(se / n) * 100 : NaN;
  setStatus(`${dataset.name}: ${smp.length} samples; RMS relative difference to model A: ${rms.toFixed(1)}%. ` +
    "The plot shows the samples with θi within 2.5° of the light and Δφ within 5° of the slice." + dataset.note, false);
  const deg = 180 / Math.PI;
  return {
    columns: ["theta_i_deg", "theta_r_deg", "delta_phi_deg", "measured", "model_a"],
    rows: smp.map((s, k) => [s.thetaI * deg, s.thetaR * deg, s.deltaPhi * deg, measured[k], model[k]]),
  };
}

/** Set Δφ (degrees, 0–180) and/or the channel ("mean", 0, 1, 2), controls included. */
export function setSelection({ deltaPhi, channel } = {}) {
  if (deltaPhi !== undefined) {
    const d = Math.min(180, Math.max(0, Math.round(Number(deltaPhi)) || 0));
    selection.deltaPhi = d;
    $("data-dphi").value = String(d);
    $("data-dphi-out").textContent = `${d}°`;
  }
  if (channel !== undefined && ["mean", 0, 1, 2, "0", "1", "2"].includes(channel)) {
    selection.channel = channel === "mean" ? "mean" : Number(channel);
    $("data-channel").value = String(selection.channel);
  }
  if (hooks) hooks.refresh();
}

/** Wire the drop zone, the file chooser and the slice controls. */
export function setupData(h, info = {}) {
  hooks = h;
  if (info.upload_bytes) limits = info.upload_bytes;
  const zone = $("dropzone");
  const stop = (ev) => { ev.preventDefault(); ev.stopPropagation(); };
  for (const t of ["dragenter", "dragover"]) document.addEventListener(t, (ev) => { stop(ev); zone.classList.add("over"); });
  document.addEventListener("dragleave", (ev) => { stop(ev); zone.classList.remove("over"); });
  const go = (file) => loadFile(file).catch((err) => { failed(file, String(err.message || err)); console.warn(err); });
  document.addEventListener("drop", (ev) => {
    stop(ev);
    zone.classList.remove("over");
    const file = ev.dataTransfer && ev.dataTransfer.files[0];
    if (file) go(file);
  });
  $("data-file").addEventListener("change", (ev) => {
    const file = ev.target.files[0];
    if (file) go(file);
    ev.target.value = "";
  });
  $("data-theta-i").addEventListener("input", (ev) => {
    if (dataset) hooks.setLight(dataset.thetaI[Number(ev.target.value)]);
  });
  $("data-dphi").addEventListener("input", (ev) => {
    selection.deltaPhi = Number(ev.target.value);
    $("data-dphi-out").textContent = `${selection.deltaPhi}°`;
    hooks.refresh();
  });
  $("data-channel").addEventListener("change", (ev) => {
    const v = ev.target.value;
    selection.channel = v === "mean" ? "mean" : Number(v);
    hooks.refresh();
  });
}
