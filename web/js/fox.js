// fox.js - a small Foxglove WebSocket protocol v1 client for the browser
// (subprotocol foxglove.websocket.v1, JSON-encoded channels only).
// connect(url, on) calls on.open(), on.close(), on.serverInfo(info),
// on.status(msg), on.advertise(channels), on.message(topic, obj, tsNs),
// on.time(tsNs), on.parameterValues(msg). The returned object subscribes by
// topic, publishes JSON on a client channel, and gets/sets parameters.

const SUBPROTOCOL = "foxglove.websocket.v1";

export function connect(url, on) {
  const ws = new WebSocket(url, [SUBPROTOCOL]);
  ws.binaryType = "arraybuffer";
  const byTopic = new Map(); // topic -> channel
  const subs = new Map(); // subscription id -> topic
  const wanted = new Set(); // topics to subscribe once advertised
  const clientChans = new Map(); // topic -> client channel id
  const decoder = new TextDecoder();
  const encoder = new TextEncoder();
  let nextSub = 1;
  let nextClientChan = 1;
  let info = null;

  const send = (obj) => ws.readyState === 1 && ws.send(JSON.stringify(obj));

  function subscribeAdvertised() {
    const list = [];
    for (const topic of wanted) {
      const ch = byTopic.get(topic);
      if (!ch || [...subs.values()].includes(topic)) continue;
      const id = nextSub++;
      subs.set(id, topic);
      list.push({ id, channelId: ch.id });
    }
    if (list.length) send({ op: "subscribe", subscriptions: list });
  }

  function onText(m) {
    switch (m.op) {
      case "serverInfo": info = m; on.serverInfo?.(m); break;
      case "status": on.status?.(m); break;
      case "advertise":
        for (const ch of m.channels) {
          // wgweb re-advertises its channels, same ids, when the daemon
          // restarts, and keeps their subscriptions: ours stays valid. A
          // topic on another id is a new channel: subscribe to that one.
          const old = byTopic.get(ch.topic);
          if (old && old.id !== ch.id) for (const [id, t] of subs) if (t === ch.topic) subs.delete(id);
          byTopic.set(ch.topic, ch);
        }
        on.advertise?.(m.channels);
        subscribeAdvertised();
        break;
      case "parameterValues": on.parameterValues?.(m); break;
      default: break;
    }
  }

  function onBinary(buf) {
    const dv = new DataView(buf);
    const op = dv.getUint8(0);
    if (op === 1) {
      const topic = subs.get(dv.getUint32(1, true));
      if (topic === undefined) return;
      const ts = dv.getBigUint64(5, true);
      on.message?.(topic, JSON.parse(decoder.decode(new Uint8Array(buf, 13))), ts);
    } else if (op === 2) {
      on.time?.(dv.getBigUint64(1, true));
    }
  }

  ws.onopen = () => on.open?.();
  ws.onclose = () => on.close?.();
  ws.onmessage = (ev) => (typeof ev.data === "string" ? onText(JSON.parse(ev.data)) : onBinary(ev.data));

  return {
    get info() { return info; },
    close() { ws.close(); },
    subscribe(topics) { for (const t of topics) wanted.add(t); subscribeAdvertised(); },
    canPublish() { return !!info && info.capabilities.includes("clientPublish"); },
    // Publish obj as JSON on the client channel `topic` (advertised on first use).
    publish(topic, obj) {
      if (!clientChans.has(topic)) {
        const id = nextClientChan++;
        clientChans.set(topic, id);
        send({ op: "advertise", channels: [{ id, topic, encoding: "json", schemaName: "wormgear.Command" }] });
      }
      const body = encoder.encode(JSON.stringify(obj));
      const frame = new Uint8Array(5 + body.length);
      frame[0] = 1;
      new DataView(frame.buffer).setUint32(1, clientChans.get(topic), true);
      frame.set(body, 5);
      if (ws.readyState === 1) ws.send(frame);
    },
    getParameters(names, id) { send({ op: "getParameters", parameterNames: names, id }); },
    setParameters(params, id) { send({ op: "setParameters", parameters: params, id }); },
    subscribeParameterUpdates(names) { send({ op: "subscribeParameterUpdates", parameterNames: names }); },
  };
}
