// The lock screen's live clock (docs/protocol.md, the clock message): each minute the server
// sends the clock box's new pixels only, a PNG to be put at (x, y) on the `lockscreen`
// backdrop; the page writes it into its backdrop texture (texSubImage2D), whenever the lock
// screen is the backdrop it holds (at once, or once the lock screen's PNG has loaded).

export const CLOCK = 2;  // the binary message type
export const LIVE = "lockscreen";
const HEADER = 28;

// Whether a binary message is a clock message (else it is geometry).
export function isClock(data) {
  return data.byteLength > 1 && new Uint8Array(data, 0, 2)[1] === CLOCK;
}

// A clock message's fields: x, y, w, h (px, y down), minute ("YYYY-MM-DDTHH:MM"), png.
export function decodeClock(data) {
  if (data.byteLength < HEADER + 8) throw new Error(`clock message of ${data.byteLength} bytes`);
  const v = new DataView(data);
  if (v.getUint8(0) !== 1 || v.getUint8(1) !== CLOCK) throw new Error("not a clock message");
  return {
    x: v.getUint16(2, true), y: v.getUint16(4, true), w: v.getUint16(6, true), h: v.getUint16(8, true),
    minute: String.fromCharCode(...new Uint8Array(data, 10, 16)), png: new Uint8Array(data, HEADER),
  };
}

export class Clock {
  constructor() {
    this.latest = null;  // the newest minute decoded: its fields and its ImageBitmap
    this.shown = null;  // the minute the backdrop texture holds
    this.received = 0;  // clock messages and their bytes (the tests and the bench read them)
    this.bytes = 0;
    this.uploads = [];  // ms each texture update took
    this.seq = 0;
  }

  // A clock message in: decoded, and shown if the lock screen is the backdrop.
  async receive(data, state) {
    const m = decodeClock(data);
    this.received += 1;
    this.bytes += data.byteLength;
    this.last = data;  // (the bench decodes it again)
    const seq = ++this.seq;
    const image = await createImageBitmap(new Blob([m.png], { type: "image/png" }),
      { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    if (seq !== this.seq) return;  // a newer minute came meanwhile
    if (image.width !== m.w || image.height !== m.h) throw new Error(`clock picture ${image.width}x${image.height}, not ${m.w}x${m.h}`);
    this.latest = { ...m, image };
    this.showOn(state);
  }

  // The latest minute into the backdrop texture, if the lock screen is what it holds.
  showOn(state) {
    const m = this.latest;
    if (!m || !state.renderer || state.shownBackdrop !== LIVE) return;
    const t0 = performance.now();
    state.renderer.setBackgroundRect(m.x, m.y, m.image);
    this.uploads.push(performance.now() - t0);
    this.shown = m.minute;
  }
}
