// "Weather where I am" (docs/phone.md, The weather where you are): on a tap the page asks
// the browser for the phone's place (the Geolocation API, which browsers give to a secure
// context only: the HTTPS page), rounds it to 0.1 degree (about 10 km) and sends that alone
// to the server (POST weather, with the token; the browser adds the page's Origin), which
// moves its weather feed there: every page then shows that place's reading. A plain-HTTP
// page, a refused permission or a refusal of the server says why in the status line.

export const STEP = 0.1;  // degrees: no closer a place leaves the phone
const ASK = { enableHighAccuracy: false, timeout: 30000, maximumAge: 10 * 60 * 1000 };

// `degrees` to STEP, as the server rounds it (app/serve/weather.py).
export function rounded(degrees) {
  return Math.round(degrees / STEP) / 10 + 0;  // (+ 0: -0 is 0)
}

// The status line's words on the server's weather (the hello's and the state's `weather`):
// its place and its reading; "" for none.
export function weatherText(weather) {
  return weather ? `${weather.place}: ${weather.reading}` : "";
}

// Why this page cannot ask for its place, or null.
export function placeProblem(win = globalThis) {
  if (!win.isSecureContext) return "Weather where I am needs the HTTPS page (this one is plain HTTP)";
  if (!win.navigator.geolocation) return "this browser cannot tell where the phone is";
  return null;
}

// What a GeolocationPositionError means, in one line.
export function positionProblem(error) {
  if (error.code === 1) return "the browser refused the location: allow it for this page in its settings";
  if (error.code === 3) return "the phone did not find where it is in time: try again";
  return `the phone cannot tell where it is (${error.message || "no position"})`;
}

// The menu's button; `say(text)` the status line (it stays), `notice(text)` a line that goes
// after a while. `last` says how the last tap went (the tests read it): {status, latitude,
// longitude} or {status, error} (`status` 0 where no request was sent).
export class WeatherHere {
  constructor(panel, query, say, notice, win = globalThis) {
    Object.assign(this, { query, say, notice, win });
    this.last = null;
    this.asking = false;
    this.button = Object.assign(win.document.createElement("button"), {
      id: "weather-here", textContent: "Weather where I am",
    });
    this.button.addEventListener("click", () => this.ask().catch((err) => this.failed(0, err.message)));
    const photo = panel.querySelector("#photo-file") || panel.querySelector("#backdrop");
    const after = photo ? photo.closest("label") || photo : null;
    if (after) after.after(this.button);
    else panel.append(this.button);
  }

  async ask() {
    const problem = placeProblem(this.win);
    if (problem) return this.failed(0, problem);
    // The phone's own frost: its weather is asked from the page (weather_local.js).
    if (this.win.frost && this.win.frost.alone && this.win.frost.alone.running) {
      const { startWeather } = await import("./weather_local.js");
      return startWeather("here");
    }
    if (this.asking) return this.notice("the weather here is being asked for already");
    this.asking = true;
    this.button.disabled = true;
    try {
      this.say("finding where the phone is…");
      let position;
      try {
        position = await new Promise((resolve, reject) =>
          this.win.navigator.geolocation.getCurrentPosition(resolve, reject, ASK));
      } catch (err) {
        return this.failed(0, positionProblem(err));
      }
      const place = { latitude: rounded(position.coords.latitude), longitude: rounded(position.coords.longitude) };
      const response = await fetch(`weather${this.query}`, {
        method: "POST", body: JSON.stringify(place), headers: { "Content-Type": "application/json" },
      });
      let answer = {};
      try {
        answer = await response.json();
      } catch { /* not the server's JSON (a proxy's page) */ }
      if (!response.ok) return this.failed(response.status, answer.error || `HTTP ${response.status}`);
      this.last = { status: response.status, latitude: answer.latitude, longitude: answer.longitude };
      this.notice(`asking the weather at ${answer.latitude}, ${answer.longitude}…`);
    } finally {
      this.asking = false;
      this.button.disabled = false;
    }
  }

  failed(status, text) {
    this.last = { status, error: text };
    this.say("");
    this.notice(status ? `weather refused: ${text}` : text);
  }
}
