// badinput.mjs WS_URL - every class of bad input against wgweb, from raw
// WebSockets and raw TCP: garbage text, non-JSON, unknown ops, unknown
// channel and subscription ids, binary garbage and unknown opcodes,
// invalid UTF-8, oversized and fragmented frames, no or a wrong
// subprotocol, path traversal over HTTP, garbage instead of HTTP, too many
// clients, clients coming and going. Each gets a status error (or a
// refused connection / 4xx); an observer client keeps receiving data
// throughout, and the bridge still serves a new client at the end.
import WebSocket from "ws";
import net from "node:net";
import { record, until, sleep, checker } from "./lib.mjs";

const url = process.argv[2];
const port = +new URL(url).port;
const { check, done } = checker();

const obs = record(url);
await until(() => obs.channels.size === 7, 5000, "observer advertise");
obs.subscribeAll();
await until(() => obs.count("/scope") > 10, 5000, "observer data");

// A raw WebSocket that collects status messages.
async function rawClient(protocols = ["foxglove.websocket.v1"]) {
  const ws = new WebSocket(url, protocols);
  const c = { ws, statuses: [], closed: false, opened: false, error: null };
  ws.on("message", (d, binary) => { if (!binary) { const m = JSON.parse(d.toString()); if (m.op === "status") c.statuses.push(m); } });
  ws.on("open", () => (c.opened = true));
  ws.on("close", () => (c.closed = true));
  ws.on("error", (e) => (c.error = e));
  await until(() => c.opened || c.closed || c.error, 3000, "connect");
  return c;
}

const bad = await rawClient();
async function expectError(name, send, pattern) {
  const n = bad.statuses.length;
  send();
  try {
    await until(() => bad.statuses.length > n, 3000, name);
    const m = bad.statuses.at(-1);
    check(`${name}: status error`, m.level === 2 && pattern.test(m.message), m.message);
  } catch (e) { check(`${name}: status error`, false, e.message); }
}
const scope0 = obs.count("/scope");
await expectError("garbage text", () => bad.ws.send("\u0001\u0002 garbage {{{"), /a control byte 0x01 at byte 0/);
await expectError("garbage text, printable", () => bad.ws.send("garbage {{{"), /not JSON/);
// a raw NUL inside a string (cJSON ended the string there: the op ran)
await expectError("a raw NUL in op", () => bad.ws.send('{"op":"getParameters\u0000junk","parameterNames":[],"id":"n"}'), /a control byte 0x00 at byte 20/);
await expectError("JSON that is not an object", () => bad.ws.send("[1,2,3]"), /JSON object with a string 'op'/);
await expectError("unknown op", () => bad.ws.send(JSON.stringify({ op: "launchMissiles" })), /unknown op 'launchMissiles'/);
await expectError("unknown channel id", () => bad.ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 1, channelId: 4242 }] })), /unknown channel id 4242/);
await expectError("non-integer ids", () => bad.ws.send(JSON.stringify({ op: "subscribe", subscriptions: [{ id: 0.5, channelId: "x" }] })), /integer 'id' and 'channelId'/);
await expectError("unknown subscription id", () => bad.ws.send(JSON.stringify({ op: "unsubscribe", subscriptionIds: [99] })), /unknown subscription id/);
await expectError("binary garbage (unknown opcode)", () => bad.ws.send(Buffer.from([0xff, 1, 2, 3])), /unknown opcode/);
await expectError("binary message on an unknown client channel", () => bad.ws.send(Buffer.from([0x01, 9, 0, 0, 0, 0x7b])), /unknown client channel id/);
await expectError("service call", () => bad.ws.send(Buffer.from([0x02, 0, 0, 0, 0])), /services are not supported/);
await expectError("oversized frame (1 MiB)", () => bad.ws.send("x".repeat(1 << 20)), /frame over 65536 bytes/);
await expectError("fragmented non-JSON", () => { bad.ws.send("{\"op\":", { fin: false }); bad.ws.send("garbage", { fin: true }); }, /not JSON/);
await expectError("deeply nested JSON", () => bad.ws.send("[".repeat(5000)), /not JSON/);
await expectError("setParameters with a string value", () => bad.ws.send(JSON.stringify({ op: "setParameters", parameters: [{ name: "omega", value: "fast" }] })), /value must be a number/);
check("bad client still connected after all that", !bad.closed);

// Invalid UTF-8 in a text message fails the connection with 1007 (RFC 6455)
// and says where; what it asked for is not done (the set ran, and the
// answer's id was "\ufffd\ufffd": a review). A character split between
// fragments is fine.
async function sendText(parts) {
  const c = await rawClient();
  const r = { code: 0, reason: "", c, values: 0 };
  c.ws.on("close", (code, reason) => { r.code = code; r.reason = reason.toString(); });
  c.ws.on("message", (d, bin) => {
    if (!bin && d.toString().includes('"parameterValues"')) r.values++;
  });
  parts.forEach((p, i) =>
    c.ws.send(Buffer.from(p, "latin1"), { binary: false, fin: i === parts.length - 1 }));
  const answered = () => c.closed || c.statuses.length || r.values;
  await until(answered, 3000, "an answer").catch(() => {});
  return r;
}
const utf8Why = /^invalid UTF-8 at byte (\d+): a text message must be UTF-8 \(RFC 6455\)$/;
const u1 = await sendText(['{"op":"setParameters","parameters":[{"name":"xi_p","value":0.082}],' +
  '"id":"\xff\xfe"}']);
check("invalid UTF-8 in a setParameters: closed with 1007 and the reason",
  u1.code === 1007 && utf8Why.test(u1.reason) && u1.reason.includes("byte 73"),
  `${u1.code} ${u1.reason}`);
check("invalid UTF-8: one message, no status as well", u1.c.statuses.length === 0,
  JSON.stringify(u1.c.statuses));
const u2 = await sendText(['{"op":"getParameters","id":"', '\xe2\x28"}']);
check("invalid UTF-8 in a later fragment: closed with 1007",
  u2.code === 1007 && utf8Why.test(u2.reason), `${u2.code} ${u2.reason}`);
const u3 = await sendText(['{"op":"getParameters","parameterNames":["xi_p"],"id":"\xe2',
  '\x82\xac"}']);
check("a character split between fragments is taken", !u3.c.closed && u3.values === 1);
u3.c.ws.terminate();
obs.client.getParameters(["xi_p"], "xi_p after utf8");
const xiAnswered = () => obs.params.some((p) => p.id === "xi_p after utf8");
await until(xiAnswered, 3000, "getParameters").catch(() => {});
const xi = obs.params.find((p) => p.id === "xi_p after utf8")?.parameters?.[0]?.value;
check("the setParameters with invalid UTF-8 did not run", xi === 0.08, `xi_p ${xi}`);

// Cross-site WebSocket hijacking: a browser page of another origin is
// refused at the handshake; the bridge's own origin and no Origin are not.
async function withOrigin(origin) {
  const ws = new WebSocket(url, ["foxglove.websocket.v1"], origin ? { origin } : {});
  const r = { opened: false, failed: false };
  ws.on("open", () => { r.opened = true; ws.close(); });
  ws.on("error", () => (r.failed = true));
  ws.on("unexpected-response", () => (r.failed = true));
  await until(() => r.opened || r.failed, 3000, `connect with origin ${origin}`);
  return r.opened;
}
check("a page of another origin is refused", !(await withOrigin("http://evil.example")));
check("a page of another port is refused", !(await withOrigin(`http://127.0.0.1:${port + 1}`)));
// an Origin too long to copy was taken as none, and let in (a review)
check("an origin of 400 characters is refused", !(await withOrigin("http://evil.example/" + "a".repeat(380))));
check("the bridge's own page may connect", await withOrigin(`http://127.0.0.1:${port}`));
check("localhost is its own page too", await withOrigin(`http://localhost:${port}`));
check("observer kept receiving during the abuse", obs.count("/scope") > scope0 + 20, `${obs.count("/scope") - scope0} scope messages`);
check("observer saw no status error", obs.statuses.every((s) => s.level < 2), JSON.stringify(obs.statuses));

// Handshakes that must fail.
const noProto = await rawClient([]);
check("WebSocket without the subprotocol refused", !noProto.opened || (await until(() => noProto.closed, 2000, "close").then(() => true, () => false)));
const wrongProto = await rawClient(["some.other.v1"]);
check("WebSocket with another subprotocol refused", !wrongProto.opened || wrongProto.ws.protocol !== "foxglove.websocket.v1");
wrongProto.ws.terminate(); noProto.ws.terminate();

// Raw HTTP: traversal, garbage.
function rawHttp(text) {
  return new Promise((resolve) => {
    const s = net.connect(port, "127.0.0.1", () => s.write(text));
    let buf = "";
    s.on("data", (d) => (buf += d.toString("latin1")));
    s.on("close", () => resolve(buf));
    s.on("error", () => resolve(buf));
    setTimeout(() => s.destroy(), 2000);
  });
}
for (const path of ["/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/js/../../../../etc/passwd", "/..%2f..%2f..%2fetc%2fpasswd"]) {
  const resp = await rawHttp(`GET ${path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n`);
  check(`HTTP ${path} does not leave the web root`, !resp.includes("root:") && !/^HTTP\/1\.1 200/.test(resp), resp.split("\r\n")[0]);
}
const idx = await rawHttp("GET /index.html HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
check("HTTP /index.html served", /^HTTP\/1\.1 200/.test(idx) && idx.includes("wormgear live"));
const nf = await rawHttp("GET /nope.html HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
check("HTTP unknown file: 404", /^HTTP\/1\.1 404/.test(nf), nf.split("\r\n")[0]);
// A WebSocket version other than RFC 6455's 13: not upgraded (it was)
const upgrade = (v) => rawHttp("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n" +
  "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Protocol: foxglove.websocket.v1\r\n" +
  `Sec-WebSocket-Version: ${v}\r\n\r\n`);
const v13 = await upgrade(13), v99 = await upgrade(99);
check("Sec-WebSocket-Version 13 upgraded", /^HTTP\/1\.1 101/.test(v13), v13.split("\r\n")[0]);
check("Sec-WebSocket-Version 99 not upgraded: 426", /^HTTP\/1\.[01] 426/.test(v99) && v99.includes("version 13"), v99.split("\r\n")[0] || "(closed)");
await rawHttp("\x16\x03\x01 this is not http at all \x00\xff\r\n\r\n");
await rawHttp("GET / HTTP/1.1\r\n" + "X-Long: " + "a".repeat(100000) + "\r\n\r\n");

// Too many clients, and clients coming and going.
const many = [];
for (let i = 0; i < 20; i++) many.push(await rawClient());
// A client over the limit is closed right after its upgrade: the last
// one's close may still be on its way when its open is seen.
const nRefused = () => many.filter((c) => c.closed || c.error).length;
await until(() => nRefused() >= 20 + 2 - 16, 3000, "refusals").catch(() => {});
const refused = nRefused();
check("clients beyond --max-clients (16) are closed", refused >= 20 + 2 - 16, `${refused} of 20 closed`);
for (const c of many) c.ws.terminate();
for (let i = 0; i < 50; i++) { const c = new WebSocket(url, ["foxglove.websocket.v1"]); c.on("error", () => {}); c.on("open", () => c.terminate()); }
await sleep(1000);
const late = record(url);
await until(() => late.channels.size === 7, 5000, "a new client after the churn");
late.subscribeAll();
await until(() => late.count("/scope") > 5, 5000, "data for the new client");
check("a new client is served after everything", true);
const scope1 = obs.count("/scope"), t1 = Date.now();
const more = await until(() => obs.count("/scope") >= scope1 + 20, 3000, "observer data").then(() => true, () => false);
check("observer still receiving", more, `20 more scope messages in ${Date.now() - t1} ms`);
check("every observer message valid against its schema", obs.invalid.length === 0);
late.client.close(); obs.client.close(); bad.ws.terminate();
done();
