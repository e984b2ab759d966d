// A canvas stand-in that records the 2-D drawing calls the plots make (plot.js, views.js) and
// writes them as SVG: the "Export SVG" of a view draws into it with the same code that draws
// on screen. Lines, arcs, rectangles and text become SVG elements; an image (the θh/θd map)
// becomes an <image> holding its pixels as PNG. Only the calls the plots use are supported.

const esc = (s) => String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;").replace(/"/g, "&quot;");
const num = (v) => (Math.round(v * 100) / 100).toString();

class SvgContext {
  constructor(width, height) {
    this.width = width;
    this.height = height;
    this.parts = [];
    this.fillStyle = "#000";
    this.strokeStyle = "#000";
    this.lineWidth = 1;
    this.font = "12px system-ui, sans-serif";
    this.imageSmoothingEnabled = true;
    this.dash = [];
    this.path = "";
    this.m = [1, 0, 0, 1, 0, 0]; // a, b, c, d, e, f as in setTransform
    this.stack = [];
    this.clipId = null;
    this.clips = 0;
    const scratch = document.createElement("canvas");
    this.measure = scratch.getContext("2d");
  }
  // ---- state
  save() { this.stack.push({ m: [...this.m], fillStyle: this.fillStyle, strokeStyle: this.strokeStyle, lineWidth: this.lineWidth, font: this.font, dash: this.dash, clipId: this.clipId }); }
  restore() { Object.assign(this, this.stack.pop() ?? {}); }
  setTransform(a, b, c, d, e, f) { this.m = [a, b, c, d, e, f]; }
  translate(x, y) { const [a, b, c, d, e, f] = this.m; this.m = [a, b, c, d, e + a * x + c * y, f + b * x + d * y]; }
  rotate(t) { const [a, b, c, d, e, f] = this.m, cs = Math.cos(t), sn = Math.sin(t); this.m = [a * cs + c * sn, b * cs + d * sn, c * cs - a * sn, d * cs - b * sn, e, f]; }
  setLineDash(d) { this.dash = [...d]; }
  measureText(text) { this.measure.font = this.font; return this.measure.measureText(text); }
  createImageData(w, h) { return this.measure.createImageData(w, h); }
  // ---- paths
  pt(x, y) { const [a, b, c, d, e, f] = this.m; return [a * x + c * y + e, b * x + d * y + f]; }
  beginPath() { this.path = ""; }
  moveTo(x, y) { const [u, v] = this.pt(x, y); this.path += `M${num(u)} ${num(v)}`; }
  lineTo(x, y) { const [u, v] = this.pt(x, y); this.path += `L${num(u)} ${num(v)}`; }
  closePath() { this.path += "Z"; }
  rect(x, y, w, h) { this.moveTo(x, y); this.lineTo(x + w, y); this.lineTo(x + w, y + h); this.lineTo(x, y + h); this.closePath(); }
  arc(x, y, r, a0, a1) {
    const n = Math.max(8, Math.ceil((Math.abs(a1 - a0) / (2 * Math.PI)) * 48));
    for (let k = 0; k <= n; k++) {
      const a = a0 + ((a1 - a0) * k) / n;
      const [u, v] = this.pt(x + r * Math.cos(a), y + r * Math.sin(a));
      this.path += `${k === 0 && this.path === "" ? "M" : "L"}${num(u)} ${num(v)}`;
    }
  }
  clip() {
    const id = `clip${++this.clips}`;
    this.parts.push(`<clipPath id="${id}"><path d="${this.path}"/></clipPath>`);
    this.clipId = id;
  }
  attrs() { return this.clipId ? ` clip-path="url(#${this.clipId})"` : ""; }
  stroke() {
    const dash = this.dash.length ? ` stroke-dasharray="${this.dash.join(" ")}"` : "";
    const w = this.lineWidth * Math.hypot(this.m[0], this.m[1]);
    this.parts.push(`<path d="${this.path}" fill="none" stroke="${esc(this.strokeStyle)}" stroke-width="${num(w)}"${dash}${this.attrs()}/>`);
  }
  fill() { this.parts.push(`<path d="${this.path}" fill="${esc(this.fillStyle)}"${this.attrs()}/>`); }
  fillRect(x, y, w, h) { this.beginPath(); this.rect(x, y, w, h); this.fill(); }
  fillText(text, x, y) {
    const [a, b, c, d, e, f] = this.m;
    const size = parseFloat(this.font) || 12;
    const tr = `matrix(${[a, b, c, d, e, f].map(num).join(" ")})`;
    this.parts.push(`<text x="${num(x)}" y="${num(y)}" transform="${tr}" font-family="system-ui, sans-serif" font-size="${size}" fill="${esc(this.fillStyle)}"${this.attrs()}>${esc(text)}</text>`);
  }
  drawImage(img, x, y, w, h) {
    const [p, q] = this.pt(x, y);
    const smooth = this.imageSmoothingEnabled ? "" : ' style="image-rendering:pixelated"';
    this.parts.push(`<image x="${num(p)}" y="${num(q)}" width="${num(w * this.m[0])}" height="${num(h * this.m[3])}" preserveAspectRatio="none" href="${img.toDataURL("image/png")}"${smooth}/>`);
  }
}

/** A canvas-like object of `width` × `height` that draws into SVG; `.svg()` gives the text. */
export function svgCanvas(width, height) {
  const ctx = new SvgContext(width, height);
  return {
    width,
    height,
    rdScale: 1,
    getContext: () => ctx,
    svg: () =>
      `<svg xmlns="http://www.w3.org/2000/svg" width="${width}" height="${height}" viewBox="0 0 ${width} ${height}">` +
      ctx.parts.join("") + "</svg>\n",
  };
}
