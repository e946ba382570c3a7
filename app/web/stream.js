// The server's messages to the page and what each does: a hello (the page's defaults and
// state, then a snapshot), a delta, a state change, a notice; and what the page counts of
// them (the tests and the bench read it through `window.frost`).

import { decodeDelta } from "./protocol.js";
import { isClock } from "./lockclock.js";
import { showOffline } from "./offline.js";
import { weatherText } from "./weather.js";

export class Stream {
  // page: `window.frost` (its clock, menu and phone); parts: the page's view, pane, taps
  // and status line, its canvas and gl.
  constructor(page, { view, pane, taps, status, canvas, gl }) {
    Object.assign(this, { page, view, pane, taps, status, canvas, gl });
    this.hello = null;  // the server's state: the last hello with each state message since
    this.hellos = 0;
    this.messages = 0;
    this.bytes = 0;
    this.tick = 0;
    this.connected = false;
    this.synced = false;       // the page holds the server's frost (a whole snapshot came)
    this.midSnapshot = false;  // a snapshot has come in part (nothing is drawn meanwhile)
    this.pong = null;  // the server's tick when it answered (the tests read it)
  }

  // The socket closed: nothing is in sync any more.
  closed() {
    this.connected = false;
    this.midSnapshot = false;
    if (this.page.phone) this.page.phone.connected(false);
    this.synced = false;
  }

  // A message of socket `ws`, once the page can draw.
  receive(ws, event) {
    this.messages += 1;
    if (typeof event.data === "string") return this.text(JSON.parse(event.data));
    this.bytes += event.data.byteLength;
    if (isClock(event.data)) return void this.page.clock.receive(event.data, this.page).catch((err) => console.error(err));
    const r = this.view.renderer;
    if (!r || this.gl.isContextLost()) return;
    try {
      const delta = decodeDelta(event.data);
      r.apply(delta);
      this.tick = delta.tick;
      this.taps.delta(delta, r.spacing);
      if (delta.snapshotEnd) this.synced = true;
      this.midSnapshot = delta.snapshot && !delta.snapshotEnd;
    } catch (err) {
      // What the page holds is no longer the server's: start again from a snapshot.
      console.error(err);
      ws.close(4000, `page: ${err.message}`.slice(0, 120));
    }
  }

  async text(msg) {
    if (msg.type === "hello" && !this.connect(msg)) return;
    if (msg.type === "hello" || msg.type === "state") {
      const hello = Object.assign(this.hello, msg, { type: "hello" });
      this.view.apply(hello);
      this.page.menu.show(hello);
      if ("weather" in msg) this.status.setIdle(weatherText(hello.weather));
      if (hello.backdrop !== this.view.backdrop) await this.view.loadBackdrop(hello.backdrop, this.page.clock, this.page);
    } else if (msg.type === "resync") {
      // The server dropped this page's queue: a snapshot follows (its first part resets).
      this.synced = false;
    } else if (msg.type === "pong") {
      this.pong = msg;
    } else if (msg.type === "notice") {
      this.status.notice(msg.text);
      this.page.menu.show(this.hello);  // a refused choice: the menu shows what is in force
    }
  }

  // A hello: the page is connected, its pane the hello's screen, its renderer the hello's;
  // false while the GL context is lost (nothing to draw with).
  connect(msg) {
    this.hello = msg;
    if (!msg.local) this.hellos += 1;  // (the server's: the phone's own frost is not a connection)
    this.connected = true;
    this.page.phone.connected(true);
    this.status.say("");
    if (!msg.local && this.page.alone) this.page.alone.serverHello();
    showOffline(false, this.canvas);
    this.pane.screen = msg.screen;
    if (this.gl.isContextLost()) return false;
    this.view.hello(msg);
    // Nothing is drawn until it is whole (what the page showed stays meanwhile).
    this.midSnapshot = true;
    return true;
  }
}
