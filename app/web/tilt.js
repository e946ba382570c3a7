// Tilting the phone moves this page's light, as a lamp fixed in the room lights a pane
// turned under it: the light's direction on the screen turns against the phone's tilt
// (DeviceOrientation's beta and gamma, as the way up on the phone's axes), measured from the pose the phone had when tilt was
// switched on (or the page came back to the front, or the screen turned). The light is the
// page's own: the server's (every other page's) is never touched. Pure maths first (the
// tests check it against hand-worked cases), then the controller.

export const CONE = 45;        // degrees: a tilt further from the rest pose counts as this far
export const MAX_POLAR = 75;   // degrees: the light never lies flatter than this off the screen's normal
export const TAU_MS = 40;      // the low-pass's time constant: 90 % of a step in TAU * ln 10 = 92 ms
export const STEP_DEG = 0.2;   // a filtered tilt this close to the drawn one is not drawn again

const RAD = Math.PI / 180;

// Which way is up, on the phone's own axes (x to its right edge, y to its top, z out of
// its screen), for DeviceOrientation's beta and gamma (degrees): the earth's up turned by
// the inverse of the phone's rotation (Rx(beta) then Ry(gamma)). Continuous in every pose:
// upright (beta 90) gamma is a turn about the vertical, which moves nothing here.
export function upVector(beta, gamma) {
  const b = beta * RAD, g = gamma * RAD;
  return [-Math.cos(b) * Math.sin(g), Math.sin(b), Math.cos(b) * Math.cos(g)];
}

// The tilt from `rest` to (beta, gamma) as a turn of the light on the screen: [right, up]
// degrees (the light moves toward the edge the user lifts, as a lamp fixed in the room
// would), turned by the screen's orientation `angle` (screen.orientation.angle: 90 when the
// phone's top points left) and held within CONE. The turn is the shortest rotation taking
// the rest pose's up to this one's: its part about the phone's y axis moves the light
// right, about its x axis up (a turn about the vertical cannot be sensed, and counts none).
export function screenTilt(beta, gamma, rest, angle = 0) {
  const u = upVector(rest.beta, rest.gamma), v = upVector(beta, gamma);
  const axis = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const sin = Math.hypot(...axis), cos = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
  if (sin < 1e-12) return [0, 0];  // no turn (or half a turn, which has no one direction)
  const turn = Math.min(Math.atan2(sin, cos) / RAD, CONE);
  const dx = turn * axis[1] / sin, dy = -turn * axis[0] / sin;
  const a = angle * RAD;
  const right = dx * Math.cos(a) - dy * Math.sin(a);
  const up = dx * Math.sin(a) + dy * Math.cos(a);
  // (to a nano-degree: a turn of exactly 45 reads 45, not 45.00000000000001)
  return [right, up].map((d) => Math.round(d * 1e9) / 1e9 + 0);
}

// `base` (the light, shader axes: x right, y down, z to the viewer) turned `right` degrees
// toward +x, then `up` degrees toward -y; unit length, no flatter than MAX_POLAR.
export function tiltLight(base, [right, up]) {
  const n = Math.hypot(...base);
  let [x, y, z] = base.map((c) => c / n);
  const a = right * RAD, b = up * RAD;
  [x, z] = [x * Math.cos(a) + z * Math.sin(a), -x * Math.sin(a) + z * Math.cos(a)];
  [y, z] = [y * Math.cos(b) - z * Math.sin(b), y * Math.sin(b) + z * Math.cos(b)];
  const minZ = Math.cos(MAX_POLAR * RAD);
  if (z < minZ) {
    const s = Math.sqrt(1 - minZ * minZ) / (Math.hypot(x, y) || 1);
    [x, y, z] = [x * s, y * s, minZ];
  }
  return [x, y, z];
}

// A first-order low-pass of a vector: each step moves it 1 - exp(-dt / tau) of the way
// to the target (so the same motion whatever the frame rate).
export class LowPass {
  constructor(tau = TAU_MS) {
    this.tau = tau;
    this.value = null;
  }

  step(target, dt) {
    if (this.value === null) this.value = [...target];
    else {
      const k = 1 - Math.exp(-Math.max(dt, 0) / this.tau);
      this.value = this.value.map((v, i) => v + k * (target[i] - v));
    }
    return this.value;
  }
}

// Why this page can have no tilt, or null: motion events need a secure context (HTTPS or
// this machine), and a browser with them.
export function tiltProblem(win = globalThis) {
  if (!win.isSecureContext) return "tilt needs the HTTPS page (this one is plain HTTP)";
  if (!("DeviceOrientationEvent" in win)) return "this browser has no motion sensors";
  return null;
}

// The controller: listens to deviceorientation while on; `light(base, now)` (once a frame)
// gives the light to draw, and whether it moved enough to draw it again.
export class Tilt {
  constructor(win = globalThis) {
    this.win = win;
    this.on = false;
    this.rest = null;       // {beta, gamma} the tilt is measured from
    this.reading = null;    // the latest {beta, gamma, t}: t when it took that value
    this.filter = new LowPass();
    this.drawn = [0, 0];    // the tilt the light last drawn had
    this.last = null;       // performance.now() of the last light()
    this.onEvent = (e) => this.read(e);
    this.recentre = () => { this.rest = null; };
  }

  // Switch on (asking iOS's permission: call from a user gesture) or off; resolves to
  // null when on, else why not.
  async enable(on) {
    const problem = tiltProblem(this.win);
    if (on && problem) on = false;
    if (on) {
      const ask = this.win.DeviceOrientationEvent.requestPermission;
      if (typeof ask === "function") {
        let answer = "denied";
        try { answer = await ask.call(this.win.DeviceOrientationEvent); } catch { /* not from a gesture */ }
        if (answer !== "granted") {
          this.stop();
          return "the browser refused motion sensors (allow them in its settings)";
        }
      }
      if (!this.on) {
        this.win.addEventListener("deviceorientation", this.onEvent);
        this.win.addEventListener("orientationchange", this.recentre);
        if (this.win.screen && this.win.screen.orientation) this.win.screen.orientation.addEventListener("change", this.recentre);
      }
      this.on = true;
      this.rest = null;
      return null;
    }
    this.stop();
    return on === false && problem ? problem : null;
  }

  stop() {
    if (this.on) {
      this.win.removeEventListener("deviceorientation", this.onEvent);
      this.win.removeEventListener("orientationchange", this.recentre);
      if (this.win.screen && this.win.screen.orientation) this.win.screen.orientation.removeEventListener("change", this.recentre);
    }
    this.on = false;
    this.reading = null;
    this.rest = null;
  }

  read(event) {
    // A browser without the sensor sends nulls (once): no change.
    if (typeof event.beta !== "number" || typeof event.gamma !== "number") return;
    // t: when the reading took this value (a sensor repeats its last one).
    const r = this.reading, same = r && r.beta === event.beta && r.gamma === event.gamma;
    this.reading = { beta: event.beta, gamma: event.gamma, t: same ? r.t : performance.now() };
    if (!this.rest) this.rest = { beta: event.beta, gamma: event.gamma };
  }

  // The tilt ([right, up] degrees) the sensor asks for now.
  target() {
    if (!this.on || !this.reading || !this.rest) return [0, 0];
    const angle = (this.win.screen && this.win.screen.orientation && this.win.screen.orientation.angle) || 0;
    return screenTilt(this.reading.beta, this.reading.gamma, this.rest, angle);
  }

  // {light, changed}: `base` turned by the filtered tilt at `now` (ms); `changed` when it
  // moved STEP_DEG or more from the one drawn last (or came to rest exactly).
  light(base, now = performance.now()) {
    const dt = this.last === null ? 0 : now - this.last;
    this.last = now;
    const target = this.target();
    const t = this.filter.step(target, this.filter.value === null ? Infinity : dt);
    const off = Math.hypot(t[0] - this.drawn[0], t[1] - this.drawn[1]);
    const settled = Math.hypot(t[0] - target[0], t[1] - target[1]) < STEP_DEG / 4;
    const changed = off >= STEP_DEG || (settled && off > 0);
    if (settled) t.splice(0, 2, ...target);
    if (changed) this.drawn = [...t];
    return { light: tiltLight(base, this.drawn), changed };
  }
}
