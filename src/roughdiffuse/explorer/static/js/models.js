// The models the explorer offers come from the server's /api/models: the registry
// (roughdiffuse/registry.py), the same JSON as `roughdiffuse models --json`, with each
// model's parameters, units, ranges and defaults, and what each model class declares about
// its GLSL copy: `glsl_id`, the number brdf.glsl dispatches on (null: no GLSL copy), and
// `glsl_keys`, the RDParams field of each declared parameter whose name differs.

/** Declared parameter name -> key of the page's state and of RDParams, where they differ
 * (the union of the models' published glsl_keys). */
const FLAT_KEY = {};
export const flatKey = (name) => FLAT_KEY[name] ?? name;

/** Every model of the registry with a GLSL copy, and every alias of one:
 * {key, id, label, short, uses, params, fixed, alias}. */
export const MODELS = [];
/** The registry's models the page leaves out, with the reason: [{key, label, reason}]. */
export const LEFT_OUT = [];
export const BY_KEY = {};
/** One declaration per state key (the first model declaring it): unit, range, default. */
export const PARAMS = {};

/** Why the page cannot offer record r (null: it can). An alias (roughdiffuse.models.alias)
 * is offered when its base model has a GLSL copy and its conversion was recorded. */
function leftOutReason(r, glsl) {
  if (r.glsl && r.glsl_id !== null && r.glsl_id !== undefined) return null;
  if (!r.alias) return "no GLSL copy of its formula";
  if (!r.alias.to_base) return `its conversion to ${r.alias.base} could not be recorded: ${r.alias.why}`;
  if (!glsl.has(r.alias.base)) return `its base model ${r.alias.base} has no GLSL copy`;
  return null;
}

/** Fill MODELS, LEFT_OUT, BY_KEY and PARAMS from the JSON of /api/models. */
export function setModels(records) {
  MODELS.length = 0;
  LEFT_OUT.length = 0;
  for (const k of Object.keys(BY_KEY)) delete BY_KEY[k];
  for (const k of Object.keys(PARAMS)) delete PARAMS[k];
  for (const k of Object.keys(FLAT_KEY)) delete FLAT_KEY[k];
  for (const r of records) Object.assign(FLAT_KEY, r.glsl_keys ?? {});
  const byId = Object.fromEntries(records.map((r) => [r.id, r]));
  const glsl = new Set(records.filter((r) => r.glsl && r.glsl_id !== null && r.glsl_id !== undefined).map((r) => r.id));
  for (const r of records) {
    const reason = leftOutReason(r, glsl);
    if (reason !== null) {
      LEFT_OUT.push({ key: r.id, label: r.label, reason });
      continue;
    }
    const params = {};
    for (const p of r.parameters) params[flatKey(p.name)] = p;
    // an alias: its own sliders; the base's GLSL after the conversion its to_base recorded
    const alias = r.alias ? { ...r.alias, glslKeys: byId[r.alias.base].glsl_keys ?? {} } : null;
    const id = alias ? byId[alias.base].glsl_id : r.glsl_id;
    const m = { key: r.id, id, label: r.label, short: r.label.replace(/ \(.*\)$/, ""), uses: Object.keys(params), params, fixed: r.fixed ?? {}, alias };
    MODELS.push(m);
    BY_KEY[m.key] = m;
    for (const [k, p] of Object.entries(params)) {
      const q = PARAMS[k];
      if (!q) PARAMS[k] = { ...p, key: k, choices: p.choices === null ? null : [...p.choices] };
      else if (p.choices !== null) { // one menu: the union of the models' choices (main.js shows each model's own)
        for (const c of p.choices) if (!q.choices.includes(c)) q.choices.push(c);
      } else if (p.choices === null) { // one slider for every model that has it: the union range
        const lo = (p.fit_range ?? [p.min, p.max])[0], hi = (p.fit_range ?? [p.min, p.max])[1];
        q.lo = Math.min(q.lo ?? lo, lo);
        q.hi = Math.max(q.hi ?? hi, hi);
      }
    }
  }
  // the legend's short name drops a label's "(...)" unless another model's label then reads
  // the same (Mitsuba 0.6's two variants, the two MaterialX nodes, Torrance–Sparrow's D)
  const count = {};
  for (const m of MODELS) count[m.short] = (count[m.short] ?? 0) + 1;
  for (const m of MODELS) if (count[m.short] > 1) m.short = m.label;
  for (const q of Object.values(PARAMS)) {
    if (q.choices !== null) continue;
    const [lo, hi] = q.fit_range ?? [q.min, q.max];
    q.lo = Math.min(q.lo ?? lo, lo);
    q.hi = Math.max(q.hi ?? hi, hi);
  }
}

const BINARY = { "+": (a, b) => a + b, "-": (a, b) => a - b, "*": (a, b) => a * b, "/": (a, b) => a / b, "**": (a, b) => a ** b };

/** The value of an expression tree of roughdiffuse.models.conversion (a parameter's name, a
 * number, or [op, operand, ...]) for the parameter values (numbers or arrays, elementwise). */
export function evaluateTree(tree, values) {
  if (typeof tree === "string") {
    if (!(tree in values)) throw new Error(`the conversion reads an unknown parameter ${tree}`);
    return values[tree];
  }
  if (typeof tree === "number") return tree;
  const [op, ...args] = tree;
  const xs = args.map((a) => evaluateTree(a, values));
  const f = op === "neg" ? (a) => -a : BINARY[op];
  if (!f) throw new Error(`the conversion has an unknown operation ${op}`);
  const n = xs.find((x) => Array.isArray(x) || ArrayBuffer.isView(x))?.length;
  if (n === undefined) return f(...xs);
  return Array.from({ length: n }, (_, j) => f(...xs.map((x) => (typeof x === "number" ? x : x[j]))));
}

/** Fetch /api/models and fill the tables. */
export async function loadModels(url = "api/models") {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`the model list (${url}) is unavailable: HTTP ${r.status}`);
  setModels(await r.json());
}

const DEG = Math.PI / 180;

/** The value the page starts a parameter at: the declaration's example, else its default. */
function start(p) {
  return p.example ?? p.default;
}

/** Default UI state of one model slot (angles in degrees, as on the sliders). */
export function defaultState(key = "oren-nayar") {
  const own = BY_KEY[key]?.params ?? {};
  const s = { model: key };
  for (const [k, q] of Object.entries(PARAMS)) {
    const p = own[k] ?? q;
    const v = start(p);
    if (p.channels) s[k] = [v, v, v];
    else if (p.unit === "radians") s[`${k}Deg`] = v / DEG;
    else s[k] = v;
  }
  return s;
}

/**
 * The record the GLSL receives (brdf.glsl's RDParams). Accepts the UI state (sigmaDeg) or a
 * record with sigma in radians already (as the tests send it). Beckmann's α is given to the
 * GLSL as σ = α/√2 (brdf.glsl's Beckmann takes the per-component slope deviation).
 * An alias gives its base model's record: its own values converted (baseState).
 */
export function gpuParams(s) {
  const m = BY_KEY[s.model];
  if (!m) throw new Error(`unknown model ${JSON.stringify(s.model)}`);
  if (m.alias) return gpuParams(baseState(s));
  const sigma = s.sigma !== undefined ? s.sigma : (s.sigmaDeg * Math.PI) / 180;
  const distribution = s.distribution ?? m.fixed.distribution ?? "gaussian";
  const beckmannId = m.fixed.distribution === "beckmann";
  return {
    model: m.id,
    albedo: Float32Array.from(s.albedo ?? [0.8, 0.8, 0.8]),
    sigma: beckmannId ? (s.alpha ?? PARAMS.alpha.default) / Math.SQRT2 : sigma,
    roughness: s.roughness ?? 0,
    eta: s.eta ?? 1.5,
    weight: s.weight ?? 0,
    limb: s.limb ?? 0.5,
    distribution: beckmannId || distribution === "beckmann" ? 1 : 0,
    // brdf.glsl RDParams: alpha, variant, k, b0, h, g, theta_bar, hg2, absorption
    alpha: s.alpha ?? 0.3,
    variant: (s.variant ?? "full") === "fast" ? 1 : 0,
    k: s.k ?? 1.0,
    b0: s.b0 ?? 0.0,
    h: s.h ?? 0.1,
    g: s.xi ?? 0.0,  // Hapke's asymmetry ξ (its parameter xi)
    theta_bar: s.theta_bar !== undefined ? s.theta_bar : ((s.theta_barDeg ?? 0) * Math.PI) / 180,
    hg2: s.hg2 ?? 0.0,
    sums: m.key === "coated",  // its parameter-only sums come first (gl.js Evaluator.withSums)
    // Coated: the layer's optical depth, one number or one per channel
    absorption: Float32Array.from(Array.isArray(s.absorption) || ArrayBuffer.isView(s.absorption)
      ? s.absorption : [s.absorption ?? 0, s.absorption ?? 0, s.absorption ?? 0]),
    // Coated: its base (a registry id of coated.COAT_BASES) as that model's GLSL number
    base: BY_KEY[s.base ?? PARAMS.base?.default]?.id ?? 2,
    base_roughness: s.base_roughness ?? PARAMS.base_roughness?.default ?? 0.5,
  };
}

/** Whether parameter `p` of a model applies with the slot state `s`: its declaration's
 * `when` (e.g. Coated's sigma only over an Oren–Nayar base) holds for the state's menus. */
export function applies(p, s) {
  return !p?.when || Object.entries(p.when).every(([k, vs]) => vs.includes(s[flatKey(k)]));
}

/** An alias's state (UI state or a record with radians) as its base model's record: the
 * alias's own parameter values (declared defaults for those missing) through the conversion
 * its Python to_base declares (recorded on the server, roughdiffuse.models.conversion). */
export function baseState(s) {
  const m = BY_KEY[s.model];
  const own = {};
  for (const [k, p] of Object.entries(m.params)) {
    if (p.choices !== null) continue;
    let v = s[k];
    if (v === undefined && p.unit === "radians" && s[`${k}Deg`] !== undefined) v = s[`${k}Deg`] * DEG;
    if (v === undefined) v = p.channels ? [p.default, p.default, p.default] : p.default;
    own[p.name] = v;
  }
  const base = { model: m.alias.base, ...m.alias.fixed };
  for (const [name, tree] of Object.entries(m.alias.to_base)) {
    const v = evaluateTree(tree, own);
    base[m.alias.glslKeys[name] ?? name] = typeof v === "number" ? v : Array.from(v);
  }
  return base;
}
