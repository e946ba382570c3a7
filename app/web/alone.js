// The phone's own frost (docs/phone.md, On this phone): when no server answers, the page
// grows frost itself, in a Web Worker (local/worker.js) that speaks frost serve's protocol
// through a stand-in for the socket, so the stream and the renderer draw it as they draw
// the server's. The status line says "on this phone"; `window.frost.local` states the
// worker's own figures; while it runs the page asks for the server now and then, and when
// one answers it offers to join it ("frost serve is back: join"), never unasked. Joining
// keeps the phone's frost: its worker waits (held), its session still saved from the menu,
// and when the server goes again the frost goes on from where it was.

import { save } from "./shot.js";

export const ON_PHONE = "on this phone";
const PROBE_MS = 3000;   // between two asks whether a server answers again (Connection.refusal)
// Said once the server's frost shows after a join.
export const KEPT = "your frost waits on this phone (the menu saves it)";

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
  // ?token= query, the join button; `serverless`: the static site's page (`frost web`),
  // which has no server to ask for, nor to join; `wanted`: the preset to begin with where
  // the page showed none (a deep link's).
  constructor(page, { connection, stream, status, query, joinButton, serverless = false, wanted = {} }) {
    Object.assign(this, { page, connection, stream, status, query, joinButton, serverless, wanted });
    this.worker = null;
    this.socket = null;
    this.failed = null;  // why the phone cannot grow frost (its modules not loaded: no cache)
    this.probing = 0;
    this.asking = false;  // a probe waits for its answer
    this.asked = new Map();  // "session" | "meta" -> resolve
    this.stats = null;  // the worker's last stats message
    this.held = false;  // the page joined a server: the worker keeps the phone's frost, not ticking
    this.waking = false;  // resumed: what the worker sent before it held is dropped until it says so
    this.joined = false;  // joining: the server's hello is told the phone's frost is kept
    page.local = null;
    joinButton.addEventListener("click", () => this.join());
  }

  // The phone's frost grows on the page now.
  get running() {
    return this.worker !== null && !this.held;
  }

  // A phone's frost is kept, growing or held (its session can be saved).
  get kept() {
    return this.worker !== null;
  }

  // Grow frost on this phone (no server answers): the held frost again, from where it was,
  // or a new one; false where it cannot (then the page waits for a server as before).
  start() {
    if (this.held) return this.resume();
    if (this.worker || this.failed) return !!this.worker;
    const worker = new Worker(new URL(`local/worker.js${this.query}`, import.meta.url), { type: "module" });
    this.worker = worker;
    worker.onmessage = (event) => this.message(event.data);
    worker.onerror = (event) => this.fail(event.message || "its modules did not load");
    this.socket = new WorkerSocket(worker);
    // (the static site's frost is the phone's own always: nothing to tell apart from a server's)
    this.status.resting = this.serverless ? "" : ON_PHONE;
    this.configure(worker).catch((err) => this.fail(err.message));
    if (!this.serverless) this.probing = setInterval(() => this.probe(), PROBE_MS);
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
      start: { preset: shown.preset ?? this.wanted.preset, look: shown.look, backdrop: shown.backdrop } });
    if (this.page.localWeather && this.page.localWeather.message) worker.postMessage(this.page.localWeather.message);
  }

  // A message of the worker: frost serve's (text or bytes) to the stream, or its own.
  // Held, or resumed before the worker says so, its frost's messages (ticks it stepped
  // before it held) are not the page's to draw.
  message(data) {
    const quiet = this.held || this.waking;
    if (typeof data === "string" || data instanceof ArrayBuffer) {
      if (!quiet && this.socket.onmessage) this.socket.onmessage({ data });
    } else if (data.type === "resumed") {
      this.waking = false;
    } else if (data.type === "stats") {
      if (quiet) return;
      // A plain object of own properties, the five (the tests read it as JSON); the
      // worker's other figures (its median tick, the touches dropped) in `stats`.
      this.stats = data;
      // (what other parts put on it, such as the weather's, stays)
      this.page.local = { ...this.page.local, tick: data.tick, crystals: data.crystals, ticksPerSecond: data.ticksPerSecond,
        tickP99Ms: data.tickP99Ms, weather: this.page.weatherLocal, clear: () => this.send({ type: "clear" }) };
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
    const growing = this.running;
    this.end();
    if (!growing) return;  // (held: the page shows the server's frost)
    if (this.serverless) return this.status.say(`this browser cannot grow the frost: ${reason}`);
    this.status.say("frost serve is not reachable: trying again");
    this.connection.connect();
  }

  // The worker ended, the page's state of it dropped.
  end() {
    if (this.worker) this.worker.terminate();
    const growing = this.running;
    this.worker = null;
    this.socket = null;
    this.held = false;
    if (growing) this.leave();
    for (const resolve of this.asked.values()) resolve(null);
    this.asked.clear();
  }

  // The page stops showing the phone's frost (ended, or held while it joins a server).
  leave() {
    clearInterval(this.probing);
    this.joinButton.hidden = true;
    this.status.resting = "";
    this.page.local = null;
    this.connection.socket = null;
    this.stream.closed();
  }

  // The held frost goes on (no server again): the worker's hello and snapshot replace what
  // the page showed, its ticks go on from the tick it held at.
  resume() {
    this.held = false;
    this.waking = true;
    this.connection.adopt(this.socket);
    this.status.resting = ON_PHONE;
    this.send({ type: "resume" });
    this.probing = setInterval(() => this.probe(), PROBE_MS);
    return true;
  }

  // Whether a server answers again: then the join is offered (the frost stays the phone's).
  // A server that refuses this page (its token replaced: 403) is said, as the connection
  // says it, and ends the phone's frost: this address has no server to join any more.
  async probe() {
    if (this.asking) return;  // (an answer may take up to 5 s)
    this.asking = true;
    const why = await this.connection.refusal().finally(() => { this.asking = false; });
    if (!this.running) return;
    if (why) {
      this.end();
      this.connection.refuse(why);
      return;
    }
    this.joinButton.hidden = !this.connection.answered;
  }

  // The user's choice: the server's frost is shown, the phone's waits in its worker (held:
  // no ticks), its session kept for Save session; it goes on when no server answers again.
  join() {
    if (!this.running) return;
    this.send({ type: "hold" });
    this.held = true;
    this.leave();
    this.joined = true;
    this.status.say("");
    this.connection.connect();
  }

  // The server's hello came: after a join, the page says where the phone's frost is.
  serverHello() {
    if (!this.joined) return;
    this.joined = false;
    if (this.held) this.status.notice(KEPT);
  }

  // The phone's session file downloaded (frost-phone-<date>-<time>.json).
  async download() {
    const session = await this.ask("session");
    if (!session) return;
    save(new Blob([JSON.stringify(session, null, 1)], { type: "application/json" }), "frost-phone", "json");
  }
}
