// The models the explorer offers come from the server's /api/models: the registry
// (roughdiffuse/registry.py), the same JSON as `roughdiffuse models --json`, with each
// model's parameters, units, ranges and defaults, and its printed shader (`shader`, from
// roughdiffuse.explorer.shaders): for each set of its menus' values a model number of the
// generated models.glsl and the JavaScript prepass that computes the model's parameter-only
// values (the uniform array RDParams.h); or `server: true` (the server traces the model for
// each parameter set and sends its GLSL: /api/shader); or `left_out` (why the page cannot
// draw it). `state_keys`: the page's key of each parameter whose key differs from its name
// (roughdiffuse.explorer.params.flat_key: Coated's α is `coat_roughness`, its own slider).

/** The page's key of declared parameter `name` of model `model` (its published state_keys). */
export const flatKey = (name, model) => BY_KEY[model]?.keys[name] ?? name;

/** Every model of the registry the page can draw:
 * {key, label, short, uses, params, fixed, alias, shader}. */
export const MODELS = [];
/** The registry's models the page leaves out, with the reason: [{key, label, reason}]. */
export const LEFT_OUT = [];
export const BY_KEY = {};
/** One declaration per state key (the first model declaring it): unit, range, default. */
export const PARAMS = {};

/** Why the page cannot offer record r (null: it can). */
function leftOutReason(r) {
  if (!r.shader) return "the server printed no shader for it";
  return r.shader.left_out ?? null;
}

/** The shader record of /api/models with each variant's prepass made a function. */
function withPrepass(shader) {
  if (!shader.variants) return shader;
  // the prepass is code the server printed from the model's own Python (engine/glsl.py)
  // eslint-disable-next-line no-new-func
  const variants = shader.variants.map((v) => ({ ...v, prepass: new Function("p", v.prepass) }));
  return { ...shader, variants };
}

/** Fill MODELS, LEFT_OUT, BY_KEY and PARAMS from the JSON of /api/models. */
export function setModels(records) {
  MODELS.length = 0;
  LEFT_OUT.length = 0;
  for (const k of Object.keys(BY_KEY)) delete BY_KEY[k];
  for (const k of Object.keys(PARAMS)) delete PARAMS[k];
  for (const r of records) {
    const reason = leftOutReason(r);
    if (reason !== null) {
      LEFT_OUT.push({ key: r.id, label: r.label, reason });
      continue;
    }
    const params = {};
    const keys = r.state_keys ?? {};
    for (const p of r.parameters) params[keys[p.name] ?? p.name] = p;
    const shader = withPrepass(r.shader);
    const m = { key: r.id, label: r.label, short: r.label.replace(/ \(.*\)$/, ""), uses: Object.keys(params), params, keys, fixed: r.fixed ?? {}, alias: r.alias ?? null, shader };
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

/** The value of declared parameter `p` (key `k`) in state `s`: radians from the sliders'
 * degrees (`${k}Deg`) unless given in radians, three channels for a colour, else the
 * declaration's starting value. */
function valueOf(p, k, s) {
  let v = s[k];
  if (v === undefined && p.unit === "radians" && s[`${k}Deg`] !== undefined) v = s[`${k}Deg`] * DEG;
  if (v === undefined) v = start(p);
  if (p.channels) return Array.isArray(v) || ArrayBuffer.isView(v) ? Array.from(v) : [v, v, v];
  return v;
}

/** The menus' values of state `s` for model m (its fixed ones, else the state's, else the
 * declared default). */
export function choicesOf(m, s) {
  const out = {};
  for (const [k, p] of Object.entries(m.params)) {
    if (p.choices === null) continue;
    const v = s[k];
    out[p.name] = p.choices.includes(v) ? v : p.default;
  }
  return out;
}

/** The flat record of a slot state for the server (/api/shader): the model's own values,
 * angles in radians, colours as three numbers. */
export function serverRecord(s) {
  const m = BY_KEY[s.model];
  const out = { model: s.model, ...choicesOf(m, s) };
  for (const [k, p] of Object.entries(m.params)) {
    if (p.choices === null && applies(p, s)) out[k] = valueOf(p, k, s);
  }
  return out;
}

const SERVER = new Map();
/** The server's GLSL of a model traced on the server (/api/shader), fetched once per
 * parameter set (synchronously: a drawing needs it now; the server answers from memory). */
function serverShader(record) {
  const key = JSON.stringify(record);
  let hit = SERVER.get(key);
  if (!hit) {
    const xhr = new XMLHttpRequest();
    xhr.open("GET", `api/shader?p=${encodeURIComponent(key)}`, false);
    xhr.send();
    if (xhr.status !== 200) throw new Error(`the server has no shader for ${record.model}: ${xhr.responseText}`);
    hit = JSON.parse(xhr.responseText);
    if (SERVER.size > 64) SERVER.delete(SERVER.keys().next().value);
    SERVER.set(key, hit);
  }
  return hit;
}

/**
 * The record the GLSL receives (models.glsl's RDParams): the model number of its menus'
 * values and the parameter-only values its prepass computes from the state (UI state with
 * sigmaDeg, or a record with sigma in radians already, as the tests send it); for a model
 * traced on the server, its GLSL function (`fn`, `source`), the values of its uniform array
 * `${fn}_u` and the number -2.
 */
export function gpuParams(s) {
  const m = BY_KEY[s.model];
  if (!m) throw new Error(`unknown model ${JSON.stringify(s.model)}`);
  if (m.shader.server) {
    const sh = serverShader(serverRecord(s));
    return { model: -2, h: new Float32Array(0), fn: sh.name, source: sh.source, values: Float32Array.from(sh.values) };
  }
  const choices = choicesOf(m, s);
  const v = m.shader.variants.find((x) => Object.entries(x.choices).every(([k, c]) => choices[k] === c));
  const p = {};
  for (const [k, q] of Object.entries(m.params)) if (q.choices === null) p[q.name] = valueOf(q, k, s);
  return { model: v.number, h: Float32Array.from(v.prepass(p)) };
}

/** Whether parameter `p` of a model applies with the slot state `s`: its declaration's
 * `when` (e.g. Coated's sigma only over an Oren–Nayar base) holds for the state's menus. */
export function applies(p, s) {
  return !p?.when || Object.entries(p.when).every(([k, vs]) => vs.includes(s[flatKey(k, s.model)]));
}

/** An alias's state (UI state or a record with radians) as its base model's record: the
 * alias's own parameter values (declared defaults for those missing) through its conversion,
 * traced on the server from its Python to_base (roughdiffuse.models.alias, `javascript`: a
 * function body; a colour channel by channel). */
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
  // eslint-disable-next-line no-new-func
  const convert = new Function("p", m.alias.javascript);
  const arrays = Object.values(own).find((v) => Array.isArray(v) || ArrayBuffer.isView(v));
  const channel = (c) => Object.fromEntries(Object.entries(own).map(([k, v]) => [k, typeof v === "number" ? v : v[c]]));
  const out = arrays ? [0, 1, 2].map((c) => convert(channel(c))) : [convert(own)];
  const base = { model: m.alias.base, ...m.alias.fixed };
  const declared = BY_KEY[m.alias.base].params;
  for (const name of Object.keys(out[0])) {
    const vs = out.map((o) => o[name]);
    const key = flatKey(name, m.alias.base);
    base[key] = declared[key]?.channels ? (vs.length === 3 ? vs : [vs[0], vs[0], vs[0]]) : vs[0];
  }
  return base;
}
