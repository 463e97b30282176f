// app.js - the wormgear dashboard: connects to wgweb's Foxglove WebSocket
// (same host and port as the page), plots the scope, phase portrait,
// Poincare map and live bifurcation diagram, shows status, sends commands.
// A test hook, window.wgTest, exposes counts, frame intervals and
// publish-to-screen latencies (tests/bench read it).
import { connect } from "./fox.js";
import { Scatter } from "./scatter.js";
import { Units } from "./units.js";

const $ = (id) => document.getElementById(id);
const RING = 16384;
const REGIME_COLOUR = { "period-1": "#1f77b4", "period-2": "#2ca02c", "period-3": "#9467bd",
  "period-4": "#ff7f0e", aperiodic: "#d62728", ramping: "#7f7f7f", unknown: "#b0b0b0" };
const MOTION_COLOUR = { no_impact: "#17becf", single_sided: "#bcbd22", double_sided: "#e377c2" };
const regimeColour = (r) => REGIME_COLOUR[r] ?? (/^period-/.test(r) ? "#8c564b" : "#b0b0b0");

const units = new Units();
const S = {
  fox: null, params: null, status: null, bridge: null, statusWall: 0, connected: false,
  scope: { t: new Float64Array(RING), step: new Float64Array(RING), x: new Float64Array(RING),
    dx: new Float64Array(RING), F: new Float64Array(RING), utime: new Float64Array(RING), n: 0 },
  impacts: [], newScope: false, newestUtime: 0, myIds: new Set(), reqSeq: 0, theta: null,
};
const T = (window.wgTest = { scope: 0, poincare: 0, contacts: 0, acks: [], frameIntervals: [],
  latencies: [], work: [], frames: 0, status: null, params: null, errors: [], badAngles: 0 });

// ---- incoming messages
function pushScope(m) {
  const s = S.scope, i = s.n % RING;
  s.t[i] = m.t_s; s.step[i] = m.step; s.x[i] = m.x_n; s.dx[i] = m.dx_n; s.F[i] = m.F; s.utime[i] = m.utime;
  if (s.n > 0 && m.step < s.step[(s.n - 1) % RING]) s.n = 0, S.impacts = []; // reset or restart
  s.n++; S.newScope = true; S.newestUtime = m.utime; T.scope++;
  if (m.theta1 !== undefined) { // shown only when both are angles, [0, 2π) (a NaN arrives as null)
    const ok = isAngle(m.theta1) && isAngle(m.theta2);
    S.theta = ok ? [m.theta1, m.theta2] : null;
    if (!ok) T.badAngles++;
  }
}
function isAngle(a) { return typeof a === "number" && a >= 0 && a < 2 * Math.PI; }

function onPoincare(m) {
  T.poincare++;
  plots.poincare.add(m.x_n, m.dx_n, "rgba(31,119,180,0.55)");
  const by = $("colour").value, known = /^(period-|aperiodic)/.test(m.regime);
  const col = by === "regime" || (by === "auto" && known) ? regimeColour(m.regime) : MOTION_COLOUR[m.motion] ?? "#999";
  plots.bif.add(m.omega, m.x_n, col);
}

function onContact(m) {
  T.contacts++;
  if (m.contact === "mesh" && (m.kind === "drive_impact" || m.kind === "back_impact")) {
    S.impacts.push({ t: m.t_s, side: m.kind === "drive_impact" ? 1 : -1 });
    if (S.impacts.length > 4000) S.impacts.splice(0, 1000);
  }
}

function onParams(m) {
  const first = !S.params;
  const reset = S.params && ["set", "reset", "restore"].includes(m.reason) &&
    JSON.stringify(m.values) !== JSON.stringify(S.params.values);
  S.params = T.params = m;
  units.setScale(m);
  if (reset) plots.poincare.clear();
  if (first) fillControls();
  updateCaption();
}

function onAck(m) {
  T.acks.push(m);
  if (!S.myIds.has(m.request_id)) return;
  const r = $("cmd-result");
  r.textContent = `${m.op}: ${m.code}${m.message ? " — " + m.message : ""}`;
  r.className = "result " + (m.accepted ? "ok" : "bad");
}

const handlers = {
  "/scope": pushScope, "/poincare": onPoincare, "/contact": onContact, "/params": onParams,
  "/ack": onAck,
  "/status": (m) => { S.status = T.status = m; S.statusWall = performance.now(); },
  "/bridge": (m) => { S.bridge = m; },
};

function start() {
  S.fox = connect(`ws://${location.host}/`, {
    open: () => { S.connected = true; },
    close: () => { S.connected = false; setTimeout(start, 2000); },
    serverInfo: () => enableControls(),
    status: (m) => { T.errors.push(m); if (m.level >= 2) showResult(m.message, false); },
    message: (topic, obj) => handlers[topic]?.(obj),
  });
  S.fox.subscribe(Object.keys(handlers));
}

// ---- controls
function showResult(text, ok) { const r = $("cmd-result"); r.textContent = text; r.className = "result " + (ok ? "ok" : "bad"); }

function command(obj) {
  const id = `dash-${++S.reqSeq}`;
  S.myIds.add(id);
  S.fox.publish("/cmd", { ...obj, id });
  showResult(`${obj.op}: sent…`, true);
}

function row(name) { return S.params?.params.find((p) => p.name === name); }

function fillControls() {
  const all = S.params.params, ramp = all.filter((p) => p.rampable);
  // names come off the bus: options as text, never as HTML
  $("set-name").replaceChildren(...all.map((p) => new Option(p.name)));
  $("ramp-name").replaceChildren(...ramp.map((p) => new Option(p.name)));
  showParam();
}

function showParam() {
  const p = row($("set-name").value);
  if (!p) return;
  const f = units.factor(p.name);
  $("set-value").value = +(S.params.values[p.name] * f).toPrecision(8);
  $("set-value").min = p.min * f; $("set-value").max = p.max * f;
  $("set-unit").textContent = units.unit(p.name, p.unit);
  $("set-range").textContent = `${p.name}: range [${+(p.min * f).toPrecision(6)}, ${+(p.max * f).toPrecision(6)}] ${units.unit(p.name, p.unit)}, default ${+(p.def * f).toPrecision(6)}`;
  const q = row($("ramp-name").value);
  if (q) $("ramp-unit").textContent = units.unit(q.name, q.unit);
}

function inRange(name, v) {
  const p = row(name);
  if (!p || !Number.isFinite(v) || v < p.min || v > p.max) {
    showResult(`${name} = ${v} is outside [${p?.min}, ${p?.max}] (dimensionless)`, false);
    return false;
  }
  return true;
}

function enableControls() {
  const ok = S.fox.canPublish();
  for (const el of document.querySelectorAll("#control-panel button, #control-panel input, #control-panel select"))
    if (!["clear-btn", "tunit", "window", "colour"].includes(el.id)) el.disabled = !ok;
  $("cmd-note").textContent = ok ? "commands go to the daemon; its ACK is shown below"
    : "read-only: start wgweb with --allow-commands to control the daemon";
}

function wireControls() {
  $("set-name").onchange = showParam;
  $("ramp-name").onchange = showParam;
  $("set-btn").onclick = () => {
    const name = $("set-name").value, v = units.parse(name, parseFloat($("set-value").value));
    if (inRange(name, v)) command({ op: "set", params: { [name]: v }, at_section: $("set-at-section").checked });
  };
  $("ramp-btn").onclick = () => {
    const name = $("ramp-name").value, v = units.parse(name, parseFloat($("ramp-to").value));
    if (inRange(name, v)) command({ op: "ramp", param: name, to: v, duration: parseFloat($("ramp-dur").value), unit: "s" });
  };
  $("pause-btn").onclick = () => command({ op: "pause" });
  $("resume-btn").onclick = () => command({ op: "resume" });
  $("reset-btn").onclick = () => command({ op: "reset" });
  $("clear-btn").onclick = () => { plots.poincare.clear(); plots.bif.clear(); S.impacts = []; };
  $("physical").onchange = () => { units.physical = $("physical").checked; makeTimePlots(); showParam(); updateCaption(); };
  $("tunit").onchange = makeTimePlots;
}

// ---- plots
const plots = {};
let captionXn = "";

function bLines(u) {
  const b = S.params?.values.b;
  if (b === undefined) return;
  const ctx = u.ctx, f = units.factor("x_n"), { left, width } = u.bbox;
  ctx.save(); ctx.setLineDash([6, 4]); ctx.strokeStyle = "#c62828"; ctx.lineWidth = devicePixelRatio;
  for (const y of [b * f, -b * f]) {
    const Y = u.valToPos(y, "y", true);
    ctx.beginPath(); ctx.moveTo(left, Y); ctx.lineTo(left + width, Y); ctx.stroke();
  }
  ctx.setLineDash([]); ctx.fillStyle = "#c62828";
  const x0 = u.scales.x.min, x1 = u.scales.x.max;
  for (const im of S.impacts) {
    const x = timeOf(im.t, null);
    if (x === null || x < x0 || x > x1) continue;
    const X = u.valToPos(x, "x", true), Y = u.valToPos(im.side * b * f, "y", true);
    ctx.beginPath(); ctx.moveTo(X, Y - 5 * devicePixelRatio); ctx.lineTo(X - 4 * devicePixelRatio, Y + 3 * devicePixelRatio);
    ctx.lineTo(X + 4 * devicePixelRatio, Y + 3 * devicePixelRatio); ctx.fill();
  }
  ctx.restore();
}

// Time of a sample on the axis: ms, or mesh periods (step / N; from t_s for events).
function timeOf(t_s, step) {
  if ($("tunit").value === "ms") return t_s * 1000;
  const N = S.params?.steps_per_period ?? 128;
  if (step !== null) return step / N;
  const s = S.scope, last = (s.n - 1) % RING;
  if (s.n === 0) return null;
  return s.step[last] / N - ((s.t[last] - t_s) * (S.status?.omega ?? 1) * (S.params?.omega_n_rad_s ?? 1)) / (2 * Math.PI);
}

function timePlot(el, label, colour, hooks) {
  const r = el.getBoundingClientRect();
  el.innerHTML = "";
  const xlabel = $("tunit").value === "ms" ? "simulated time t [ms]" : "mesh periods";
  return new uPlot({
    width: Math.floor(r.width), height: Math.floor(r.height) - 4, legend: { show: false },
    scales: { x: { time: false } }, cursor: { drag: { x: false, y: false } },
    axes: [{ label: xlabel, size: 40 }, { label, size: 62 }],
    series: [{}, { stroke: colour, width: 1, points: { show: false } }],
    hooks,
  }, [[], []], el);
}

function makeTimePlots() {
  plots.xn?.destroy(); plots.f?.destroy();
  plots.xn = timePlot($("plot-xn"), `x_n [${units.unit("x_n")}]`, "#1f77b4", { draw: [bLines] });
  plots.f = timePlot($("plot-f"), `F [${units.unit("F")}]`, "#6a1b9a", {});
  S.newScope = true;
  updateCaption();
}

function makePlots() {
  plots.phase = new Scatter($("plot-phase"), { max: 6000, size: 2 });
  plots.poincare = new Scatter($("plot-poincare"), { max: 20000, size: 2, grow: 0.25 });
  plots.bif = new Scatter($("plot-bif"), { max: 200000, size: 1.5, grow: 0.25 });
  makeTimePlots();
  const legend = $("legend");
  const key = (text, colour) => {
    const s = document.createElement("span"), i = document.createElement("i");
    i.style.background = colour; s.append(i, text); legend.append(s);
  };
  legend.append("regime: ");
  for (const [k, c] of Object.entries(REGIME_COLOUR)) key(k, c);
  legend.append(" | motion: ");
  for (const [k, c] of Object.entries(MOTION_COLOUR)) key(k, c);
}

// The samples inside the time window, oldest first.
function windowSamples() {
  const s = S.scope, W = parseFloat($("window").value);
  const n = Math.min(s.n, RING), last = s.n - 1, out = [];
  if (n === 0) return out;
  const tEnd = s.t[last % RING];
  for (let k = 0; k < n; k++) {
    const i = (last - k) % RING;
    if (tEnd - s.t[i] > W) break;
    out.push(i);
  }
  return out.reverse();
}

function drawScope() {
  const s = S.scope, idx = windowSamples(), fx = units.factor("x_n"), fF = units.factor("F"), fv = units.factor("dx_n");
  const xs = idx.map((i) => timeOf(s.t[i], s.step[i]));
  plots.xn.setData([xs, idx.map((i) => s.x[i] * fx)]);
  plots.f.setData([xs, idx.map((i) => s.F[i] * fF)]);
  plots.phase.set(idx.map((i) => [s.x[i], s.dx[i], "rgba(31,119,180,0.6)"]));
  for (const id of ["plot-xn", "plot-f", "plot-phase"]) setSamples(id, idx.length);
  const N = S.params?.steps_per_period ?? 128;
  const periods = idx.length > 1 ? (s.step[idx[idx.length - 1]] - s.step[idx[0]]) / N : 0;
  $("cap-phase").textContent = `last ${idx.length} scope samples, over ${periods.toFixed(periods < 10 ? 2 : 0)} mesh periods`;
  const spacing = idx.length > 1 ? periods / (idx.length - 1) : 0;
  // the aliasing note joins the PARAMS caption with "; " only when there is one
  const alias = spacing > 0.5 ? `samples ${spacing.toFixed(1)} mesh periods apart: ` +
    "a stroboscopic (aliased) view, not the waveform (run the daemon slower, e.g. --rate 0.01, to see it)" : "";
  $("cap-xn").textContent = [captionXn, alias].filter((t) => t).join("; ");
  plots.phase.setLabels(`x_n [${units.unit("x_n")}]`, `x_n′ [${units.unit("dx_n")}]`, fx, fv);
}

// ---- status
function fmt(v, d = 3) { return v === undefined || v === null ? "–" : typeof v === "number" ? +v.toPrecision(d) : v; }

function updateStatus() {
  const st = S.status, br = S.bridge, now = performance.now();
  const silent = S.statusWall ? (now - S.statusWall) / 1000 : Infinity;
  const noHb = !S.connected || silent > 3 || br?.daemon === "no heartbeat";
  $("conn").textContent = S.connected ? "bridge connected" : "bridge disconnected";
  $("conn").className = "badge " + (S.connected ? "ok" : "bad");
  $("banner").classList.toggle("hidden", !noHb);
  $("banner").textContent = !S.connected ? "BRIDGE DISCONNECTED — reconnecting" :
    S.statusWall ? `NO HEARTBEAT — daemon silent for ${silent.toFixed(0)} s` : "NO HEARTBEAT — waiting for the daemon";
  $("health").textContent = st ? `${st.run} · ${st.health}` : "–";
  $("health").className = "badge " + (!st || noHb ? "bad" : st.health === "ok" ? "ok" : st.health === "lagging" ? "warn" : "bad");
  const om = st ? `${fmt(units.show("omega", st.omega), 5)} ${units.unit("omega")}` : "–";
  const rows = st ? [
    ["mode", `${st.mode} ×${st.rate}`], ["health", st.health + (st.fault ? ` — ${st.fault}` : "")],
    ["real-time factor", fmt(st.rtf, 5)], ["lag", `${fmt(st.lag_s * 1e3)} ms`], ["overruns", st.overruns],
    ["daemon CPU", `${fmt(st.cpu_share * 100)} %`], ["bridge CPU", br ? `${fmt(br.cpu_share * 100)} %` : "–"],
    ["ω", om], ["regime", st.regime], ["motion", st.motion], ["impacts / period", fmt(st.impacts_per_period)],
    ["simulated time", `${fmt(st.t_s, 6)} s (τ ${fmt(st.tau, 7)})`],
    ["worm θ1, wheel θ2", S.theta ? S.theta.map((a) => `${(a * 180 / Math.PI).toFixed(2)}°`).join(", ") : "–"],
    ["drops", `daemon not published ${st.msgs_dropped}, ticks lost ${st.ticks_lost ?? "–"}, LCM gaps ${br?.lcm_gaps ?? "–"}, bridge queues ${br?.queue_drops ?? "–"}`],
    ["scope", br ? `${fmt(br.scope_in_hz)} → ${fmt(br.scope_hz)} samples/s` : "–"],
    // ticks the daemon refused (each ACKed to its driver): shown to whoever watches
    ...(st.ticks_refused > 0 ? [["ticks refused", `${st.ticks_refused} — the last: ${st.tick_refusal}`]] : []),
  ] : [["daemon", "no STATUS yet"]];
  // every value is text: a STATUS string (fault, regime, ...) is whatever a
  // sender on the multicast group put there, never markup
  $("status").replaceChildren(...rows.map((r) => {
    const tr = document.createElement("tr");
    for (const x of r) tr.insertCell().textContent = String(x);
    return tr;
  }));
}

function updateCaption() {
  const p = S.params;
  if (!p) return;
  const v = p.values;
  const text = `scene ${p.scene} · model ${p.model} · ${p.stepper} · N = ${p.steps_per_period} · ξ_p = ${v.xi_p} · ` +
    `ω = ${fmt(units.show("omega", v.omega), 5)} ${units.unit("omega")} · b = ${fmt(units.show("b", v.b))} ${units.unit("b")} · ` +
    `ω_n = ${fmt(p.omega_n_rad_s, 5)} rad/s`;
  $("caption").textContent = text;
  const short = `${p.scene}, ξ_p = ${v.xi_p}, N = ${p.steps_per_period}`;
  captionXn = `${short}; dashed: ±b; triangles: mesh impacts (drive side at +b, back side at −b)`;
  $("cap-f").textContent = `${short}; F = 2ξ_p x_n′ + k_p g(x_n; b)`;
  $("cap-poincare").textContent = `${short}; one point per mesh period (rate-capped by the bridge), cleared on a parameter change`;
  $("cap-bif").textContent = `${short}; every section received while ω moves (ramp or wgrig sweep), coloured by the daemon's regime (period-n, aperiodic), else by the period's motion (while ramping or unknown); dashed: ±b`;
  const fx = units.factor("x_n"), fv = units.factor("dx_n"), fo = units.factor("omega");
  plots.poincare.setLabels(`x_n [${units.unit("x_n")}]`, `x_n′ [${units.unit("dx_n")}]`, fx, fv);
  plots.bif.setLabels(`ω [${units.unit("omega")}]`, `Poincaré x_n [${units.unit("x_n")}]`, fo, fx);
  plots.bif.setGuides([{ y: v.b, colour: "#c62828" }, { y: -v.b, colour: "#c62828" }]);
}

// ---- the frame loop
// data-samples on each plot (the tests read it), written only when it changes.
function setSamples(id, n) { const el = $(id); if (el.dataset.samples !== String(n)) el.dataset.samples = n; }

let lastFrame = 0, lastStatus = 0;
function frame(now) {
  if (lastFrame) { T.frameIntervals.push(now - lastFrame); if (T.frameIntervals.length > 4000) T.frameIntervals.splice(0, 2000); }
  lastFrame = now; T.frames++;
  if (S.newScope) {
    drawScope();
    S.newScope = false;
    const lat = performance.timeOrigin + performance.now() - S.newestUtime / 1000;
    T.latencies.push(lat); if (T.latencies.length > 4000) T.latencies.splice(0, 2000);
  }
  plots.phase.draw(); plots.poincare.draw(); plots.bif.draw();
  setSamples("plot-poincare", plots.poincare.count);
  setSamples("plot-bif", plots.bif.count);
  if (now - lastStatus > 250) { updateStatus(); lastStatus = now; }
  T.work.push(performance.now() - now); if (T.work.length > 4000) T.work.splice(0, 2000);
  requestAnimationFrame(frame);
}

window.addEventListener("resize", () => { for (const k of ["phase", "poincare", "bif"]) plots[k].resize(); makeTimePlots(); });
if (typeof uPlot === "undefined") {
  document.body.innerHTML = "<p>uPlot is missing from vendor/: run <code>npm ci</code> in web/ (tools/setup.sh) and rebuild.</p>";
} else {
  makePlots(); wireControls(); start(); requestAnimationFrame(frame);
}
