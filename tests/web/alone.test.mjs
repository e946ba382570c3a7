// The phone alone (app/web/alone.js) in Node, with stand-ins for its Worker, the page's
// connection, stream and status line: joining a server holds the phone's frost (its
// worker's messages are not the page's); resumed, what the worker sent before it took the
// resume (stale ticks from before it held) is dropped until it says "resumed".

import assert from "node:assert/strict";
import { test } from "node:test";

class FakeWorker {
  static made = [];
  constructor() {
    this.posted = [];
    FakeWorker.made.push(this);
  }
  postMessage(message) { this.posted.push(message); }
  terminate() {}
}
globalThis.Worker = FakeWorker;
globalThis.WebSocket = { OPEN: 1 };
globalThis.fetch = async () => ({ ok: true, json: async () => ({}) });

const { Alone } = await import("../../app/web/alone.js");

test("a resumed worker's messages reach the page only once it says it resumed", async () => {
  const drawn = [];
  const connection = {
    socket: null,
    adopt(socket) { this.socket = socket; socket.onmessage = (event) => drawn.push(event.data); },
    connect() {},
    refusal: async () => null,
  };
  const page = {};
  const alone = new Alone(page, {
    connection, stream: { hello: {}, closed() {} }, query: "",
    status: { resting: "", say() {}, notice() {} },
    joinButton: { hidden: true, addEventListener() {} },
  });
  const intervals = [];
  const realSetInterval = globalThis.setInterval;
  globalThis.setInterval = () => { intervals.push(1); return 0; };
  try {
    assert.equal(alone.start(), true);
    await new Promise((resolve) => setImmediate(resolve));  // (configure: params.json, adopt)
    const worker = FakeWorker.made.at(-1), say = (data) => worker.onmessage({ data });
    say("tick 1");
    say({ type: "stats", tick: 1, crystals: 5 });
    assert.deepEqual(drawn, ["tick 1"]);
    assert.equal(page.local.crystals, 5);
    alone.join();  // held: the server's frost is shown
    assert.deepEqual(worker.posted.at(-1), { type: "hold" });
    say("tick 2");  // (sent before it held)
    say({ type: "stats", tick: 2, crystals: 6 });
    assert.deepEqual(drawn, ["tick 1"]);
    assert.equal(page.local, null);
    assert.equal(alone.start(), true);  // no server again: the held frost goes on
    assert.deepEqual(worker.posted.at(-1), { type: "resume" });
    say("tick 3");  // sent before the worker took the resume: stale
    say({ type: "stats", tick: 3, crystals: 7 });
    assert.deepEqual(drawn, ["tick 1"]);
    assert.equal(page.local, null);
    say({ type: "resumed" });
    say("hello");
    say({ type: "stats", tick: 3, crystals: 7 });
    assert.deepEqual(drawn, ["tick 1", "hello"]);
    assert.equal(page.local.crystals, 7);
  } finally {
    globalThis.setInterval = realSetInterval;
  }
});
