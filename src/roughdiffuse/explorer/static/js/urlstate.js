// The page's state in the URL's hash, so that a view can be shared: the two model slots, the
// compare mode, the light, the exposure and the view options. Read back with every value
// checked: an unknown model or parameter is ignored, a number is clamped to its slider's range.

import { BY_KEY, PARAMS, defaultState } from "./models.js";

const DEG = Math.PI / 180;

/** The hash ("#…") for a state {a, b, mode, light, exposure, view}. */
export function encodeState(s) {
  const q = new URLSearchParams({
    a: JSON.stringify(s.a),
    b: JSON.stringify(s.b),
    mode: String(s.mode),
    light: `${s.light.theta},${s.light.phi}`,
    exposure: String(s.exposure),
    view: JSON.stringify(s.view),
  });
  return `#${q}`;
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
  const q = new URLSearchParams(hash.slice(1));
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
