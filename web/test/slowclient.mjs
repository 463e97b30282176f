// slowclient.mjs WS_URL - a client that subscribes to everything and then
// never reads (its socket paused) must not delay another client or the
// daemon. Measures, for a normal client, the /scope message rate and the
// publish-to-receive latency (daemon utime -> arrival) before and while the
// other client is stalled; the bridge's per-client queue and drops; the
// daemon's real-time factor and lag. Prints the figures.
import WebSocket from "ws";
import { record, until, sleep, checker } from "./lib.mjs";

const url = process.argv[2];
const { check, done } = checker();
const pct = (a, p) => { const s = [...a].sort((x, y) => x - y); return s.length ? s[Math.min(s.length - 1, Math.floor(p * s.length))] : NaN; };

const a = record(url);
await until(() => a.channels.size === 7, 5000, "advertise");
a.subscribeAll();
await until(() => a.count("/scope") > 50 && a.count("/status") > 0, 5000, "data and a STATUS");

async function measure(ms) {
  const lat = [], n0 = a.count("/scope"), t0 = Date.now(), st0 = a.last("/status");
  const onMsg = () => { const m = a.last("/scope"); if (m) lat.push(Date.now() - m.utime / 1000); };
  const timer = setInterval(onMsg, 5);
  await sleep(ms);
  clearInterval(timer);
  const rate = ((a.count("/scope") - n0) * 1000) / (Date.now() - t0);
  const st = a.last("/status");
  return { rate, p50: pct(lat, 0.5), p99: pct(lat, 0.99), rtf: st.rtf, lag_ms: st.lag_s * 1e3, overruns: st.overruns - st0.overruns };
}
// Latency per message as it arrives (not polled).
const arrivals = [];
a.client.on("message", () => { const m = a.last("/scope"); if (m) arrivals.push(Date.now() - m.utime / 1000); });

const base = await measure(3000);
const baseLat = arrivals.splice(0);

// The staller: subscribes to every channel, then stops reading.
const b = new WebSocket(url, ["foxglove.websocket.v1"]);
b.on("message", (d, binary) => {
  if (binary) return;
  const m = JSON.parse(d.toString());
  if (m.op === "advertise") {
    b.send(JSON.stringify({ op: "subscribe", subscriptions: m.channels.map((c, i) => ({ id: i + 1, channelId: c.id })) }));
    setTimeout(() => b._socket.pause(), 50);
  }
});
b.on("error", () => {});
await until(() => (a.last("/bridge")?.per_client ?? []).some((c) => c.drops > 0), 30000, "the stalled client's queue to overflow");
const stalled = await measure(4000);
const stalledLat = arrivals.splice(0);
const br = a.last("/bridge");
const bq = br.per_client.reduce((m, c) => (c.drops > m.drops ? c : m));
console.log(`figures: normal client /scope ${base.rate.toFixed(0)} msg/s, latency p50 ${pct(baseLat, 0.5).toFixed(1)} ms p99 ${pct(baseLat, 0.99).toFixed(1)} ms (alone)`);
console.log(`figures: normal client /scope ${stalled.rate.toFixed(0)} msg/s, latency p50 ${pct(stalledLat, 0.5).toFixed(1)} ms p99 ${pct(stalledLat, 0.99).toFixed(1)} ms (beside a stalled client)`);
console.log(`figures: stalled client: queue ${bq.queue} msgs / ${(bq.queue_bytes / 1024).toFixed(0)} KiB, ${bq.drops} dropped (oldest first); bridge CPU ${(br.cpu_share * 100).toFixed(1)} %`);
console.log(`figures: daemon rtf ${base.rtf.toFixed(4)} -> ${stalled.rtf.toFixed(4)}, lag ${base.lag_ms.toFixed(2)} -> ${stalled.lag_ms.toFixed(2)} ms, overruns +${base.overruns} / +${stalled.overruns}`);
check("stalled client's queue is bounded and drops the oldest", bq.drops > 0 && bq.queue <= 256, `queue ${bq.queue}, drops ${bq.drops}`);
// Rates and the daemon's real-time factor are figures (they move with the
// machine's load); what is checked is what a stall could do to them: the
// normal client still served, the bridge not spinning on the stalled one.
check("normal client keeps being served (>= 50 % of its rate alone)", stalled.rate >= 0.5 * base.rate, `${stalled.rate.toFixed(0)} vs ${base.rate.toFixed(0)} msg/s`);
// A bridge that waited on the stalled socket would hold the normal client
// for whole seconds; a loaded machine adds tens to hundreds of ms (ASan at
// load 5: 114 -> 268 ms), so the bound is a second.
check("normal client's latency holds (p99 < alone p99 + 1 s)", pct(stalledLat, 0.99) < pct(baseLat, 0.99) + 1000,
  `p99 ${pct(stalledLat, 0.99).toFixed(1)} vs ${pct(baseLat, 0.99).toFixed(1)} ms alone`);
// The daemon never sees the bridge's clients (LCM is fire-and-forget): a
// stall could slow it only by the bridge eating the CPU it needs.
if (base.rtf < 0.9) console.log("note: the daemon could not keep real time even before the stall (a loaded machine or a sanitizer build)");
check("the bridge does not spin on the stalled client (< 50 % of a core)", br.cpu_share < 0.5, `bridge CPU ${(br.cpu_share * 100).toFixed(1)} %`);
b.terminate();
await sleep(300);
check("the stalled client's departure is noticed", (a.last("/bridge")?.clients ?? 0) <= 2);
a.client.close();
done();
