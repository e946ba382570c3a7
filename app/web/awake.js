// Keeps the screen on while the frost is in front and live: a Screen Wake Lock held while
// the page is visible and connected, asked again when the page comes back to the front
// (the browser drops it whenever the page is hidden), released when hidden or
// disconnected. Silent where the browser has none (plain HTTP, older browsers).

export class Awake {
  constructor(nav = navigator, doc = document) {
    this.nav = nav;
    this.doc = doc;
    this.connected = false;
    this.sentinel = null;   // the lock held, or null
    this.asking = false;
    this.requests = 0;      // locks asked for (the tests read it)
    doc.addEventListener("visibilitychange", () => this.update());
  }

  get supported() {
    return !!(this.nav.wakeLock && this.nav.wakeLock.request);
  }

  get held() {
    return !!this.sentinel && !this.sentinel.released;
  }

  setConnected(connected) {
    this.connected = connected;
    this.update();
  }

  wanted() {
    return this.connected && this.doc.visibilityState === "visible";
  }

  async update() {
    if (!this.supported) return;
    if (!this.wanted()) {
      const s = this.sentinel;
      this.sentinel = null;
      if (s && !s.released) {
        try { await s.release(); } catch { /* already gone */ }
      }
      return;
    }
    if (this.held || this.asking) return;
    this.asking = true;
    this.requests += 1;
    try {
      const s = await this.nav.wakeLock.request("screen");
      if (this.wanted()) {
        this.sentinel = s;
        // Dropped by the browser (hidden, battery saver): asked again when wanted.
        s.addEventListener("release", () => { if (this.sentinel === s) this.sentinel = null; });
      } else {
        await s.release();
      }
    } catch { /* refused (battery saver, a policy): the screen may dim, nothing else */ }
    this.asking = false;
  }
}
