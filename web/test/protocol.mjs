// protocol.mjs WS_URL - wgweb against the upstream @foxglove/ws-protocol
// client: serverInfo and advertise; every channel subscribed, every message
// decoded and checked against its advertised JSON Schema; message times are
// the simulated time; setParameters omega 1.3 reaches the daemon's PARAMS;
// an out-of-range value returns the daemon's reason; clientPublish on /cmd
// (pause, resume) answered on /ack; a read-only bridge refuses commands;
// the daemon restarting: "no heartbeat", then re-advertised and data again.
import { spawn } from "node:child_process";
import { writeFileSync } from "node:fs";
import { record, until, sleep, checker } from "./lib.mjs";

const url = process.argv[2];
const { check, done } = checker();
const r = record(url);
await until(() => r.info && r.channels.size === 7, 5000, "serverInfo and advertise");
check("serverInfo capabilities", ["parameters", "parametersSubscribe", "time", "clientPublish"].every((c) => r.info.capabilities.includes(c)),
  r.info.capabilities.join(" "));
check("supportedEncodings json", r.info.supportedEncodings?.includes("json"));
check("7 channels advertised, json + jsonschema", [...r.channels.values()].every((c) => c.encoding === "json" && c.schemaEncoding === "jsonschema"),
  [...r.channels.keys()].join(" "));
r.subscribeAll();
r.client.subscribeParameterUpdates([]);
// The daemon publishes STATUS once it takes commands (a slow start, e.g.
// under ASan, would leave setParameters unanswered).
await until(() => r.count("/status") > 0, 10000, "a STATUS from the daemon");

// Impacts at omega 1.2 so /contact carries events; then the 1.3 / 12 checks.
r.client.setParameters([{ name: "omega", value: 1.2 }], "s0");
await until(() => r.params.some((p) => p.id === "s0"), 5000, "answer to setParameters s0");
await until(() => ["/status", "/params", "/scope", "/poincare", "/contact", "/bridge"].every((t) => r.count(t) > 0) && r.times > 0,
  8000, "a message on every daemon channel");
r.client.setParameters([{ name: "omega", value: 1.3 }], "s1");
await until(() => r.params.some((p) => p.id === "s1"), 5000, "answer to setParameters s1");
const s1 = r.params.find((p) => p.id === "s1");
check("setParameters omega 1.3 answered with 1.3", s1.parameters[0]?.name === "omega" && s1.parameters[0]?.value === 1.3, JSON.stringify(s1.parameters));
await until(() => r.msgs.get("/params").some((m) => m.obj.values.omega === 1.3 && m.obj.reason === "set"), 5000, "PARAMS with omega 1.3");
check("the daemon's PARAMS show omega = 1.3", true);
check("/ack carries the request id", r.msgs.get("/ack")?.some((m) => m.obj.request_id === "s1" && m.obj.accepted && m.obj.code === "OK"));
check("parameter update pushed", r.params.some((p) => p.id === undefined && p.parameters.some((q) => q.name === "omega" && q.value === 1.3)));

const nStatus = r.statuses.length;
r.client.setParameters([{ name: "omega", value: 12 }], "s2");
await until(() => r.params.some((p) => p.id === "s2"), 5000, "answer to setParameters s2");
const refusal = r.statuses.slice(nStatus).find((s) => s.level === 2);
check("out of range: the daemon's reason as a status error", /ERANGE omega = 12 out of range \[0\.01, 10\]/.test(refusal?.message ?? ""), refusal?.message);
check("out of range: the value stays 1.3", r.params.find((p) => p.id === "s2").parameters[0]?.value === 1.3);

r.client.getParameters([], "g");
await until(() => r.params.some((p) => p.id === "g"), 3000, "getParameters");
const g = r.params.find((p) => p.id === "g");
check("getParameters returns the whole table", g.parameters.length === 35 && g.parameters.every((p) => p.type === "float64"), `${g.parameters.length} parameters`);

// clientPublish: pause and resume on /cmd, ACKs on /ack.
const cmd = r.client.advertise({ topic: "/cmd", encoding: "json", schemaName: "wormgear.Command" });
const enc = (o) => new TextEncoder().encode(JSON.stringify(o));
r.client.sendMessage(cmd, enc({ op: "pause", id: "p1" }));
await until(() => r.msgs.get("/ack").some((m) => m.obj.request_id === "p1"), 5000, "ACK of pause");
await until(() => r.last("/status").run === "paused", 3000, "STATUS paused");
r.client.sendMessage(cmd, enc({ op: "resume", id: "p2" }));
await until(() => r.msgs.get("/ack").some((m) => m.obj.request_id === "p2" && m.obj.accepted), 5000, "ACK of resume");
check("clientPublish pause/resume acknowledged", true);
r.client.sendMessage(cmd, enc({ op: "ramp", param: "no_such_param", to: 0.1, duration: 1, id: "p3" }));
await until(() => r.msgs.get("/ack").some((m) => m.obj.request_id === "p3"), 5000, "ACK of a refused ramp");
const p3 = r.msgs.get("/ack").find((m) => m.obj.request_id === "p3").obj;
check("a refused command: ACK and status error", !p3.accepted && r.statuses.some((s) => s.level === 2 && s.message.includes(p3.message)), `${p3.code} ${p3.message}`);

// An explicit rate outside the daemon's range is refused by the bridge: 0 on
// the wire means "keep the rate", so rate 0 (or -0) was answered OK and kept
// rate 1. Nothing is sent: the get after it is answered, the modes are not.
const rateWhy = "/cmd: mode: 'rate' must be a number in [1e-06, 1000]";
const nRate = r.statuses.length;
for (const text of ['{"op":"mode","mode":"realtime","rate":0,"id":"r0"}',
  '{"op":"mode","mode":"realtime","rate":-0,"id":"r-0"}'])
  r.client.sendMessage(cmd, new TextEncoder().encode(text));
r.client.sendMessage(cmd, enc({ op: "get", id: "r-get" }));
await until(() => r.msgs.get("/ack").some((m) => m.obj.request_id === "r-get"), 5000, "ACK of get");
const rateRefusals = r.statuses.slice(nRate)
  .filter((s) => s.level === 2 && s.message.startsWith(rateWhy));
check("mode with rate 0 and -0: refused with the range, not sent",
  rateRefusals.length === 2 && !r.msgs.get("/ack").some((m) => /^r-?0$/.test(m.obj.request_id)),
  rateRefusals.map((s) => s.message).join(" | "));

// Message times: the simulated time, in ns.
const sc = r.msgs.get("/scope").at(-1);
check("/scope message time = t_s", Math.abs(Number(sc.ts) / 1e9 - sc.obj.t_s) < 1e-6, `${sc.ts} ns vs t_s ${sc.obj.t_s}`);
check("/scope carries theta1, theta2 in [0, 2 pi)", [sc.obj.theta1, sc.obj.theta2].every((a) => a >= 0 && a < 2 * Math.PI),
  `theta1 ${sc.obj.theta1}, theta2 ${sc.obj.theta2}`);

// A read-only bridge refuses commands.
const ro = record(process.env.WG_RO_URL);
await until(() => ro.info && ro.channels.size === 7, 5000, "read-only bridge");
check("read-only bridge: no clientPublish", !ro.info.capabilities.includes("clientPublish"));
ro.client.setParameters([{ name: "omega", value: 1.1 }], "ro");
await until(() => ro.statuses.some((s) => s.level === 2), 3000, "read-only refusal");
check("read-only bridge refuses setParameters", ro.statuses.some((s) => /--allow-commands/.test(s.message)));
ro.client.close();

// The daemon restarting under the bridge.
process.kill(+process.env.WG_DAEMON_PID, "SIGTERM");
await until(() => r.statuses.some((s) => /no heartbeat/.test(s.message)), 8000, "no heartbeat status");
await until(() => r.last("/bridge").daemon === "no heartbeat", 3000, "bridge status says no heartbeat");
check("daemon gone: 'no heartbeat' status and bridge state", true);
const adverts = r.adverts, nScope = r.count("/scope");
const d2 = spawn(process.env.WG_DAEMON, ["--state-dir", process.env.WG_STATE_DIR], { stdio: "ignore" });
writeFileSync(process.env.WG_DAEMON2_PIDFILE, String(d2.pid));
await until(() => r.adverts > adverts && r.count("/scope") > nScope + 20, 10000, "re-advertise and data after the restart");
check("daemon restarted: re-advertised, data flows again", true, `${r.count("/scope") - nScope} scope messages since`);
await sleep(500);
d2.kill("SIGTERM");

const counts = [...r.msgs].map(([t, l]) => `${t} ${l.length}`).join(", ");
check("every message valid against its schema", r.invalid.length === 0,
  r.invalid.length ? JSON.stringify(r.invalid[0]).slice(0, 400) : counts);
check("no unexpected status errors on the commanding client",
  r.statuses.filter((s) => s.level === 2)
    .every((s) => /refused/.test(s.message) || s.message.startsWith(rateWhy)),
  JSON.stringify(r.statuses.filter((s) => s.level === 2).map((s) => s.message)));
r.client.close();
done();
