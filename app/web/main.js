// The phone page: connects to `frost serve`, draws the shared frost with the WebGL2 port of
// the desktop renderer, and sends touches, melts, keys and menu choices back.

import { decodeDelta } from "./protocol.js";
import { Program, Renderer, fetchShaders } from "./renderer.js";
import { Pointers } from "./input.js";
import { Menu } from "./menu.js";
import { withText } from "./png.js";
import { makeApp } from "./makeapp.js";
import { FITS, canvasScale, paneRect as fitPane, prefs, visiblePane } from "./fit.js";
import { PhoneApp } from "./phone.js";
import { Clock, isClock } from "./lockclock.js";
import { rememberBackdrop, showOffline } from "./offline.js";
import { PhotoPicker, backdropUrl } from "./photo.js";

const SCREEN = [760, 1280];
const RETRY_FIRST = 250, RETRY_MOST = 8000;  // ms between reconnects: doubling up to this
const ASK_MS = 5000;  // at most this long for /meta's answer when a socket failed (refusal)
// What the page says, and then does nothing more, when the server refuses its token.
const TOKEN_REPLACED = "this page's link (its token) was replaced: scan the new QR code";

const token = new URLSearchParams(location.search).get("token");
const query = token ? `?token=${encodeURIComponent(token)}` : "";

const canvas = document.getElementById("frost");

// What the page knows; `window.frost` exposes it to the tests and the bench.
const state = {
  hello: null, renderer: null, tick: 0, connected: false, synced: false, dirty: true,
  messages: 0, bytes: 0, hellos: 0, lost: 0, watch: null, latencies: [], frostLatencies: [], backdrop: null, shownBackdrop: null, error: null, frames: 0, blitter: null, socket: null,
  early: [], stopped: false, midSnapshot: false, fit: prefs.get("fit", "fill", FITS),
  refused: null, retry: null, frameError: null, frameErrors: 0,
};
window.frost = state;
state.clock = new Clock();

// The socket first, before the GL context and the shaders (a few hundred ms on a slow
// phone): the server writes this page's hello and snapshot meanwhile. What comes waits in
// state.early, in order, until main() can draw it.
connect(RETRY_FIRST);

const gl = canvas.getContext("webgl2", {
  alpha: false, antialias: false, depth: false, premultipliedAlpha: false, preserveDrawingBuffer: true,
});

// The status line; once the server refused the page (refuse), it says that alone.
function status(text) {
  document.getElementById("status").textContent = state.refused || text;
}

let noticeTimer = 0;
function notice(text) {
  status(text);
  clearTimeout(noticeTimer);
  noticeTimer = setTimeout(() => status(""), 4000);
}

async function main() {
  if (!gl) {
    state.stopped = true;
    state.early = null;
    if (state.socket) state.socket.close(1000, "page: no WebGL2");
    status("This browser has no WebGL2.");
    state.error = "no WebGL2";
    return;
  }
  const sources = await fetchShaders("shaders/", query);
  state.sources = sources;
  state.blitter = new Blitter(gl, sources);
  const pointers = new Pointers(canvas, paneRect, send);
  pointers.attach();
  pointers.onDown = (kind, p, t0) => {
    if (kind === "touch") state.watch = { x: p[0], y: p[1], t0, seen: false, frost: false, frostDrawn: false };
  };
  state.menu = new Menu(document.getElementById("menu"), send, screenshot);
  state.menu.pointers = pointers;
  state.photo = new PhotoPicker(document.getElementById("panel"), query, status, notice);
  makeApp(document.getElementById("menu"), query, state);
  state.phone = new PhoneApp(state, document.getElementById("menu"));
  addEventListener("keydown", onKey);
  addEventListener("resize", () => { state.dirty = true; });
  // A phone may take the GPU away (in the background): start again when it gives it back,
  // the server's snapshot refilling what the context held.
  canvas.addEventListener("webglcontextlost", (event) => {
    event.preventDefault();
    state.renderer = null;
    state.lost += 1;
  });
  canvas.addEventListener("webglcontextrestored", () => {
    state.blitter = new Blitter(gl, sources);
    state.backdrop = state.shownBackdrop = null;
    if (state.socket) state.socket.close(4001, "page: the GPU context was restored");
  });
  // What came while the page got ready, from the socket open now (a closed one's is gone).
  const early = state.early;
  state.early = null;
  for (const [ws, event] of early) {
    if (ws === state.socket) receive(ws, event);
  }
  requestAnimationFrame(frame);
}

// ---- the connection ------------------------------------------------------------------

function connect(retry) {
  state.retry = null;
  const url = new URL("ws" + query, location.href);
  url.protocol = location.protocol === "https:" ? "wss:" : "ws:";
  const ws = new WebSocket(url);
  ws.binaryType = "arraybuffer";
  state.socket = ws;
  let opened = false;
  ws.onopen = () => { retry = RETRY_FIRST; opened = true; };
  ws.onmessage = (event) => {
    if (state.early) state.early.push([ws, event]);
    else receive(ws, event);
  };
  ws.onclose = async (event) => {
    state.connected = false;
    state.midSnapshot = false;
    if (state.phone) state.phone.connected(false);
    state.synced = false;
    state.socket = null;
    if (state.stopped) return;
    if (event.code === 1008 || event.code === 1009 || event.code === 4403) {
      status(`refused: ${event.reason || event.code}`);
    } else if (!opened && !event.reason) {  // gone or refused (a browser does not say which)
      const why = await refusal();
      if (why) return void refuse(why);
      if (state.stopped) return;  // (no WebGL2, found meanwhile)
      status("frost serve is not reachable: trying again");  // (the page may have opened from the cache)
      if (!state.renderer) showOffline(true, canvas, query, state.fit);
    } else {
      status(`reconnecting (${event.reason || "connection lost"})`);
    }
    state.retry = setTimeout(() => connect(Math.min(retry * 2, RETRY_MOST)), retry);
  };
}

// Why the server refuses this page, or null (no answer, or it lets the page in). A socket
// refused (403: the token was replaced, `frost serve --new-token`) fails as one to a server
// that is gone, 1006 and no reason, so /meta is asked: the server refuses it alike.
async function refusal() {
  let r;
  try {
    const signal = AbortSignal.timeout ? AbortSignal.timeout(ASK_MS) : undefined;
    r = await fetch(`meta${query}`, { cache: "no-store", signal });
  } catch {
    return null;  // not reachable
  }
  if (r.status !== 403) return null;
  if (token) return TOKEN_REPLACED;
  // No token: the server says why (a token in force now, a name not this machine's).
  const line = await r.text().then((t) => t.split("\n")[0].replace(/^frost: /, ""), () => "");
  return (line || "frost serve refused this page (HTTP 403)").slice(0, 160);
}

// The server refuses this page for good: the status line says why from now on, and the page
// neither retries nor says anything else (a new address is needed, not a new try).
function refuse(why) {
  state.refused = why;
  state.stopped = true;
  status(why);
  console.warn(`frost: ${why}`);
}

// A message of socket `ws`, once the page can draw.
function receive(ws, event) {
  state.messages += 1;
  if (typeof event.data === "string") return onText(JSON.parse(event.data));
  state.bytes += event.data.byteLength;
  if (isClock(event.data)) return void state.clock.receive(event.data, state).catch((err) => console.error(err));
  if (!state.renderer || gl.isContextLost()) return;
  try {
    const delta = decodeDelta(event.data);
    state.renderer.apply(delta);
    state.tick = delta.tick;
    const w = state.watch;
    if (w && !w.frost) w.frost = grewNear(delta, w, true);
    if (w && !w.seen) w.seen = grewNear(delta, w, false);
    if (delta.snapshotEnd) state.synced = true;
    state.midSnapshot = delta.snapshot && !delta.snapshotEnd;
  } catch (err) {
    // What the page holds is no longer the server's: start again from a snapshot.
    console.error(err);
    ws.close(4000, `page: ${err.message}`.slice(0, 120));
  }
}

function send(message) {
  const ws = state.socket;
  if (ws && ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(message));
}

async function onText(msg) {
  if (msg.type === "hello") {
    state.hello = msg;
    state.hellos += 1;
    state.connected = true;
    state.phone.connected(true);
    status("");
    showOffline(false, canvas);
    const [cols, rows] = msg.grid;
    const r = state.renderer;
    if (gl.isContextLost()) return;
    if (!r || r.gridSize[0] !== cols || r.gridSize[1] !== rows || r.spacing !== msg.spacing
        || r.tile !== msg.tile || r.maxDepth !== msg.max_depth) {
      state.renderer = new Renderer(gl, state.sources, { width: SCREEN[0], height: SCREEN[1], grid: msg.grid,
        spacing: msg.spacing, tile: msg.tile, maxDepth: msg.max_depth, defines: msg.defines });
      state.warm = msg.look;  // (at the next frame: the snapshot is on its way)
    } else {
      r.reset();  // the snapshot that follows holds the whole frost
    }
    // Nothing is drawn until it is whole (what the page showed stays meanwhile).
    state.midSnapshot = true;
    state.backdrop = null;
  }
  if (msg.type === "hello" || msg.type === "state") {
    Object.assign(state.hello, msg, { type: "hello" });
    applyView(state.hello);
    state.menu.show(state.hello);
    state.renderer.damageAll();
    if (state.hello.backdrop !== state.backdrop) await loadBackdrop(state.hello.backdrop);
  } else if (msg.type === "resync") {
    // The server dropped this page's queue: a snapshot follows (its first part resets).
    state.synced = false;
  } else if (msg.type === "pong") {
    state.pong = msg;  // the server's tick when it answered (the tests read it)
  } else if (msg.type === "notice") {
    notice(msg.text);
    state.menu.show(state.hello);  // a refused choice: the menu shows what is in force
  }
}

// The light, the material and the toggles the server sends (names as the shader's uniforms
// without u_, or as sim.look.material.Material's fields).
function applyView(hello) {
  const r = state.renderer;
  for (const [key, value] of Object.entries(hello.uniforms || {})) {
    const name = key.replace(/^u_/, "");
    if (name === "light") r.light = value;
    else r.material[name] = value;
  }
  const view = hello.view || {};
  if ("light" in view) r.light = view.light;
  if ("features" in view) r.showFeatures = !!view.features;
  if ("bumps" in view) r.showBumps = !!view.bumps;
  state.serverLight = r.light;  // the page's tilt turns it (phone.js), for this page alone
}

async function loadBackdrop(name) {
  state.backdrop = name;
  const r = await fetch(backdropUrl(name, query));
  if (!r.ok) return status(`backdrop ${name}: HTTP ${r.status}`);
  const image = await createImageBitmap(await r.blob(), { colorSpaceConversion: "none", premultiplyAlpha: "none" });
  if (state.backdrop !== name) return;  // another came meanwhile
  state.renderer.setBackgroundImage(image);
  state.shownBackdrop = name;
  rememberBackdrop(name);
  state.clock.showOn(state);  // (the lock screen's PNG holds no clock)
}

// Touch to first drawn growth (the bench reads frost.latencies, ms): whether a delta
// brings features (a link's ridge) within GREW_NEAR px of the last finger down: the
// desktop log's "growth", a first crystal frozen onto the seed (a link from the seed
// itself, so its ridge has vertices there whatever hc is). With `anyIce`, ice of any thickness on a grid vertex there counts
// too: the first frost (frost.frostLatencies: the seed's own ice, drawn with the first
// step after the touch, as the desktop log's "frost").
const GREW_NEAR = 12;
function grewNear(delta, { x, y }, anyIce) {
  const f = delta.features;
  for (let i = 0; i < f.length; i += 6) {
    if (Math.hypot(f[i] - x, f[i + 1] - y) < GREW_NEAR) return true;
  }
  if (!anyIce) return false;
  const cols = delta.grid[0], s = state.renderer.spacing;
  let k = 0;
  for (const [start, count] of delta.runs) {
    for (let i = start; i < start + count; i++, k++) {
      const px = (i % cols) * s, py = Math.floor(i / cols) * s;
      if (delta.heights[k] > 0 && Math.hypot(px - x, py - y) < GREW_NEAR) return true;
    }
  }
  return false;
}

// ---- keys ----------------------------------------------------------------------------

// A key as GLFW names it (app/keys.py), or null.
export function keyName(event) {
  const code = event.code;
  if (/^Key[A-Z]$/.test(code)) return code.slice(3);
  if (/^Digit[0-9]$/.test(code)) return code.slice(5);
  if (/^F[0-9]+$/.test(code)) return code;
  const named = {
    Space: "SPACE", Period: "PERIOD", Equal: "EQUAL", Minus: "MINUS", NumpadAdd: "KP_ADD",
    NumpadSubtract: "KP_SUBTRACT", BracketLeft: "LEFT_BRACKET", BracketRight: "RIGHT_BRACKET",
    Quote: "APOSTROPHE", Semicolon: "SEMICOLON", ArrowLeft: "LEFT", ArrowRight: "RIGHT",
    ArrowUp: "UP", ArrowDown: "DOWN", Tab: "TAB", Escape: "ESCAPE",
  };
  return named[code] || null;
}

function onKey(event) {
  if (event.target.closest && event.target.closest("#menu")) return;
  if (event.ctrlKey || event.metaKey || event.altKey) return;
  const name = keyName(event);
  if (!name) return;
  event.preventDefault();
  if (name === "S" || name === "F12") return void screenshot();
  send({ type: "key", key: name });
}

// ---- drawing -------------------------------------------------------------------------

// Where the 760x1280 pane lies on the canvas, canvas px (fitCanvas): covering it, centred, cropped
// (state.fit "fill"), or whole and letterboxed ("pane"); fit.js.
function paneRect() {
  return fitPane(canvas.width, canvas.height, state.fit, SCREEN);
}

function fitCanvas() {
  const cw = canvas.clientWidth, ch = canvas.clientHeight, dpr = window.devicePixelRatio || 1;
  const k = canvasScale(cw, ch, dpr, state.fit, SCREEN);
  // At a canvas px a pane px, even sizes (as the pane's) leave the pane's crop or bars the
  // same each side: centred to the px.
  const even = k < dpr ? 2 : 1;
  const w = Math.max(even * Math.round(cw * k / even), 1), h = Math.max(even * Math.round(ch * k / even), 1);
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w;
    canvas.height = h;
    state.dirty = true;
  }
}

// Draw what changed into the pane's texture, where the screen shows it (`whole`: all of
// it); the canvas is told of it at the next frame.
function drawPane(all = false, whole = false) {
  // (a px more each way: a scaled blit's filter reaches past the last px shown)
  const [x0, y0, x1, y1] = visiblePane(paneRect(), canvas.width, canvas.height, SCREEN);
  const d = state.renderer.render(all, whole ? null : [x0 - 2, y0 - 2, x1 + 2, y1 + 2]);
  const b = state.blitDamage;
  if (d) state.blitDamage = b ? [Math.min(b[0], d[0]), Math.min(b[1], d[1]), Math.max(b[2], d[2]), Math.max(b[3], d[3])] : d;
}

// One frame, and the next asked for whatever this one met: a frame that throws (a bad
// value set on `frost`, a renderer's bug) stopped every frame after it, ticks still coming.
function frame() {
  try {
    drawFrame();
    if (state.frameError) frameRecovered();
  } catch (err) {
    frameFailed(err);
  } finally {
    requestAnimationFrame(frame);
  }
}

// A failed frame: counted, its reason in the status line and the console, logged once for
// each reason (a frame fails again 60 times a second while its cause stays).
const FRAME_REASONS_LOGGED = 16;
const loggedReasons = new Set();
function frameFailed(err) {
  const reason = (err && err.message) || String(err);
  state.frameErrors += 1;
  if (reason === state.frameError) return;
  state.frameError = reason;
  status(`a frame failed: ${reason}`);
  if (!loggedReasons.has(reason) && loggedReasons.size < FRAME_REASONS_LOGGED) {
    loggedReasons.add(reason);
    console.error(`frost: a frame failed: ${reason}`, err);
  }
}

// Frames run again: the status line's word on the failure goes.
function frameRecovered() {
  if (document.getElementById("status").textContent === `a frame failed: ${state.frameError}`) status("");
  state.frameError = null;
}

function drawFrame() {
  fitCanvas();
  if (state.renderer && state.serverLight) state.phone.frame(state.renderer, state.serverLight);
  // (a snapshot comes in parts: the pane is drawn once it is whole, not half drawn first,
  // a whole pane's draw spent on a frame the next part replaces)
  if (state.renderer && state.warm) {
    const look = state.warm in state.renderer.defines.ice ? state.warm : "paper";
    state.warm = null;
    if (state.midSnapshot) state.renderer.warm(look);
  }
  if (state.renderer && !state.midSnapshot) drawPane();
  if (state.renderer && (state.dirty || state.blitDamage)) {
    state.blitter.draw(state.renderer.frame, paneRect(), state.dirty ? null : state.blitDamage);
    state.dirty = false;
    state.blitDamage = null;
    state.frames += 1;
    const w = state.watch;
    if (w && (w.seen || (w.frost && !w.frostDrawn))) {  // the tap's first frost or growth is drawn
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
      const ms = performance.now() - w.t0;
      if (!w.frostDrawn) {
        state.frostLatencies.push(ms);
        state.phone.tapped();  // a short buzz: the tap took
      }
      w.frostDrawn = true;
      if (w.seen) {
        state.latencies.push(ms);
        state.watch = null;
      }
    }
  }
}

// The pane's texture drawn into the canvas's rect (canvas px, y down), black around it.
class Blitter {
  constructor(gl, sources) {
    this.gl = gl;
    this.prog = new Program(gl, sources, "blit.vert", "blit.frag");
    this.array = gl.createVertexArray();
  }

  // `damage`: only the pane px [x0, y0, x1, y1] (y down) changed, else all of it (and the
  // black around it) is drawn.
  draw(texture, rect, damage = null) {
    const gl = this.gl;
    const H = gl.drawingBufferHeight;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    if (damage) {
      // Its canvas px, and two more each way (linear filtering reaches a texel further).
      // Within the pane's rect and the canvas (a covering pane reaches past it).
      const x0 = Math.max(Math.floor(rect.x + damage[0] * rect.scale) - 2, rect.x, 0);
      const y0 = Math.max(Math.floor(rect.y + damage[1] * rect.scale) - 2, rect.y, 0);
      const x1 = Math.min(Math.ceil(rect.x + damage[2] * rect.scale) + 2, rect.x + rect.w, gl.drawingBufferWidth);
      const y1 = Math.min(Math.ceil(rect.y + damage[3] * rect.scale) + 2, rect.y + rect.h, H);
      if (x1 <= x0 || y1 <= y0) return;  // changed where the screen does not show
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(x0, H - y1, x1 - x0, y1 - y0);
    } else {
      gl.viewport(0, 0, gl.drawingBufferWidth, H);
      gl.clearColor(0, 0, 0, 1);
      gl.clear(gl.COLOR_BUFFER_BIT);
    }
    gl.viewport(rect.x, H - rect.y - rect.h, rect.w, rect.h);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    // One canvas px per pane px: nearest, so the page shows the frame exactly.
    const filter = rect.scale === 1 ? gl.NEAREST : gl.LINEAR;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
    this.prog.use({ u_texture: 0, u_rect: [-1, -1, 1, 1] });
    gl.bindVertexArray(this.array);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    gl.bindVertexArray(null);
    gl.disable(gl.SCISSOR_TEST);
  }
}

// ---- screenshot ----------------------------------------------------------------------

// What the screen shows of the pane, in pane px (all 760x1280 of it in "whole pane", the
// part the screen crops it to in "fill"), as PNG bytes with the desktop's metadata keys.
async function screenshotPng() {
  const r = state.renderer;
  drawPane();
  const pixels = r.readFrame();
  for (let i = 3; i < pixels.length; i += 4) pixels[i] = 255;
  const [x0, y0, x1, y1] = visiblePane(paneRect(), canvas.width, canvas.height, SCREEN);
  const c = document.createElement("canvas");
  [c.width, c.height] = [x1 - x0, y1 - y0];
  c.getContext("2d").putImageData(new ImageData(new Uint8ClampedArray(pixels.buffer), ...SCREEN), -x0, -y0);
  const blob = await new Promise((resolve) => c.toBlob(resolve, "image/png"));
  const png = new Uint8Array(await blob.arrayBuffer());
  // frost_meta's keys in its order; parameters, seed and touches as the server gives them
  // (GET /meta).
  const known = await serverMeta();
  const local = new Date(Date.now() - new Date().getTimezoneOffset() * 60000);
  const meta = {
    parameters: known.parameters ?? null, seed: known.seed ?? null, tick: state.tick,
    touches: known.touches ?? [], Software: "frost (page)",
    "Creation Time": local.toISOString().slice(0, 19),
    view: { light: r.light, features: r.showFeatures, bumps: r.showBumps, background: state.backdrop },
  };
  // A crop: where its px lie on the pane (the touches' px are the pane's).
  if (c.width !== SCREEN[0] || c.height !== SCREEN[1]) meta.view.crop = [x0, y0, c.width, c.height];
  return withText(png, meta);
}

async function serverMeta() {
  try {
    const r = await fetch(`meta${query}`);
    if (r.ok) return await r.json();
  } catch { /* the server is gone: the page's own keys only */ }
  return {};
}

async function screenshot() {
  if (!state.renderer) return;
  const png = await screenshotPng();
  const a = document.createElement("a");
  a.href = URL.createObjectURL(new Blob([png], { type: "image/png" }));
  const stamp = new Date().toISOString().replace(/[-:]/g, "").replace("T", "-").slice(0, 15);
  a.download = `frost-${stamp}.png`;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}
state.screenshotPng = screenshotPng;

// The pane's pixels now (RGBA, top row first) as base64: for the tests and the bench.
state.framePixels = () => {
  drawPane(false, true);
  const px = state.renderer.readFrame();
  let s = "";
  for (let i = 0; i < px.length; i += 0x8000) s += String.fromCharCode(...px.subarray(i, i + 0x8000));
  return btoa(s);
};

state.canvasSize = () => [canvas.width, canvas.height];
state.pane = paneRect;
// Where the pane lies in CSS px (the page's client coordinates): {x, y, w, h, sx, sy}, sx
// and sy CSS px per pane px (a rounded canvas may be stretched a hair more one way).
state.paneCss = () => {
  const r = paneRect(), box = canvas.getBoundingClientRect();
  const kx = box.width / canvas.width, ky = box.height / canvas.height;
  return { x: box.left + r.x * kx, y: box.top + r.y * ky, w: r.w * kx, h: r.h * ky,
    sx: r.scale * kx, sy: r.scale * ky };
};

// Frame times (ms) of `n` full frames at 760x1280, each waited for (a 1-pixel read).
state.frameTimes = (n) => {
  const r = state.renderer, one = new Uint8Array(4), times = [];
  for (let i = 0; i < n; i++) {
    const t0 = performance.now();
    r.render(true);
    gl.bindFramebuffer(gl.FRAMEBUFFER, r.frameFbo);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    times.push(performance.now() - t0);
  }
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return times;
};

main().catch((err) => {
  state.error = String(err);
  status(`error: ${err.message}`);
  console.error(err);
});
