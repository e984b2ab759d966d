// BRDF samples from a CSV file, parsed in the browser.
//
// Format: a header line, then one sample per line, comma-separated; '#' starts a comment
// line; blank lines are skipped. Columns (any order, case-insensitive):
//   theta_i, theta_r                      incidence and viewing angles, [0, 90] degrees
//   delta_phi  or  phi_i and phi_r        azimuth difference phi_r - phi_i (or both azimuths)
//   brdf  or  brdf_r, brdf_g, brdf_b      BRDF value(s) in 1/sr, >= 0
// Angles are in degrees unless the column name ends in _rad or "(rad)"/"[rad]"
// (_deg / "(deg)" say degrees explicitly). Other columns are ignored.

export class CsvError extends Error {
  constructor(line, message) {
    super(`line ${line}: ${message}`);
    this.line = line;
  }
}

function parseHeaderName(raw) {
  let name = raw.trim().toLowerCase().replace(/\s+/g, "");
  let unit = null;
  const m = name.match(/^(.*?)(?:_|\(|\[)(deg|rad|degrees|radians)[)\]]?$/);
  if (m) {
    name = m[1];
    unit = m[2].startsWith("rad") ? "rad" : "deg";
  }
  return { name, unit };
}

const ANGLES = ["theta_i", "theta_r", "delta_phi", "phi_i", "phi_r"];

/** Parse CSV text; returns {samples, channels}; throws CsvError naming the line. */
export function parseBrdfCsv(text) {
  const lines = text.split(/\r\n|\n|\r/);
  let k = 0;
  while (k < lines.length && (lines[k].trim() === "" || lines[k].trim().startsWith("#"))) k++;
  if (k >= lines.length) throw new CsvError(1, "the file is empty (a header line is expected)");
  const headerLine = k + 1;
  const header = lines[k].split(",").map(parseHeaderName);
  const col = {};
  header.forEach((h, j) => {
    if (h.name in col) throw new CsvError(headerLine, `column '${h.name}' appears twice`);
    col[h.name] = j;
  });
  const need = (name) => {
    if (!(name in col)) {
      const names = header.map((h) => h.name).join(", ");
      throw new CsvError(headerLine, `no '${name}' column (header has: ${names})`);
    }
  };
  need("theta_i");
  need("theta_r");
  const azimuth = "delta_phi" in col ? "delta" : "phi_i" in col || "phi_r" in col ? "pair" : null;
  if (azimuth === null) need("delta_phi");
  if (azimuth === "pair") { need("phi_i"); need("phi_r"); }
  let valueCols;
  if ("brdf" in col) valueCols = ["brdf"];
  else if ("brdf_r" in col || "brdf_g" in col || "brdf_b" in col) valueCols = ["brdf_r", "brdf_g", "brdf_b"];
  else need("brdf");
  valueCols.forEach(need);
  const toRad = {};
  for (const a of ANGLES) {
    if (a in col) toRad[a] = header[col[a]].unit === "rad" ? 1 : Math.PI / 180;
  }
  const samples = [];
  for (let i = k + 1; i < lines.length; i++) {
    const raw = lines[i].trim();
    if (raw === "" || raw.startsWith("#")) continue;
    const line = i + 1;
    const cells = raw.split(",");
    if (cells.length !== header.length) {
      throw new CsvError(line, `expected ${header.length} values, found ${cells.length}`);
    }
    const num = (name) => {
      const text = cells[col[name]].trim();
      const v = text === "" ? NaN : Number(text);
      if (!Number.isFinite(v)) {
        throw new CsvError(line, `column '${name}': ${text === "" ? "missing value" : `'${text}' is not a number`}`);
      }
      return v;
    };
    const angle = (name) => num(name) * toRad[name];
    const thetaI = angle("theta_i");
    const thetaR = angle("theta_r");
    for (const [name, v] of [["theta_i", thetaI], ["theta_r", thetaR]]) {
      if (v < 0 || v > Math.PI / 2 + 1e-9) {
        throw new CsvError(line, `column '${name}': ${num(name)} is outside [0, 90] degrees`);
      }
    }
    const deltaPhi = azimuth === "delta" ? angle("delta_phi") : angle("phi_r") - angle("phi_i");
    const vals = valueCols.map((c) => {
      const v = num(c);
      if (v < 0) throw new CsvError(line, `column '${c}': a BRDF cannot be negative (${v})`);
      return v;
    });
    const value = vals.length === 1 ? [vals[0], vals[0], vals[0]] : vals;
    samples.push({ line, thetaI, thetaR, deltaPhi, value });
  }
  if (samples.length === 0) throw new CsvError(headerLine, "no samples after the header");
  return { samples, channels: valueCols.length };
}
