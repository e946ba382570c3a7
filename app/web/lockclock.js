// The lock screen's live clock (docs/protocol.md, the clock message): each minute the server
// sends the clock box's new pixels only, a PNG to be put at (x, y) on the `lockscreen`
// backdrop; the page writes it into its backdrop texture (texSubImage2D), whenever the lock
// screen is the backdrop it holds (at once, or once the lock screen's PNG has loaded).
// With no server (the phone's own frost: the static site, or the page with its server
// gone) the page draws the box itself each minute, as app/lockscreen.py's clock_patch does:
// the date, the time and, after a weather reading of the page's own (weather_local.js
// calls `outside`), the temperature outside under the time.

import { backdropUrl } from "./photo.js";
import { CLOCK_BOX, CLOCK_LINES } from "./local/shared.js";

export const CLOCK = 2;  // the binary message type
export const LIVE = "lockscreen";
const HEADER = 28;
// app/lockscreen.py's drawing: the box's colours (its CLOCK_BOX, x0, y0, x1, y1 on the
// 760x1280 backdrop, and CLOCK_LINES, each line's centre and size, come from shared.js).
const TEXT = "rgb(248, 249, 252)";
const SHADOW = "rgba(8, 14, 34, 0.55)";  // (Pillow's mask, blurred with a radius of 7, times 0.55)
const FONT = "Aileron, 'Helvetica Neue', Helvetica, Arial, sans-serif";
const DAYS = ["Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday"];
const MONTHS = ["January", "February", "March", "April", "May", "June", "July", "August",
  "September", "October", "November", "December"];

// A number rounded as Python's round() does (half to even), never "-0".
function wholeDegrees(t) {
  let r = Math.round(t);
  if (Math.abs(t % 1) === 0.5 && r % 2 !== 0) r -= 1;
  return r === 0 ? 0 : r;
}

// What the lock screen says under its clock of a reading of `t` degrees C outside
// (app/lockscreen.py's outside_line): "-7 °C outside".
export function outsideLine(t) {
  return Number.isFinite(t) ? `${wholeDegrees(t)} °C outside` : "";
}

// The box's lines at `when` (local time), as app/lockscreen.py's clock_patch words them:
// {minute ("YYYY-MM-DDTHH:MM"), date ("Thursday 26 November"), time ("09:41")}.
export function clockLines(when) {
  const two = (n) => String(n).padStart(2, "0");
  const time = `${two(when.getHours())}:${two(when.getMinutes())}`;
  return {
    minute: `${when.getFullYear()}-${two(when.getMonth() + 1)}-${two(when.getDate())}T${time}`,
    date: `${DAYS[when.getDay()]} ${when.getDate()} ${MONTHS[when.getMonth()]}`, time,
  };
}

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
    this.outsideC = null;  // the page's own reading of the temperature outside (C), or null
    this.box = null;  // the lock screen's static box pixels (an ImageBitmap), once fetched
    this.drawn = null;  // what the page drew in the box itself: {minute, date, time, outside}
    this.page = null;  // `window.frost`, once the lock screen was shown on it
    this.timer = 0;   // the next minute's redraw, while the page draws the box
  }

  // The page's own weather reading (weather_local.js): `t` degrees C outside, drawn under
  // the time at once where the page draws the box.
  outside(t) {
    this.outsideC = Number.isFinite(t) ? t : null;
    if (this.page) this.showOn(this.page);
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

  // The latest minute into the backdrop texture, if the lock screen is what it holds: the
  // server's, or with no server (the phone's own frost) the page's own.
  showOn(state) {
    this.page = state;
    if (state.alone && state.alone.running) {
      this.drawOwn(state).catch((err) => console.error(err));
      return;
    }
    const m = this.latest;
    if (!m || !state.renderer || state.shownBackdrop !== LIVE) return;
    const t0 = performance.now();
    state.renderer.setBackgroundRect(m.x, m.y, m.image);
    this.uploads.push(performance.now() - t0);
    this.shown = m.minute;
  }

  // The page's own clock box (no server sends one): the lock screen's static box, the date,
  // the time and the temperature outside drawn over it, redrawn as each minute turns.
  async drawOwn(state) {
    clearTimeout(this.timer);
    if (!state.renderer || state.shownBackdrop !== LIVE) return;
    const seq = ++this.seq;
    const [x0, y0, x1, y1] = CLOCK_BOX;
    const w = x1 - x0, h = y1 - y0;
    if (!this.box) {
      const r = await fetch(backdropUrl(LIVE, state.alone.query || ""));
      if (!r.ok) throw new Error(`the lock screen's clock box: HTTP ${r.status}`);
      this.box = await createImageBitmap(await r.blob(), x0, y0, w, h,
        { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    }
    const now = new Date();
    const lines = { ...clockLines(now), outside: outsideLine(this.outsideC ?? NaN) };
    const canvas = document.createElement("canvas");
    canvas.width = w;
    canvas.height = h;
    const g = canvas.getContext("2d");
    g.drawImage(this.box, 0, 0);
    // White figures over a soft shadow (a blur of sigma 7 px), as the desktop draws them.
    Object.assign(g, { textAlign: "center", textBaseline: "middle", fillStyle: TEXT,
      shadowColor: SHADOW, shadowBlur: 14 });
    for (const [name, [y, size]] of Object.entries(CLOCK_LINES)) {
      if (!lines[name]) continue;
      g.font = `${size}px ${FONT}`;
      g.fillText(lines[name], w / 2, y);
    }
    const image = await createImageBitmap(canvas, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
    if (seq !== this.seq || !state.renderer || state.shownBackdrop !== LIVE || !state.alone.running) return;
    state.renderer.setBackgroundRect(x0, y0, image);
    this.shown = lines.minute;
    this.drawn = lines;
    // the next minute's box, drawn as it turns
    const wait = 60_000 - (now.getSeconds() * 1000 + now.getMilliseconds()) + 50;
    this.timer = setTimeout(() => this.showOn(state), wait);
  }
}
