// The phone's own frost (docs/phone.md, On this phone): when no server answers, the page
// grows frost itself, in a Web Worker (local/worker.js) that speaks frost serve's protocol
// through a stand-in for the socket, so the stream and the renderer draw it as they draw
// the server's. The status line says "on this phone"; `window.frost.local` states the
// worker's own figures; while it runs the page asks for the server now and then, and when
// one answers it offers to join it ("frost serve is back: join"), never unasked.

import { save } from "./shot.js";

export const ON_PHONE = "on this phone";
const PROBE_MS = 3000;   // between two asks whether a server answers again (Connection.refusal)

// The worker as the page's socket: what Connection and Stream use of a WebSocket.
class WorkerSocket {
  constructor(worker) {
    this.worker = worker;
    this.readyState = WebSocket.OPEN;
    this.onmessage = null;
  }

  send(text) {
    this.worker.postMessage(JSON.parse(text));
  }

  // The page could not apply a message (Stream closes the socket then): the whole frost again.
  close(code, reason) {
    console.warn(`frost: the phone's frost sent again (${code} ${reason || ""})`);
    this.worker.postMessage({ type: "resync" });
  }
}

export class Alone {
  // page: `window.frost`; parts: the page's connection, stream and status line, its
  // ?token= query, the join button, and `start()` giving the preset, look and backdrop to
  // begin with.
  constructor(page, { connection, stream, status, query, joinButton }) {
    Object.assign(this, { page, connection, stream, status, query, joinButton });
    this.worker = null;
    this.socket = null;
    this.failed = null;  // why the phone cannot grow frost (its modules not loaded: no cache)
    this.probing = 0;
    this.asking = false;  // a probe waits for its answer
    this.asked = new Map();  // "session" | "meta" -> resolve
    this.stats = null;  // the worker's last stats message
    page.local = null;
    joinButton.addEventListener("click", () => this.join());
  }

  get running() {
    return this.worker !== null;
  }

  // Grow frost on this phone (no server answers); false where it cannot (then the page
  // waits for a server as before).
  start() {
    if (this.worker || this.failed) return !!this.worker;
    const worker = new Worker(new URL(`local/worker.js${this.query}`, import.meta.url), { type: "module" });
    this.worker = worker;
    worker.onmessage = (event) => this.message(event.data);
    worker.onerror = (event) => this.fail(event.message || "its modules did not load");
    this.socket = new WorkerSocket(worker);
    this.status.resting = ON_PHONE;
    this.configure(worker).catch((err) => this.fail(err.message));
    this.probing = setInterval(() => this.probe(), PROBE_MS);
    return true;
  }

  async configure(worker) {
    const r = await fetch(new URL(`local/params.json${this.query}`, import.meta.url));
    if (!r.ok) throw new Error(`params.json: HTTP ${r.status}`);
    const config = await r.json();
    if (worker !== this.worker) return;
    const shown = this.stream.hello || {};
    this.connection.adopt(this.socket);
    worker.postMessage({ type: "start", config,
      start: { preset: shown.preset, look: shown.look, backdrop: shown.backdrop } });
  }

  // A message of the worker: frost serve's (text or bytes) to the stream, or its own.
  message(data) {
    if (typeof data === "string" || data instanceof ArrayBuffer) {
      if (this.socket.onmessage) this.socket.onmessage({ data });
    } else if (data.type === "stats") {
      // A plain object of own properties, the five (the tests read it as JSON); the
      // worker's other figures (its median tick, the touches dropped) in `stats`.
      this.stats = data;
      this.page.local = { tick: data.tick, crystals: data.crystals, ticksPerSecond: data.ticksPerSecond,
        tickP99Ms: data.tickP99Ms, clear: () => this.send({ type: "clear" }) };
    } else if (data.type === "session" || data.type === "meta") {
      const resolve = this.asked.get(data.type);
      this.asked.delete(data.type);
      if (resolve) resolve(data.data);
    } else if (data.type === "failed") {
      this.fail(data.reason);
    }
  }

  send(message) {
    if (this.worker) this.worker.postMessage(message);
  }

  // The worker's session file ("session") or screenshot keys ("meta").
  ask(type) {
    if (!this.worker) return Promise.resolve(null);
    return new Promise((resolve) => {
      this.asked.set(type, resolve);
      this.send({ type });
    });
  }

  // The phone cannot grow frost: said once, and the page waits for a server again.
  fail(reason) {
    if (this.failed) return;  // (a worker that fails may say so twice: its error and its message)
    this.failed = reason;
    console.warn(`frost: the phone's own frost stopped: ${reason}`);
    this.end();
    this.status.say("frost serve is not reachable: trying again");
    this.connection.connect();
  }

  // The worker ended, the page's state of it dropped.
  end() {
    if (this.worker) this.worker.terminate();
    this.worker = null;
    this.socket = null;
    clearInterval(this.probing);
    this.joinButton.hidden = true;
    this.status.resting = "";
    this.page.local = null;
    this.connection.socket = null;
    this.stream.closed();
    for (const resolve of this.asked.values()) resolve(null);
    this.asked.clear();
  }

  // Whether a server answers again: then the join is offered (the frost stays the phone's).
  // A server that refuses this page (its token replaced: 403) is said, as the connection
  // says it, and ends the phone's frost: this address has no server to join any more.
  async probe() {
    if (this.asking) return;  // (an answer may take up to 5 s)
    this.asking = true;
    const why = await this.connection.refusal().finally(() => { this.asking = false; });
    if (!this.worker) return;
    if (why) {
      this.end();
      this.connection.refuse(why);
      return;
    }
    this.joinButton.hidden = !this.connection.answered;
  }

  // The user's choice: the server's frost replaces the phone's.
  join() {
    this.end();
    this.status.say("");
    this.connection.connect();
  }

  // The phone's session file downloaded (frost-phone-<date>-<time>.json).
  async download() {
    const session = await this.ask("session");
    if (!session) return;
    save(new Blob([JSON.stringify(session, null, 1)], { type: "application/json" }), "frost-phone", "json");
  }
}
