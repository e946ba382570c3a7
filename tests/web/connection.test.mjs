// The page's socket to frost serve (app/web/connection.js) in Node, with a stand-in for the
// browser's WebSocket, location and timers: the waits between reconnects double from
// 0.25 s and stop at 8 s (docs/phone.md's status table: "0.25 s doubling to 8 s apart"),
// and an open socket starts them at 0.25 s again.

import assert from "node:assert/strict";
import { test } from "node:test";

// What connection.js uses of the browser, made here before it is imported.
class FakeSocket {
  static OPEN = 1;
  static made = [];
  constructor(url) {
    this.url = String(url);
    this.readyState = 0;
    FakeSocket.made.push(this);
  }
  close() {}
}
globalThis.WebSocket = FakeSocket;
globalThis.location = { href: "http://192.0.2.1:8000/", protocol: "http:" };
const realSetTimeout = globalThis.setTimeout;

const { Connection } = await import("../../app/web/connection.js");

const status = { said: [], say(text) { this.said.push(text); }, refuse() {} };

// The socket open now closes (a reason given: not the unreachable path, which asks /meta),
// and the reconnect it schedules runs at once; returns the wait it was scheduled after.
async function lose(connection, { opened = false } = {}) {
  const ws = FakeSocket.made.at(-1);
  if (opened) ws.onopen();
  let scheduled = null;
  globalThis.setTimeout = (fn, ms) => { scheduled = [fn, ms]; return 1; };
  try {
    await ws.onclose({ code: 1001, reason: "frost serve is ending" });
  } finally {
    globalThis.setTimeout = realSetTimeout;
  }
  assert.ok(scheduled, "a reconnect is scheduled");
  const [fn, ms] = scheduled;
  fn();  // the next try: a new socket
  return ms;
}

test("the reconnect waits double from 0.25 s and stop at 8 s", async () => {
  const connection = new Connection(null, "", status);
  connection.connect();
  const got = [];
  for (let i = 0; i < 10; i++) got.push(await lose(connection));
  assert.deepEqual(got, [250, 500, 1000, 2000, 4000, 8000, 8000, 8000, 8000, 8000]);
  assert.equal(FakeSocket.made.length, 11);
  assert.ok(status.said.every((s) => s === "reconnecting (frost serve is ending)"), status.said);
  // a socket that opened starts the waits anew
  assert.equal(await lose(connection, { opened: true }), 250);
  assert.equal(await lose(connection), 500);
});

test("a socket the server refuses for its size or policy is said refused", async () => {
  // 1008 (policy), 1009 (a message too big) and 4403 (a token) are refusals, said as such
  for (const code of [1008, 1009, 4403]) {
    const said = { said: [], say(text) { this.said.push(text); }, refuse() {} };
    const connection = new Connection(null, "", said);
    connection.connect();
    const ws = FakeSocket.made.at(-1);
    globalThis.setTimeout = () => 1;
    try {
      await ws.onclose({ code, reason: "too big" });
    } finally {
      globalThis.setTimeout = realSetTimeout;
    }
    assert.deepEqual(said.said, ["refused: too big"], `close code ${code}`);
  }
});

test("what came before the page could draw is handed on only from the socket open now", async () => {
  const connection = new Connection(null, "", status);
  connection.connect();
  FakeSocket.made.at(-1).onmessage({ data: "from the lost socket" });
  await lose(connection);  // lost, and a new socket opened
  FakeSocket.made.at(-1).onmessage({ data: "from the new socket" });
  const got = [];
  connection.ready((_ws, event) => got.push(event.data));
  assert.deepEqual(got, ["from the new socket"]);
  FakeSocket.made.at(-1).onmessage({ data: "later" });  // from now on, as it comes
  assert.deepEqual(got, ["from the new socket", "later"]);
});
