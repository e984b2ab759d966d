// Plots of radiance in the plane of incidence on a 2-D canvas: Cartesian (L against theta_r)
// and polar (radius L at angle theta_r from the normal). A series is
// {label, color, x: theta_r in degrees (signed), y: values, points: bool, dash: bool}.

const FONT = "12px system-ui, sans-serif";

function niceMax(v) {
  if (!(v > 0) || !Number.isFinite(v)) return 1;
  const e = Math.pow(10, Math.floor(Math.log10(v)));
  for (const m of [1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10]) if (m * e >= v) return m * e;
  return 10 * e;
}

function yMax(series) {
  let m = 0;
  for (const s of series) for (const y of s.y) if (Number.isFinite(y)) m = Math.max(m, y);
  return niceMax(m * 1.05);
}

/** The drawing size of a canvas in layout pixels: its pixels divided by `canvas.rdScale` (2
 *  for the 2x PNG export; the on-screen canvases have 1). */
export function canvasSize(canvas) {
  const s = canvas.rdScale ?? 1;
  return { W: canvas.width / s, H: canvas.height / s, s };
}

/** The 2-D context of `canvas`, scaled by its rdScale, cleared to white. */
export function prepare(canvas) {
  const ctx = canvas.getContext("2d");
  const { W, H, s } = canvasSize(canvas);
  ctx.setTransform(s, 0, 0, s, 0, 0);
  ctx.fillStyle = "#fff";
  ctx.fillRect(0, 0, W, H);
  ctx.font = FONT;
  return ctx;
}

/** Width of the legend box of `series` (its swatch, gap and longest label). */
function legendWidth(ctx, series) {
  return Math.max(0, ...series.map((s) => ctx.measureText(s.label).width)) + 30;
}

function legend(ctx, series, x, y) {
  const widest = Math.max(0, ...series.map((s) => ctx.measureText(s.label).width));
  ctx.fillStyle = "rgba(255, 255, 255, 0.85)";
  ctx.fillRect(x - 4, y - 14, widest + 30, 16 * series.length + 4);
  series.forEach((s, k) => {
    ctx.fillStyle = s.color;
    ctx.strokeStyle = s.color;
    if (s.points) {
      ctx.beginPath();
      ctx.arc(x + 8, y + 16 * k - 4, 3, 0, 2 * Math.PI);
      ctx.fill();
    } else {
      ctx.setLineDash(s.dash ? [4, 3] : []);
      ctx.beginPath();
      ctx.moveTo(x, y + 16 * k - 4);
      ctx.lineTo(x + 16, y + 16 * k - 4);
      ctx.stroke();
      ctx.setLineDash([]);
    }
    ctx.fillStyle = "#222";
    ctx.fillText(s.label, x + 22, y + 16 * k);
  });
}

/** The y axis: linear from 0, or log10 over at most `decades` decades below the largest value. */
function yAxis(series, log, decades = 4) {
  const ymax = yMax(series);
  if (!log) return { log, lo: 0, hi: ymax, ticks: [0, 1, 2, 3, 4].map((k) => (ymax * k) / 4) };
  let lo = Infinity;
  for (const s of series) for (const y of s.y) if (y > 0 && Number.isFinite(y)) lo = Math.min(lo, y);
  const hi = Math.pow(10, Math.ceil(Math.log10(ymax) - 1e-9));
  lo = Math.max(Math.pow(10, Math.floor(Math.log10(Number.isFinite(lo) ? lo : hi / 10))), hi / Math.pow(10, decades));
  if (!(lo < hi)) lo = hi / 10;
  const ticks = [];
  for (let t = lo; t <= hi * 1.0001; t *= 10) ticks.push(t);
  return { log, lo, hi, ticks };
}

/**
 * Cartesian plot; returns the number of points (markers) drawn. Options: x range and label
 * (default θr from -90° to 90°), `log` for a log10 y axis. The mapping from pixels to data is
 * kept on the canvas (`canvas.rdPlot`) for the hover readout (views.js).
 */
export function drawCartesian(canvas, series, {
  title = "", ylabel = "", log = false, xmin = -90, xmax = 90, xstep = 30,
  xlabel = "θr (degrees; > 0 on the light's side)",
} = {}) {
  const ctx = prepare(canvas);
  const { W, H } = canvasSize(canvas);
  // the legend goes beside the plot (or above it on a narrow canvas), never over the data
  const lw = legendWidth(ctx, series);
  const beside = W - lw - 74 >= 0.68 * W; // a wide canvas: the plot keeps 2/3 of it
  const L = 58, R = beside ? lw + 16 : 24, B = 40;
  const T = beside ? 26 : 30 + 16 * series.length;
  const ax = yAxis(series, log);
  const px = (x) => L + ((x - xmin) / (xmax - xmin)) * (W - L - R);
  const frac = (y) => (log ? (Math.log10(Math.max(y, ax.lo * 1e-3)) - Math.log10(ax.lo)) / Math.log10(ax.hi / ax.lo) : y / ax.hi);
  const py = (y) => H - B - Math.min(Math.max(frac(y), -0.05), 1.05) * (H - T - B);
  ctx.strokeStyle = "#ddd";
  ctx.fillStyle = "#444";
  ctx.lineWidth = 1;
  for (let x = xmin; x <= xmax; x += xstep) {
    ctx.beginPath(); ctx.moveTo(px(x), T); ctx.lineTo(px(x), H - B); ctx.stroke();
    ctx.fillText(`${x}°`, px(x) - 10, H - B + 15);
  }
  for (const y of ax.ticks) {
    ctx.beginPath(); ctx.moveTo(L, py(y)); ctx.lineTo(W - R, py(y)); ctx.stroke();
    ctx.fillText(log ? y.toExponential(0) : y.toPrecision(2), 4, py(y) + 4);
  }
  ctx.fillText(xlabel, L + 40, H - 6);
  ctx.fillStyle = "#222";
  ctx.fillText(title, L, 16);
  const yl = log ? `${ylabel} (log scale)` : ylabel;
  if (yl) ctx.fillText(yl, W - R - ctx.measureText(yl).width, 16);
  ctx.save();
  ctx.beginPath(); ctx.rect(L, T - 4, W - L - R, H - T - B + 8); ctx.clip();
  let drawn = 0;
  for (const s of series) {
    ctx.strokeStyle = ctx.fillStyle = s.color;
    ctx.lineWidth = 2;
    if (s.points) {
      s.x.forEach((x, k) => {
        if (!Number.isFinite(s.y[k])) return;
        ctx.beginPath(); ctx.arc(px(x), py(Math.min(s.y[k], ax.hi)), 3, 0, 2 * Math.PI); ctx.fill();
        drawn++;
      });
    } else {
      ctx.setLineDash(s.dash ? [5, 4] : []);
      ctx.beginPath();
      s.x.forEach((x, k) => (k ? ctx.lineTo(px(x), py(s.y[k])) : ctx.moveTo(px(x), py(s.y[k]))));
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }
  ctx.restore();
  if (beside) legend(ctx, series, W - R + 12, T + 14);
  else legend(ctx, series, L + 8, 34);
  canvas.rdPlot = { series, xmin, xmax, left: L, right: W - R, top: T, bottom: H - B, log, title };
  return drawn;
}

/** Polar plot: the normal points up, theta_r > 0 towards the right (the light's side). */
export function drawPolar(canvas, series, { title = "", lightDeg = null, log = false } = {}) {
  const ctx = prepare(canvas);
  const { W, H } = canvasSize(canvas);
  // the legend at the top right, the half disc below it and left of it: no overlap
  const lw = legendWidth(ctx, series), lh = 16 * series.length + 24;
  const cy = H - 24;
  let R = Math.min(H - 40, (W - 32) / 2), cx = W / 2;
  if (cy - R < lh + 4) { // the disc reaches the legend's height: keep it left of the legend
    cx = Math.min(W / 2, W - lw - 16 - R);
    if (cx - R < 16) { R = Math.max(40, (W - lw - 32) / 2); cx = 16 + R; }
  }
  const ax = yAxis(series, log);
  const ymax = ax.hi;
  // log: the radius runs over the decades from ax.lo (centre) to ax.hi (outer ring)
  const radius = (v) => (log ? Math.max(Math.log10(Math.max(v, ax.lo) / ax.lo) / Math.log10(ax.hi / ax.lo), 0) : Math.max(v, 0) / ymax);
  const pt = (deg, v) => {
    const a = (deg * Math.PI) / 180, r = radius(v) * R;
    return [cx + r * Math.sin(a), cy - r * Math.cos(a)];
  };
  ctx.strokeStyle = "#ddd";
  ctx.fillStyle = "#444";
  ctx.lineWidth = 1;
  for (let k = 1; k <= 4; k++) {
    ctx.beginPath(); ctx.arc(cx, cy, (R * k) / 4, Math.PI, 2 * Math.PI); ctx.stroke();
  }
  for (let d = -90; d <= 90; d += 30) {
    const [x, y] = pt(d, ymax);
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(x, y); ctx.stroke();
    ctx.fillText(`${d}°`, x - 10 + 8 * Math.sin((d * Math.PI) / 180), y - 4);
  }
  ctx.fillText(log ? `log scale: centre ${ax.lo.toExponential(0)}, outer ring ${ymax.toExponential(0)}` : `outer ring ${ymax.toPrecision(2)}`, 6, H - 6);
  if (lightDeg !== null) {
    const [x, y] = pt(lightDeg, ymax);
    ctx.strokeStyle = "#d9a400";
    ctx.setLineDash([2, 3]);
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(x, y); ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = "#b08000";
    ctx.fillText("light", x + 4, y + 12);
  }
  ctx.fillStyle = "#222";
  ctx.fillText(title, 8, 16);
  for (const s of series) {
    ctx.strokeStyle = ctx.fillStyle = s.color;
    ctx.lineWidth = 2;
    if (s.points) {
      s.x.forEach((x, k) => {
        if (!Number.isFinite(s.y[k])) return;
        const [u, v] = pt(x, Math.min(s.y[k], ymax));
        ctx.beginPath(); ctx.arc(u, v, 3, 0, 2 * Math.PI); ctx.fill();
      });
    } else {
      ctx.setLineDash(s.dash ? [5, 4] : []);
      ctx.beginPath();
      s.x.forEach((x, k) => {
        const [u, v] = pt(x, s.y[k]);
        k ? ctx.lineTo(u, v) : ctx.moveTo(u, v);
      });
      ctx.stroke();
      ctx.setLineDash([]);
    }
  }
  legend(ctx, series, W - lw, 20);
  canvas.rdPolar = { cx, cy, R, series };
}

/** Scatter of measured against model values with the identity line; returns points drawn. */
export function drawScatter(canvas, model, measured, { title = "" } = {}) {
  const ctx = prepare(canvas);
  const { W, H } = canvasSize(canvas);
  const L = 58, R = 24, T = 26, B = 40;
  let m = 0;
  for (let k = 0; k < model.length; k++) m = Math.max(m, model[k], measured[k]);
  const vmax = niceMax(m * 1.05);
  const px = (v) => L + (v / vmax) * (W - L - R);
  const py = (v) => H - B - (v / vmax) * (H - T - B);
  ctx.strokeStyle = "#ddd";
  ctx.fillStyle = "#444";
  for (let k = 0; k <= 4; k++) {
    const v = (vmax * k) / 4;
    ctx.beginPath(); ctx.moveTo(L, py(v)); ctx.lineTo(W - R, py(v)); ctx.stroke();
    ctx.beginPath(); ctx.moveTo(px(v), T); ctx.lineTo(px(v), H - B); ctx.stroke();
    ctx.fillText(v.toPrecision(2), 4, py(v) + 4);
    ctx.fillText(v.toPrecision(2), px(v) - 10, H - B + 15);
  }
  ctx.fillText("model A BRDF (1/sr)", L + 40, H - 6);
  ctx.fillStyle = "#222";
  ctx.fillText(title, L, 16);
  ctx.strokeStyle = "#888";
  ctx.beginPath(); ctx.moveTo(px(0), py(0)); ctx.lineTo(px(vmax), py(vmax)); ctx.stroke();
  ctx.fillStyle = "#c0392b";
  let drawn = 0;
  for (let k = 0; k < model.length; k++) {
    if (!Number.isFinite(model[k]) || !Number.isFinite(measured[k])) continue;
    ctx.beginPath(); ctx.arc(px(model[k]), py(measured[k]), 3, 0, 2 * Math.PI); ctx.fill();
    drawn++;
  }
  return drawn;
}
