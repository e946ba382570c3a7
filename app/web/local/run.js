// The phone's own frost, as frost serve runs it for its pages: the simulation (Frost) and
// its geometry (FrostGeometry), the page's input applied before each tick within a bound,
// the menu's choices (preset, look, backdrop, pause, clear), and what the page is sent:
// a hello, snapshots and deltas in the binary protocol's bytes (Encoder), and state
// messages, so the renderer draws the phone's frost as it draws the server's.

import { Frost } from "./frost.js";
import { FrostGeometry } from "./geometry.js";
import { Encoder } from "./encode.js";
import { Fingers } from "./fingers.js";
import { SessionRecord } from "./record.js";
import { THAW_TICKS } from "./shared.js";

export const TOUCHES_PER_TICK = 16;  // the page's touches and melts applied before a tick
const TEXT_KINDS = ["preset", "look", "backdrop", "pause", "clear", "step"];
// In a thaw, a layer of the ice's tips melts every THAW_TICKS ticks (sim/weather/glass.py,
// as the desktop's timeline melts them).
export { THAW_TICKS };
// Before the first hello, a frost of its own grown this many ticks from three touches and
// thrown away: the first ticks after a touch run before the JavaScript engine has compiled
// the simulation's loops, and took 5-10 times as long (Node, fern: a p99 of 92-142 ms over
// the first 250 ticks after three touches, 15-32 ms after this, on a loaded machine).
const WARM_TICKS = 60;
// The warm-up's touches come as a page's taps do: one a tick, off the pixel grid (a
// fraction makes other number types than a whole pixel, and the engine compiles for the
// types it has seen: a tap of the page's own would throw that code away mid-growth).
const WARM_TOUCHES = [[380.37, 640.61], [200.52, 300.29], [560.73, 1000.18]];

// A frost grown WARM_TICKS from WARM_TOUCHES and thrown away (the worker's, before its hello).
export function warmUp(config) {
  const warm = new LocalRun(config, () => {}, { seed: 1 });
  for (const [x, y] of WARM_TOUCHES) {
    warm.input({ type: "touch", phase: "down", id: 0, x, y });
    warm.tick();
  }
  for (let i = 0; i < WARM_TICKS; i++) warm.tick();
}

export class LocalRun {
  // config: params.json; post(message, transfer): to the page; start: {preset, look, backdrop, seed}.
  constructor(config, post, start = {}) {
    this.config = config;
    this.post = post;
    this.screen = config.hello.screen;
    const preset = this.runs(start.preset) ? start.preset : config.default_preset;
    this.chosen = preset;  // the preset's name (the menu's)
    this.params = { ...config.presets[preset] };
    if (config.hello.looks.includes(start.look)) this.params.look = start.look;
    this.shown = config.hello.backdrops.includes(start.backdrop) ? start.backdrop : config.hello.backdrops[0];
    this.seed = Number.isInteger(start.seed) ? start.seed : Math.floor(Math.random() * 2 ** 31);
    this.paused = false;
    this.weather = null;  // the page's last weather: {temperature, supply} (null temperature: a thaw)
    this.steps = 0;      // ticks stepped in all (the session's steps)
    this.timeline = 0;   // ticks of this timeline (a rebuild starts one at 0)
    this.again = [];     // what a rebuild plants again, [[tick, kind, x, y, r], ...]
    this.fingers = new Fingers(this.screen, (kind) => kind === "melt"
      ? config.melt_spacing * config.hello.melt_radius : config.drag_spacing_hc * this.params.hc);
    this.record = new SessionRecord(config.session, this.seed, this.params, this.screen);
    this.build();
  }

  // Whether the phone grows preset `name` (params.json's server_only: none now).
  runs(name) {
    return name in this.config.presets && !this.config.server_only.includes(name);
  }

  build() {
    const [width, height] = this.screen;
    this.frost = new Frost(this.params, { width, height, seed: this.seed });
    this.applyWeather();  // (a rebuild keeps it: the weather is the night's, not the frost's)
    this.geometry = this.drawn();
    this.encoder = new Encoder(...this.config.hello.grid);
  }

  // The geometry of this.params' look (its deltas' heights views: each is encoded at once).
  drawn() {
    const [width, height] = this.screen;
    return new FrostGeometry(this.params, { width, height, views: true });
  }

  state() {
    return { paused: this.paused, preset: this.chosen, look: this.params.look,
      backdrop: this.shown, backdrops: this.config.hello.backdrops, tick: this.frost.tick };
  }

  // The hello a page starts from, then the whole frost.
  /** What the page's stats show of the frost: its tick, the crystals alive (melted ones
   * are not), the touches dropped, and whether it is paused. */
  stats() {
    return { tick: this.frost.tick, crystals: this.frost.alive, dropped: this.fingers.dropped,
      paused: this.paused };
  }

  hello() {
    this.text({ type: "hello", ...this.config.hello, ...this.state(), local: true,
      server_only: this.config.server_only });
    this.snapshot();
  }

  snapshot() {
    const d = this.geometry.redraw(this.frost);
    this.encoder.delta(d, true);  // (the grid as the snapshot leaves the page's)
    for (const part of this.encoder.snapshot(this.frost.tick, d.features, d.look, d.heightScale)) {
      this.post(part, [part]);
    }
  }

  text(message) {
    this.post(JSON.stringify(message));
  }

  notice(text) {
    this.text({ type: "notice", text });
  }

  // One of the page's messages (as it sends frost serve), already parsed.
  input(m) {
    if (!m || typeof m !== "object") return;
    if (m.type === "touch" || m.type === "melt") this.fingers.take(m);
    else if (TEXT_KINDS.includes(m.type)) this[m.type](m.name);
    else if (m.type === "ping") this.text({ type: "pong", t: m.t, tick: this.frost.tick });
    else if (m.type === "key") this.key(String(m.name));
    else if (m.type === "weather") this.setWeather(m.temperature, m.supply);
  }

  // The page's weather (its glass model's answer): the window's frost grows as if its
  // `temperature` (degrees C below freezing, > 0) were this, its pane's water `supply`
  // times as much (default 1); null temperature: a thaw, the ice's tips melting a layer
  // every THAW_TICKS ticks. Anything else is refused in one notice and changes nothing.
  setWeather(temperature, supply = 1) {
    const thaw = temperature === null;
    const ok = (thaw || (Number.isFinite(temperature) && temperature > 0 && temperature <= 1000))
      && Number.isFinite(supply) && supply >= 0 && supply <= 1000;
    if (!ok) return this.notice(`weather ${String(temperature).slice(0, 16)}, ${String(supply).slice(0, 16)} refused`);
    this.weather = { temperature, supply };
    this.applyWeather();
  }

  applyWeather() {
    if (this.weather) this.frost.setWeather(this.weather.temperature, this.weather.supply);
  }

  // One tick: the waiting touches and melts (at most TOUCHES_PER_TICK), then a step.
  tick() {
    if (this.paused) return false;
    for (const [kind, x, y, r] of this.due()) this.apply(kind, x, y, r);
    this.thaw();
    const added = this.frost.step();
    this.steps += 1;
    this.timeline += 1;
    this.send(this.geometry.update(this.frost, added));
    return true;
  }

  // What applies before this tick: a rebuild's touches and melts due now, the page's waiting ones.
  due() {
    const out = [];
    while (this.again.length && this.again[0][0] <= this.timeline) out.push(this.again.shift().slice(1));
    for (const [kind, x, y] of this.fingers.next(TOUCHES_PER_TICK)) {
      const r = this.config.hello.melt_radius;
      out.push([kind, x, y, r]);
      const event = kind === "melt" ? { kind, tick: this.timeline, x, y, r } : { kind, tick: this.timeline, x, y };
      this.record.add(event);
    }
    return out;
  }

  apply(kind, x, y, r) {
    if (kind === "touch") {
      this.frost.touch(x, y);
    } else if (this.frost.melt(x, y, r).length) {  // (what it took: frost.melted)
      this.send(this.geometry.melt(this.frost, this.frost.melted));
    }
  }

  // In a thaw, every THAW_TICKS ticks the ice's thin edges melt (sim/io/timeline.py _thaw).
  thaw() {
    if (this.frost.thawing && this.frost.tick % THAW_TICKS === 0 && this.frost.meltTips().length) {
      this.send(this.geometry.melt(this.frost, this.frost.melted));
    }
  }

  send(delta) {
    const message = this.encoder.delta(delta);
    this.post(message, [message]);
  }

  // The menu's choices, as frost serve's controls apply them.
  preset(name) {
    if (!this.runs(name)) {
      this.notice(name in this.config.presets ? `${name}: needs frost serve (a computer grows it)`
        : `${String(name).slice(0, 16)} refused: one of ${Object.keys(this.config.presets).join(", ")}`);
      return this.text({ type: "state", ...this.state() });
    }
    this.chosen = name;
    this.rebuild({ ...this.config.presets[name], grid_spacing: this.params.grid_spacing });
  }

  look(name) {
    if (!this.config.hello.looks.includes(name)) return this.notice(`look ${String(name).slice(0, 16)} refused`);
    if (name === this.params.look) return;
    this.params = { ...this.params, look: name };
    this.record.add({ kind: "params", tick: this.timeline, params: { ...this.params } });
    // A look is drawn anew, not grown anew (as frost serve): the same frost, its new geometry.
    this.geometry = this.drawn();
    this.text({ type: "state", ...this.state() });
    this.snapshot();
  }

  backdrop(name) {
    if (!this.config.hello.backdrops.includes(name)) {
      return this.notice(`backdrop ${String(name).slice(0, 40)} refused: one of ${this.config.hello.backdrops.join(", ")}`);
    }
    this.shown = name;
    this.record.add({ kind: "backdrop", tick: this.timeline, name });
    this.text({ type: "state", ...this.state() });
  }

  // A key of the window's: its pause, step and clear (params.json's keys), as frost serve's.
  key(name) {
    const command = Object.hasOwn(this.config.keys, name) ? this.config.keys[name] : null;
    if (command) this[command]();
    else this.notice(`key ${name.slice(0, 16)}: not on this phone`);
  }

  // One tick while paused.
  step() {
    if (!this.paused) return;
    this.paused = false;
    this.tick();
    this.paused = true;
  }

  pause() {
    this.paused = !this.paused;
    this.text({ type: "state", ...this.state() });
  }

  // Clear: the pane, its water and the touches waiting (window.frost.local.clear() too).
  clear() {
    this.fingers.clear();
    this.again = this.record.rebuild(this.timeline);
    this.frost.clear();
    this.timeline = 0;
    this.send(this.geometry.reset());
  }

  // New parameters: a new frost, the touches so far planted again at their own pace.
  rebuild(params) {
    this.params = params;
    this.again = this.record.rebuild(this.timeline, params);
    this.timeline = 0;
    const tick = this.frost.tick;
    this.build();
    this.text({ type: "state", ...this.state(), tick });
    this.send(this.geometry.reset());
  }

  // The session file's JSON, and the screenshot's keys (as GET /meta answers them).
  session() {
    return this.record.json(this.steps, { ...this.config.hello.view, background: this.shown });
  }

  meta() {
    return { parameters: this.params, seed: this.seed,
      touches: this.record.touches.map((t) => [t.x, t.y]), source: "phone" };
  }
}
