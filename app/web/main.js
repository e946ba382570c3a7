// The phone page: connects to `frost serve`, draws the shared frost with the WebGL2 port of
// the desktop renderer, and sends touches, melts, keys and menu choices back. This module
// makes the page's parts, each with one job, and wires them together.

import { fetchShaders } from "./renderer.js";
import { Pointers } from "./input.js";
import { Menu } from "./menu.js";
import { makeApp } from "./makeapp.js";
import { PhoneApp } from "./phone.js";
import { Clock } from "./lockclock.js";
import { showOffline } from "./offline.js";
import { PhotoPicker } from "./photo.js";
import { WeatherHere } from "./weather.js";
import { StatusLine } from "./status.js";
import { Connection } from "./connection.js";
import { Pane } from "./pane.js";
import { TapWatch } from "./taps.js";
import { View } from "./view.js";
import { Stream } from "./stream.js";
import { FrameLoop } from "./frames.js";
import { Screenshots } from "./shot.js";
import { listenToKeys } from "./keys.js";
import { Alone } from "./alone.js";
import { SITE } from "./site.js";
import { DeepLinks } from "./links.js";
import { startWeather } from "./weather_local.js";

const token = new URLSearchParams(location.search).get("token");
const query = token ? `?token=${encodeURIComponent(token)}` : "";

const canvas = document.getElementById("frost");
const menuElement = document.getElementById("menu");

const status = new StatusLine(document.getElementById("status"));
const connection = new Connection(token, query, status);
const pane = new Pane(canvas);
const taps = new TapWatch();

// What the page knows; `window.frost` exposes it to the tests and the bench: its parts'
// fields by their names (frost.synced is the stream's), and the page's menu, phone app,
// photo picker, weather button and clock.
const frost = { error: null, clock: new Clock() };
window.frost = frost;

// The address's deep links (?preset=, ?weather=): taken with the first hello.
const links = new DeepLinks(location.search);

// The socket first, before the GL context and the shaders (a few hundred ms on a slow
// phone): the server writes this page's hello and snapshot meanwhile. What comes waits in
// the connection, in order, until main() can draw it. The static site (`frost web`) has no
// server: it asks none, and grows its own frost at once (below).
if (!SITE.static) connection.connect();

const gl = canvas.getContext("webgl2", {
  alpha: false, antialias: false, depth: false, premultipliedAlpha: false, preserveDrawingBuffer: true,
});
const view = new View(gl, query, (text) => status.say(text));
const stream = new Stream(frost, { view, pane, taps, status, canvas, gl });
const frames = new FrameLoop(frost, { view, stream, pane, taps, status, gl });
const shots = new Screenshots(query, { view, pane, frames, stream });

// No server answers: the phone grows its own frost (alone.js), else the remembered backdrop.
const alone = new Alone(frost, { connection, stream, status, query, joinButton: document.getElementById("join"),
  serverless: SITE.static, wanted: { preset: links.preset } });
frost.alone = alone;
frost.site = SITE;
shots.localMeta = () => alone.running && alone.ask("meta");
// The weather a deep link asks for: the page's own (weather_local.js), where the phone grows
// its own frost (at once on the static site; when the server is not reachable on frost
// serve's page, which follows the server's weather meanwhile).
let weatherAsked = false;
function ownWeather() {
  if (weatherAsked || !links.weather) return;
  weatherAsked = true;
  startWeather(links.weather);
}
if (SITE.static) {
  showOffline(true, canvas, query, pane.fit);  // (the remembered backdrop until the first frame)
  alone.start();
  ownWeather();
}

connection.onClosed = () => stream.closed();
// (A server that answers while its socket fails is tried again: an HTTPS socket that an
// untrusted certificate stops.)
connection.onUnreachable = (answered) => {
  // (the backdrop until the first frame, the phone's own frost's or the server's)
  if (!view.renderer) showOffline(true, canvas, query, pane.fit);
  const growing = !answered && alone.start();
  if (growing) ownWeather();
  return growing;
};

// `names` of `part` read and set as `frost`'s own.
function expose(part, names) {
  for (const name of names) {
    Object.defineProperty(frost, name, {
      get: () => part[name], set: (value) => { part[name] = value; }, enumerable: true,
    });
  }
}
expose(status, ["refused"]);
expose(connection, ["socket", "retry", "stopped", "early"]);
expose(pane, ["fit", "dirty"]);
expose(taps, ["watch", "latencies", "frostLatencies"]);
expose(view, ["renderer", "sources", "blitter", "backdrop", "shownBackdrop", "serverLight", "warm", "lost"]);
expose(stream, ["hello", "hellos", "messages", "bytes", "tick", "connected", "synced", "midSnapshot", "pong"]);
expose(frames, ["frames", "blitDamage", "frameError", "frameErrors"]);
Object.assign(frost, {
  screenshotPng: () => shots.png(),
  framePixels: () => frames.pixels(),  // the pane's pixels now, base64
  frameTimes: (n) => frames.times(n),  // ms of `n` full frames, each waited for
  canvasSize: () => pane.size(),
  pane: () => pane.rect(),    // the pane's rect, canvas px
  paneCss: () => pane.css(),  // the pane's rect, CSS px
});

async function main() {
  if (!gl) {
    connection.stop("page: no WebGL2");
    status.say("This browser has no WebGL2.");
    frost.error = "no WebGL2";
    return;
  }
  view.ready(await fetchShaders("shaders/", query));
  const send = (message) => connection.send(message);
  const screenshot = () => shots.take();
  const pointers = new Pointers(canvas, () => pane.rect(), send, () => pane.screen);
  pointers.attach();
  pointers.onDown = (kind, p, t0) => taps.down(kind, p, t0);
  frost.menu = new Menu(menuElement, send, screenshot, () => alone.download(), () => alone.kept);
  frost.menu.pointers = pointers;
  frost.photo = new PhotoPicker(document.getElementById("panel"), query,
    (text) => status.say(text), (text) => status.notice(text));
  frost.weather = new WeatherHere(document.getElementById("panel"), query,
    (text) => status.say(text), (text) => status.notice(text));
  if (!SITE.static) makeApp(menuElement, query, frost);  // (a static host has no ports nor authority)
  frost.phone = new PhoneApp(frost, menuElement);
  listenToKeys(send, screenshot);
  addEventListener("resize", () => { pane.dirty = true; });
  view.watchContext(canvas, () => {
    if (connection.socket) connection.socket.close(4001, "page: the GPU context was restored");
  });
  connection.ready((ws, event) => {
    stream.receive(ws, event);
    if (stream.hello && !links.applied) links.hello(stream.hello, send, (text) => status.say(text));
  });
  frames.start();
}

main().catch((err) => {
  frost.error = String(err);
  status.say(`error: ${err.message}`);
  console.error(err);
});
