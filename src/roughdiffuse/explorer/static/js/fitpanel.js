// Fitting from the page: model A fitted to the loaded data on the server (POST api/fit, with
// roughdiffuse.fit.fit), its sliders moved to the result; every registry model ranked by BIC
// (POST api/rank, roughdiffuse.fit.compare_models), one model per request so that the table
// grows as the fits finish and no request holds the server for long (Coated's request fits it
// over each of its bases: one row per base, labelled "coated base=eon").
//
// Interface: setupFit(hooks) with hooks {modelA() -> registry id, choicesA() -> the values of
// its menus (Coated's base), applyToA(updates)};
// fitA() and rank(models) return promises (the tests call them through window.rdData).

import { dataset, onDataset } from "./data.js";
import { BY_KEY, PARAMS, flatKey } from "./models.js";

const $ = (id) => document.getElementById(id);
const DEG = Math.PI / 180;
let hooks = null;
let generation = 0; // a new dataset or a new ranking makes older answers stale

function setStatus(text, isError = false, id = "fit-status") {
  const el = $(id);
  el.textContent = text;
  el.classList.toggle("error", isError);
}

async function post(path, body) {
  const r = await fetch(path, { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body) });
  let out;
  try {
    out = await r.json();
  } catch {
    out = { error: `the server answered HTTP ${r.status}` };
  }
  if (!r.ok) throw new Error(out.error ?? `HTTP ${r.status}`);
  return out;
}

const fmt = (v) => (v === null ? "∞" : Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(3) : v.toPrecision(4));

/** "σ", "albedo R"… and the value in the slider's unit (degrees for an angle); no standard
 * error at a bound or where it is not determined (note from roughdiffuse.fit.summary). */
function describe(model, name, value, error, note = "") {
  const m = name.match(/^(\w+)(?:\[(\d)\])?$/);
  const key = flatKey(m[1], model);
  const chan = m[2] === undefined ? "" : ` ${"RGB"[Number(m[2])]}`;
  const q = PARAMS[key];
  const deg = q && q.unit === "radians" && value !== null;
  const err = note === "at bound" ? " (at bound)" : error === null ? " ± not determined" : deg ? ` ± ${(error / DEG).toPrecision(2)}°` : ` ± ${error.toPrecision(2)}`;
  if (deg) return { label: `${m[1]}${chan}`, text: `${(value / DEG).toFixed(3)}°${err} (${fmt(value)} rad)` };
  return { label: `${m[1]}${chan}`, text: `${fmt(value)}${err}` };
}

/** The state updates of slot A for a fit result (names as roughdiffuse.fit gives them). */
export function updatesFor(result) {
  const u = {};
  result.names.forEach((name, k) => {
    const v = result.values[k];
    if (v === null) return;
    const m = name.match(/^(\w+)(?:\[(\d)\])?$/);
    const key = flatKey(m[1], result.model);
    const q = PARAMS[key];
    if (!q) return;
    if (q.channels) {
      u[key] = u[key] ?? [null, null, null];
      if (m[2] === undefined) u[key] = [v, v, v];
      else u[key][Number(m[2])] = v;
    } else if (q.unit === "radians") u[`${key}Deg`] = v / DEG;
    else u[key] = v;
  });
  return u;
}

/** Fit model A to the dataset; show the values with their standard errors; move A's sliders. */
export async function fitA() {
  if (!dataset || !dataset.id) throw new Error("load a dataset first");
  const model = hooks.modelA();
  const gen = generation;
  document.body.dataset.fit = "running";
  setStatus(`fitting ${BY_KEY[model]?.short ?? model} to ${dataset.fit_samples} samples of ${dataset.name} on the server…`);
  let r;
  try {
    r = await post("api/fit", { dataset: dataset.id, model, choices: hooks.choicesA() }); // the slot's menus: Coated's base
  } catch (err) {
    if (gen === generation) {
      setStatus(`no fit: ${err.message}`, true);
      document.body.dataset.fit = "error";
    }
    return null;
  }
  if (gen !== generation) return null;
  const rows = r.names.map((n, k) => {
    const note = r.error_notes[k];
    const d = describe(r.model, n, r.values[k], r.errors[k], note);
    return `<tr data-note="${note}"><td>${d.label}</td><td>${d.text}</td><td>${note}</td></tr>`;
  });
  $("fit-table").innerHTML = `<caption>${BY_KEY[model]?.short ?? model}, fitted (± standard error, ${r.noise} noise)</caption>` + rows.join("");
  const warn = r.warnings.length ? ` ${r.warnings.join(" ")}` : "";
  setStatus(`RMS residual ${fmt(r.rms)} 1/sr (${(100 * r.rms_relative).toPrecision(3)}% of the data), ` +
    `${r.residuals} residuals from ${r.fit_samples} of ${r.samples} samples; BIC ${r.bic === null ? "–" : r.bic.toFixed(1)}.${warn}`);
  hooks.applyToA(updatesFor(r));
  document.body.dataset.fit = "done";
  window.rdData.lastFit = r;
  return r;
}

/** Rank models (default: every fittable registry model) by BIC, one request per model. */
export async function rank(models = null) {
  if (!dataset || !dataset.id) throw new Error("load a dataset first");
  const ids = models ?? dataset.candidates;
  const gen = ++generation;
  const done = [];
  document.body.dataset.rank = "running";
  const table = $("rank-table");
  const show = () => {
    done.sort((a, b) => (a.bic ?? Infinity) - (b.bic ?? Infinity));
    const best = done.length ? done[0].bic : 0;
    table.innerHTML = "<caption>models ranked by BIC (lower is better)</caption><tr><th>#</th><th>model</th><th>ΔBIC</th><th>RMS %</th><th>parameters</th></tr>" +
      done.map((r, k) => `<tr data-model="${r.model}" data-label="${r.label}"><td>${k + 1}</td><td>${r.label}</td><td>${r.bic === null ? "–" : (r.bic - best).toFixed(1)}</td>` +
        `<td>${(100 * r.rms_relative).toPrecision(3)}</td><td>${r.names.map((n, j) => describe(r.model, n, r.values[j], r.errors[j], r.error_notes[j])).map((d) => `${d.label} ${d.text}`).join("; ")}</td></tr>`).join("");
  };
  for (const [k, id] of ids.entries()) {
    if (gen !== generation) return null;
    setStatus(`ranking by BIC: fitting ${id} (${k + 1} of ${ids.length})…`, false, "rank-status");
    let r;
    try {
      r = await post("api/rank", { dataset: dataset.id, models: [id] });
    } catch (err) {
      if (gen === generation) {
        setStatus(`ranking stopped at ${id}: ${err.message}`, true, "rank-status");
        document.body.dataset.rank = "error";
      }
      return null;
    }
    if (gen !== generation) return null;
    done.push(...r.ranking); // coated: one row per base
    show();
  }
  setStatus(`${done.length} models ranked by BIC on ${dataset.fit_samples} samples; best: ${done[0].label}.`, false, "rank-status");
  document.body.dataset.rank = "done";
  return done.map((r) => r.label);
}

/** Wire the buttons; hooks: {modelA() -> id, choicesA() -> menus, applyToA(updates)}. */
export function setupFit(h) {
  hooks = h;
  window.rdData = { ...(window.rdData ?? {}), fitA, rank };
  const report = (err) => setStatus(String(err.message || err), true);
  $("fit-run").addEventListener("click", () => fitA().catch(report));
  $("fit-rank").addEventListener("click", () => rank().catch((err) => setStatus(String(err.message || err), true, "rank-status")));
  onDataset((ds) => {
    generation++;
    $("fit-panel").hidden = !ds;
    const ok = Boolean(ds && ds.id);
    $("fit-run").disabled = $("fit-rank").disabled = !ok;
    $("fit-table").innerHTML = "";
    $("rank-table").innerHTML = "";
    setStatus("", false, "rank-status");
    setStatus(ok ? `fits use ${ds.fit_samples} of the ${ds.total} samples.` : ds ? "this dataset could not be sent to the server: no fits" : "");
  });
}
