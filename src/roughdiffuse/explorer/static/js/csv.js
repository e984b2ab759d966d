// BRDF samples from a CSV file, parsed in the browser. The format is the one
// roughdiffuse.fit.read_csv reads (src/roughdiffuse/fit/csv_samples.py), so one file serves both:
//
//   # irradiance = 2.0        (optional; for radiance values without an irradiance column)
//   theta_i_deg, theta_r_deg, delta_phi_deg, brdf
//   30, 45, 0, 0.2312
//
// Angles: theta_i, theta_r (theta_o) and delta_phi (phi_d), or phi_i and phi_r (phi_o); each
// states its unit: _deg / _rad, or "[deg]", "(rad)", "degrees", "radians". θ in [0, 90] degrees.
// Values: brdf (1/sr) or radiance (with an irradiance column or the '# irradiance = E0' line);
// for colour brdf_r, brdf_g, brdf_b (or radiance_r …). A unit in brackets after a value
// column ("brdf [1/sr]") is ignored. '#' starts a comment line; blank lines are skipped.
// Every error names the line (and the column).

export class CsvError extends Error {
  constructor(line, message) {
    super(`line ${line}: ${message}`);
    this.line = line;
  }
}

const UNIT = /^\s*([a-z_]+?)\s*(?:_|\s|\[|\()\s*(deg|degs|degree|degrees|rad|rads|radian|radians)\s*[\])]?\s*$/i;
const ANGLE_ALIASES = {
  theta_i: "theta_i", theta_r: "theta_r", theta_o: "theta_r", delta_phi: "delta_phi",
  phi_d: "delta_phi", dphi: "delta_phi", phi_i: "phi_i", phi_r: "phi_r", phi_o: "phi_r",
};
const CHANNEL_ALIASES = { r: "r", red: "r", g: "g", green: "g", b: "b", blue: "b" };

/** Role (and unit) of each column: theta_i…, brdf, brdf_r…, radiance…, irradiance. */
function classify(header, line) {
  const roles = header.map((raw) => {
    const low = raw.trim().toLowerCase();
    const base = low.replace(/\s*[[(].*[\])]\s*$/, "").trim();
    const m = low.match(UNIT);
    if (m && m[1].replace(/_+$/, "") in ANGLE_ALIASES) {
      return { role: ANGLE_ALIASES[m[1].replace(/_+$/, "")], unit: m[2].startsWith("deg") ? "deg" : "rad", raw: raw.trim() };
    }
    if (base in ANGLE_ALIASES) {
      throw new CsvError(line, `column '${raw.trim()}' must state its unit: ${base}_deg or ${base}_rad (or '${base} [deg]')`);
    }
    for (const kind of ["brdf", "radiance"]) {
      if (base === kind) return { role: kind, raw: raw.trim() };
      if (base.startsWith(`${kind}_`) && base.slice(kind.length + 1) in CHANNEL_ALIASES) {
        return { role: `${kind}_${CHANNEL_ALIASES[base.slice(kind.length + 1)]}`, raw: raw.trim() };
      }
    }
    if (base === "irradiance" || base === "e0") return { role: "irradiance", raw: raw.trim() };
    return { role: null, raw: raw.trim() };
  });
  const seen = {};
  roles.forEach((r, j) => {
    if (!r.role) return;
    if (r.role in seen) throw new CsvError(line, `columns '${roles[seen[r.role]].raw}' and '${r.raw}' both give ${r.role}`);
    seen[r.role] = j;
  });
  return { roles, index: seen };
}

/** Parse CSV text; returns {samples, channels}; throws CsvError naming the line. */
export function parseBrdfCsv(text) {
  const lines = text.split(/\r\n|\n|\r/);
  let irradiance = null;
  let k = 0;
  for (; k < lines.length; k++) {
    const t = lines[k].trim();
    if (t === "") continue;
    if (!t.startsWith("#")) break;
    const m = t.match(/^#\s*irradiance\s*=\s*(\S+)\s*$/i);
    if (m) {
      irradiance = Number(m[1]);
      if (!(irradiance > 0) || !Number.isFinite(irradiance)) {
        throw new CsvError(k + 1, `irradiance must be a number > 0 (got '${m[1]}')`);
      }
    }
  }
  if (k >= lines.length) throw new CsvError(lines.length, "no header line (theta_i_deg, theta_r_deg, delta_phi_deg, brdf)");
  const headerLine = k + 1;
  const header = lines[k].split(",");
  const { roles, index } = classify(header, headerLine);
  for (const need of ["theta_i", "theta_r"]) {
    if (!(need in index)) throw new CsvError(headerLine, `no ${need} column (e.g. '${need}_deg' or '${need}_rad')`);
  }
  let azimuth;
  if ("delta_phi" in index) azimuth = "delta";
  else if ("phi_i" in index && "phi_r" in index) azimuth = "pair";
  else throw new CsvError(headerLine, "no azimuth: give delta_phi, or phi_i and phi_r (with units)");
  const kinds = ["brdf", "radiance"].filter((kd) => kd in index || `${kd}_r` in index || `${kd}_g` in index || `${kd}_b` in index);
  if (kinds.length !== 1) {
    throw new CsvError(headerLine, "give exactly one kind of value column: 'brdf' (1/sr) or 'radiance' (or brdf_r, brdf_g, brdf_b …)");
  }
  const kind = kinds[0];
  const valueRoles = kind in index ? [kind] : ["r", "g", "b"].map((c) => `${kind}_${c}`);
  const missing = valueRoles.filter((r) => !(r in index));
  if (missing.length) throw new CsvError(headerLine, `colour columns ${missing.join(", ")} missing`);
  if (kind === "radiance" && !("irradiance" in index) && irradiance === null) {
    throw new CsvError(headerLine, "radiance values need the irradiance: an 'irradiance' column or a line '# irradiance = E0' before the header");
  }
  if (kind === "brdf" && "irradiance" in index) {
    throw new CsvError(headerLine, "an irradiance column only makes sense with radiance values");
  }
  const samples = [];
  for (let i = k + 1; i < lines.length; i++) {
    const raw = lines[i].trim();
    if (raw === "" || raw.startsWith("#")) continue;
    const line = i + 1;
    const cells = raw.split(",");
    if (cells.length !== header.length) {
      throw new CsvError(line, `expected ${header.length} values (as in the header), found ${cells.length}`);
    }
    const num = (role) => {
      const j = index[role];
      const t = cells[j].trim();
      if (t === "") throw new CsvError(line, `column '${roles[j].raw}': missing value`);
      const v = Number(t);
      if (!Number.isFinite(v)) throw new CsvError(line, `column '${roles[j].raw}': not a number ('${t}')`);
      return v;
    };
    const angle = (role) => (roles[index[role]].unit === "deg" ? num(role) * (Math.PI / 180) : num(role));
    const theta = {};
    for (const role of ["theta_i", "theta_r"]) {
      const v = num(role);
      const deg = roles[index[role]].unit === "deg";
      const top = deg ? 90 : Math.PI / 2;
      if (v < 0 || v > top * (1 + 1e-12)) {
        throw new CsvError(line, `column '${roles[index[role]].raw}': angle ${v} out of range ${deg ? "[0, 90] degrees" : "[0, π/2] radians"}`);
      }
      theta[role] = Math.min(angle(role), Math.PI / 2);
    }
    const deltaPhi = azimuth === "delta" ? angle("delta_phi") : angle("phi_r") - angle("phi_i");
    let vals = valueRoles.map((r) => {
      const v = num(r);
      if (v < 0) throw new CsvError(line, `column '${roles[index[r]].raw}': negative value ${v}`);
      return v;
    });
    if (kind === "radiance") {
      const e0 = "irradiance" in index ? num("irradiance") : irradiance;
      if (!(e0 > 0)) throw new CsvError(line, `column '${roles[index.irradiance].raw}': irradiance must be > 0 (got ${e0})`);
      const cosI = Math.cos(theta.theta_i);
      if (!(cosI > 0)) throw new CsvError(line, "radiance at θi = 90° cannot be turned into a BRDF (cos θi = 0)");
      vals = vals.map((v) => v / (e0 * cosI));
    }
    const value = vals.length === 1 ? [vals[0], vals[0], vals[0]] : vals;
    samples.push({ line, thetaI: theta.theta_i, thetaR: theta.theta_r, deltaPhi, value });
  }
  if (samples.length === 0) throw new CsvError(headerLine, "no samples after the header");
  return { samples, channels: valueRoles.length };
}
