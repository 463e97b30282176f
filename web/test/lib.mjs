// lib.mjs - helpers shared by the Node tests of wgweb: an upstream Foxglove
// client that records everything, waits with timeouts, schema validation.
import pkg from "@foxglove/ws-protocol";
import WebSocket from "ws";
import Ajv from "ajv";

const { FoxgloveClient } = pkg;
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Poll cond() every 20 ms until true; throws `what` after ms.
export async function until(cond, ms, what) {
  const end = Date.now() + ms;
  while (!cond()) {
    if (Date.now() > end) throw new Error(`timed out after ${ms} ms: ${what}`);
    await sleep(20);
  }
}

// A Foxglove client (the upstream @foxglove/ws-protocol) that records
// serverInfo, advertisements, statuses, parameter values, time and every
// message by topic, each decoded and validated against its channel's schema.
export function record(url) {
  const ajv = new Ajv({ strict: false, allErrors: true });
  const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
  const client = new FoxgloveClient({ ws });
  const r = { client, ws, info: null, channels: new Map(), validators: new Map(), subTopic: new Map(),
    adverts: 0, statuses: [], params: [], times: 0, msgs: new Map(), invalid: [], closed: false };
  client.on("serverInfo", (i) => (r.info = i));
  client.on("status", (s) => r.statuses.push(s));
  client.on("parameterValues", (p) => r.params.push(p));
  client.on("time", () => r.times++);
  client.on("close", () => (r.closed = true));
  client.on("advertise", (chs) => {
    r.adverts++;
    for (const ch of chs) {
      r.channels.set(ch.topic, ch);
      if (!r.validators.has(ch.topic)) r.validators.set(ch.topic, ajv.compile(JSON.parse(ch.schema)));
    }
  });
  client.on("message", ({ subscriptionId, timestamp, data }) => {
    const topic = r.subTopic.get(subscriptionId);
    const obj = JSON.parse(new TextDecoder().decode(data));
    const ok = r.validators.get(topic)(obj);
    if (!ok) r.invalid.push({ topic, obj, errors: r.validators.get(topic).errors });
    if (!r.msgs.has(topic)) r.msgs.set(topic, []);
    const list = r.msgs.get(topic);
    list.push({ obj, ts: timestamp });
    if (list.length > 20000) list.splice(0, 10000);
  });
  r.subscribeAll = () => { for (const [t, ch] of r.channels) r.subTopic.set(client.subscribe(ch.id), t); };
  r.count = (t) => r.msgs.get(t)?.length ?? 0;
  r.last = (t) => r.msgs.get(t)?.at(-1)?.obj;
  return r;
}

// Test bookkeeping: check(name, cond, detail) prints ok/FAIL; done() exits.
export function checker() {
  let failed = 0;
  return {
    check(name, cond, detail = "") {
      console.log(`${cond ? "ok  " : "FAIL"} ${name}${detail ? ": " + detail : ""}`);
      if (!cond) failed++;
    },
    done() { console.log(failed ? `${failed} check(s) failed` : "all checks passed"); process.exit(failed ? 1 : 0); },
  };
}
