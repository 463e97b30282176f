// scatter.js - a canvas scatter plot made for accumulating points: new
// points are drawn onto a persistent layer (no full redraw per frame); a
// full redraw happens only when the axes' range grows or the units change.
// Axes with ticks, labels (with units) and optional horizontal guide lines.

const PAD = { l: 62, r: 12, t: 10, b: 40 };

function niceTicks(lo, hi, n = 5) {
  const span = hi - lo;
  if (!(span > 0)) return [lo];
  const step0 = span / n;
  const mag = 10 ** Math.floor(Math.log10(step0));
  const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= step0) ?? step0;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(+v.toPrecision(12));
  return out;
}

export class Scatter {
  // el: a container element; opts: {xlabel, ylabel, max (points kept), size (dot px)}
  constructor(el, opts) {
    this.el = el;
    this.opts = { max: 50000, size: 2, ...opts };
    this.canvas = document.createElement("canvas");
    el.appendChild(this.canvas);
    this.ctx = this.canvas.getContext("2d");
    this.pts = []; // [x, y, colour]
    this.drawn = 0; // points already on the canvas
    this.range = null; // {x0, x1, y0, y1}
    this.guides = []; // horizontal lines [{y, colour}]
    this.fx = 1; this.fy = 1; // display factors (units)
    this.dirty = true;
    this.resize();
  }
  resize() {
    const r = this.el.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    this.w = Math.max(200, Math.floor(r.width));
    this.h = Math.max(150, Math.floor(r.height));
    this.canvas.width = this.w * dpr;
    this.canvas.height = this.h * dpr;
    this.canvas.style.width = this.w + "px";
    this.canvas.style.height = this.h + "px";
    this.ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    this.dirty = true;
  }
  setLabels(xlabel, ylabel, fx = 1, fy = 1) {
    if (xlabel !== this.opts.xlabel || ylabel !== this.opts.ylabel || fx !== this.fx || fy !== this.fy) {
      Object.assign(this.opts, { xlabel, ylabel });
      this.fx = fx; this.fy = fy; this.dirty = true;
    }
  }
  setGuides(g) { if (JSON.stringify(g) !== JSON.stringify(this.guides)) { this.guides = g; this.dirty = true; } }
  clear() { this.pts = []; this.drawn = 0; this.range = null; this.dirty = true; }
  get count() { return this.pts.length; }
  add(x, y, colour) {
    if (!Number.isFinite(x) || !Number.isFinite(y)) return;
    this.pts.push([x, y, colour]);
    if (this.pts.length > this.opts.max) { this.pts.splice(0, this.pts.length - this.opts.max); this.dirty = true; }
    const r = this.range;
    if (!r || x < r.x0 || x > r.x1 || y < r.y0 || y > r.y1) this.grow(x, y);
  }
  // Replace every point (e.g. the phase portrait's window).
  set(points) { this.pts = []; this.range = null; for (const p of points) this.add(...p); this.dirty = true; }
  grow(x, y) {
    const r = this.range ?? { x0: x, x1: x, y0: y, y1: y };
    for (const g of this.guides) { r.y0 = Math.min(r.y0, g.y); r.y1 = Math.max(r.y1, g.y); }
    const g = this.opts.grow ?? 0.1; // margin added when the range grows (fewer full redraws)
    const mx = (Math.max(r.x1, x) - Math.min(r.x0, x)) * g || Math.abs(x) * 0.05 || 0.1;
    const my = (Math.max(r.y1, y) - Math.min(r.y0, y)) * g || Math.abs(y) * 0.05 || 0.1;
    const n = {
      x0: x < r.x0 ? x - mx : r.x0, x1: x > r.x1 ? x + mx : r.x1,
      y0: y < r.y0 ? y - my : r.y0, y1: y > r.y1 ? y + my : r.y1,
    };
    // Never a zero-width axis (e.g. every section at one omega): +-2 % around it.
    for (const [a, b] of [["x0", "x1"], ["y0", "y1"]]) {
      if (n[b] - n[a] < 1e-9 * Math.abs(n[a]) + 1e-12) {
        const d = Math.max(Math.abs(n[a]) * 0.02, 0.01);
        n[a] -= d; n[b] += d;
      }
    }
    this.range = n;
    this.dirty = true;
  }
  px(x) { const r = this.range; return PAD.l + ((x - r.x0) / (r.x1 - r.x0 || 1)) * (this.w - PAD.l - PAD.r); }
  py(y) { const r = this.range; return this.h - PAD.b - ((y - r.y0) / (r.y1 - r.y0 || 1)) * (this.h - PAD.t - PAD.b); }
  axes() {
    const c = this.ctx, r = this.range;
    c.clearRect(0, 0, this.w, this.h);
    c.strokeStyle = "#999"; c.fillStyle = "#222"; c.lineWidth = 1; c.font = "11px sans-serif";
    c.strokeRect(PAD.l, PAD.t, this.w - PAD.l - PAD.r, this.h - PAD.t - PAD.b);
    if (!r) return;
    c.textAlign = "center"; c.textBaseline = "top";
    for (const v of niceTicks(r.x0 * this.fx, r.x1 * this.fx)) {
      const X = this.px(v / this.fx);
      c.beginPath(); c.moveTo(X, this.h - PAD.b); c.lineTo(X, this.h - PAD.b + 4); c.stroke();
      c.fillText(String(+v.toPrecision(6)), X, this.h - PAD.b + 5);
    }
    c.textAlign = "right"; c.textBaseline = "middle";
    for (const v of niceTicks(r.y0 * this.fy, r.y1 * this.fy)) {
      const Y = this.py(v / this.fy);
      c.beginPath(); c.moveTo(PAD.l - 4, Y); c.lineTo(PAD.l, Y); c.stroke();
      c.fillText(String(+v.toPrecision(6)), PAD.l - 6, Y);
    }
    c.textAlign = "center"; c.textBaseline = "bottom";
    c.fillText(this.opts.xlabel ?? "", PAD.l + (this.w - PAD.l - PAD.r) / 2, this.h - 2);
    c.save(); c.translate(12, PAD.t + (this.h - PAD.t - PAD.b) / 2); c.rotate(-Math.PI / 2);
    c.textBaseline = "middle"; c.fillText(this.opts.ylabel ?? "", 0, 0); c.restore();
    c.setLineDash([5, 4]);
    for (const g of this.guides) {
      c.strokeStyle = g.colour; const Y = this.py(g.y);
      c.beginPath(); c.moveTo(PAD.l, Y); c.lineTo(this.w - PAD.r, Y); c.stroke();
    }
    c.setLineDash([]);
  }
  // Draw what is new (everything after a change of range, size or units).
  draw() {
    if (this.dirty) { this.axes(); this.drawn = 0; this.dirty = false; }
    if (!this.range) return 0;
    const c = this.ctx, s = this.opts.size;
    c.save();
    c.beginPath(); c.rect(PAD.l, PAD.t, this.w - PAD.l - PAD.r, this.h - PAD.t - PAD.b); c.clip();
    let n = 0, cur = null;
    const r = this.range, ax = (this.w - PAD.l - PAD.r) / (r.x1 - r.x0 || 1), ay = (this.h - PAD.t - PAD.b) / (r.y1 - r.y0 || 1);
    const bx = PAD.l - r.x0 * ax - s / 2, by = this.h - PAD.b + r.y0 * ay - s / 2;
    for (let i = this.drawn; i < this.pts.length; i++, n++) {
      const p = this.pts[i];
      if (p[2] !== cur) c.fillStyle = cur = p[2];
      c.fillRect(bx + p[0] * ax, by - p[1] * ay, s, s);
    }
    c.restore();
    this.drawn = this.pts.length;
    return n;
  }
}
