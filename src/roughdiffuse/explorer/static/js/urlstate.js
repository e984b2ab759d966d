// The page's state in the URL's hash, so that a view can be shared: the two model slots, the
// compare mode, the light, the exposure and the view options, in a compact text (encodeState).
// Read back with every value checked: an unknown model or parameter is ignored, a number is
// clamped to its slider's range.

import { BY_KEY, PARAMS, defaultState } from "./models.js";

const DEG = Math.PI / 180;

/** View options in the order of the compact "v=" field. */
const VIEW_KEYS = ["tab", "log", "gt", "bounces", "yaw", "pitch", "deltaPhi", "channel", "sliceLog"];

const numText = (v) => String(v); // shortest text that reads back as the same number

/** One slot, compactly: its model id, then only the parameters that differ from the model's
 *  defaults, e.g. "oren-nayar-full;sigma:20;albedo:0.7,0.7,0.7". */
function encodeSlot(s) {
  const d = defaultState(s.model);
  const parts = [s.model];
  for (const [k, q] of Object.entries(PARAMS)) {
    const key = q.unit === "radians" && !q.channels ? `${k}Deg` : k;
    const v = s[key];
    if (v === undefined || JSON.stringify(v) === JSON.stringify(d[key])) continue;
    parts.push(`${k}:${Array.isArray(v) ? v.map(numText).join(",") : typeof v === "number" ? numText(v) : v}`);
  }
  return parts.join(";");
}

/**
 * The hash ("#…") for a state {a, b, mode, light, exposure, view}: a compact text of about a
 * hundred characters, readable and safe in a URL without escapes, e.g.
 * "#a=eon;roughness:0.7&b=lambert&m=1&l=40,20&e=1.5&v=albedo,1,0,all,-0.5,0.35,0,mean,1".
 * Links in the older form (URL-encoded JSON, "#a=%7B…") still load (decodeState).
 */
export function encodeState(s) {
  const v = VIEW_KEYS.map((k) => {
    const x = s.view[k];
    return typeof x === "boolean" ? (x ? "1" : "0") : String(x ?? "");
  });
  return `#a=${encodeSlot(s.a)}&b=${encodeSlot(s.b)}&m=${s.mode}&l=${s.light.theta},${s.light.phi}` +
    `&e=${numText(s.exposure)}&v=${v.join(",")}`;
}

/** The fields of a compact hash as {a: {...slot}, b, mode, light, exposure, view} texts. */
function parseCompact(hash) {
  const fields = {};
  for (const part of hash.slice(1).split("&")) {
    const i = part.indexOf("=");
    if (i <= 0) continue;
    try {
      fields[part.slice(0, i)] = decodeURIComponent(part.slice(i + 1));
    } catch { /* a damaged field is ignored */ }
  }
  const slot = (text) => {
    if (!text) return null;
    const [model, ...rest] = text.split(";");
    const raw = { model };
    for (const item of rest) {
      const j = item.indexOf(":");
      if (j < 0) continue;
      const k = item.slice(0, j), val = item.slice(j + 1);
      const q = PARAMS[k];
      if (!q) continue;
      if (q.channels) raw[k] = val.split(",").map(Number);
      else if (q.choices !== null) raw[k] = val;
      else if (q.unit === "radians") raw[`${k}Deg`] = Number(val);
      else raw[k] = Number(val);
    }
    return JSON.stringify(raw);
  };
  const view = {};
  (fields.v ?? "").split(",").forEach((x, k) => {
    const key = VIEW_KEYS[k];
    if (!key || x === "") return;
    if (["log", "gt", "sliceLog"].includes(key)) view[key] = x === "1";
    else if (["yaw", "pitch", "deltaPhi"].includes(key)) view[key] = Number(x);
    else view[key] = x;
  });
  return { a: slot(fields.a), b: slot(fields.b), mode: fields.m, light: fields.l, exposure: fields.e, view: JSON.stringify(view) };
}

const finite = (v) => typeof v === "number" && Number.isFinite(v);
const clamp = (v, lo, hi) => Math.min(Math.max(v, lo), hi);

/** A model slot from its JSON: the model's defaults, overridden by the valid values given. */
function decodeSlot(text) {
  let raw;
  try {
    raw = JSON.parse(text);
  } catch {
    return null;
  }
  if (!raw || typeof raw !== "object" || !(raw.model in BY_KEY)) return null;
  const s = defaultState(raw.model);
  for (const [k, q] of Object.entries(PARAMS)) {
    if (q.channels) {
      const v = raw[k];
      if (Array.isArray(v) && v.length === 3 && v.every(finite)) s[k] = v.map((x) => clamp(x, q.lo, q.hi));
    } else if (q.choices !== null) {
      if (q.choices.includes(raw[k])) s[k] = raw[k];
    } else if (q.unit === "radians") {
      if (finite(raw[`${k}Deg`])) s[`${k}Deg`] = clamp(raw[`${k}Deg`], q.lo / DEG, q.hi / DEG);
    } else if (finite(raw[k])) {
      s[k] = clamp(raw[k], q.lo, q.hi);
    }
  }
  return Object.assign(s, BY_KEY[raw.model].fixed); // a choice the id fixes, as main.js readPanel
}

/** The state a hash describes (only the parts it gives validly), or null for no state. */
export function decodeState(hash) {
  if (!hash || hash.length < 2) return null;
  const old = new URLSearchParams(hash.slice(1));
  const legacy = (old.get("a") ?? old.get("b") ?? "").startsWith("{") || old.has("mode");
  let q = old;
  if (!legacy) { // the compact form of encodeState
    const c = parseCompact(hash);
    q = new Map([["a", c.a], ["b", c.b], ["mode", c.mode], ["light", c.light], ["exposure", c.exposure], ["view", c.view]]
      .filter(([, v]) => v !== undefined && v !== null));
  }
  const out = {};
  for (const slot of ["a", "b"]) {
    const s = q.has(slot) ? decodeSlot(q.get(slot)) : null;
    if (s) out[slot] = s;
  }
  const mode = Number(q.get("mode"));
  if (q.has("mode") && [0, 1, 2].includes(mode)) out.mode = mode;
  const light = (q.get("light") ?? "").split(",").map(Number);
  if (light.length === 2 && light.every(Number.isFinite)) out.light = { theta: clamp(light[0], 0, 180), phi: clamp(light[1], -180, 180) };
  const ev = Number(q.get("exposure"));
  if (q.has("exposure") && Number.isFinite(ev)) out.exposure = clamp(ev, -4, 4);
  try {
    const v = JSON.parse(q.get("view") ?? "null");
    if (v && typeof v === "object") out.view = v;
  } catch { /* no view options */ }
  return Object.keys(out).length ? out : null;
}
