// The weather on the phone itself (docs/phone.md, The weather on this phone): with no
// server, "Weather where I am" (or a ?weather= link) asks the forecast API from the page:
// the place, the phone's own rounded to 0.1 degree or one given, goes to that API and
// nowhere else. Each reading (at once, then every READ_MS while the page is open) goes
// through the glass model (glass.js, sim/weather/glass.py's) to the phone's frost, as
// {type: "weather", temperature, supply} to its worker (temperature null: a thaw); the
// status line shows it as frost serve's pages do, `window.frost.local.weather` holds
// {outside, glass, state}, and the lock screen's clock box the temperature. The place and
// the last reading are kept on the phone (localStorage, with their time) and used when the
// API cannot be reached. Every failure is one line in the status line.

import { describe, frostOf } from "./glass.js";
import { placeProblem, positionProblem, rounded } from "./weather.js";

export const READ_MS = 15 * 60 * 1000;  // between two readings while the page is open
export const KEPT = "frost-weather";  // localStorage: {place, reading, at} (at: ms since the epoch)
export const FORECAST_API = "https://api.open-meteo.com";
export const GEOCODING_API = "https://geocoding-api.open-meteo.com";
const TIMEOUT_MS = 5000;  // one request's limit (app/weather/client.py's)
const MOST_BYTES = 1 << 20;  // a reply longer than this is not the API's
// The current values asked for (app/weather/client.py's CURRENT); the first five required.
const CURRENT = ["temperature_2m", "relative_humidity_2m", "dew_point_2m", "weather_code", "is_day",
  "wind_speed_10m", "apparent_temperature", "cloud_cover"];
const ASK = { enableHighAccuracy: false, timeout: 30000, maximumAge: 10 * 60 * 1000 };

// The place `spec` names: "here" (the phone's, asked for), or {lat, lon} (also
// {latitude, longitude}); an Error of one line when it is neither.
export function placeOf(spec) {
  if (spec === "here") return "here";
  const lat = spec && (spec.lat ?? spec.latitude), lon = spec && (spec.lon ?? spec.longitude);
  if (typeof lat !== "number" || typeof lon !== "number" || !(Math.abs(lat) <= 90) || !(Math.abs(lon) <= 180)) {
    throw new Error(`weather: a place is "here" or a latitude in [-90, 90] and a longitude in [-180, 180], not ${short(spec)}`);
  }
  return { latitude: rounded(lat), longitude: rounded(lon) };
}

function short(value) {
  let text;
  try {
    text = JSON.stringify(value) ?? String(value);
  } catch {
    text = String(value);
  }
  return text.length <= 60 ? text : `${text.slice(0, 57)}...`;
}

// A place's name in the status line: "59.3, 18.1".
export function placeName(place) {
  return `${place.latitude.toFixed(1)}, ${place.longitude.toFixed(1)}`;
}

function host(url) {
  try {
    return new URL(url).host || url;
  } catch {
    return url;
  }
}

const number = (v) => typeof v === "number" && Number.isFinite(v);

// The forecast's JSON `data` as a reading at `place` (sim/weather/reading.py's fields), or
// an Error naming what is wrong, in one line.
export function readingOf(data, place, api) {
  const now = data && typeof data === "object" ? data.current : null;
  if (!now || typeof now !== "object") throw new Error(`${host(api)} answered JSON without 'current': ${short(data)}`);
  const missing = ["time", ...CURRENT.slice(0, 5)].filter((k) => now[k] === null || now[k] === undefined);
  if (missing.length) throw new Error(`${host(api)}'s reading lacks ${missing.join(", ")}`);
  const bounds = { temperature_2m: [-100, 70], relative_humidity_2m: [0, 100], dew_point_2m: [-120, 70] };
  for (const [k, [lo, hi]] of Object.entries(bounds)) {
    if (!number(now[k]) || now[k] < lo || now[k] > hi) throw new Error(`${host(api)}'s ${k} is not a reading: ${short(now[k])}`);
  }
  if (typeof now.time !== "string" || !/^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}$/.test(now.time)) {
    throw new Error(`${host(api)}'s time is not YYYY-MM-DDTHH:MM: ${short(now.time)}`);
  }
  return { place: placeName(place), latitude: place.latitude, longitude: place.longitude,
    temperature_c: now.temperature_2m, humidity_pct: now.relative_humidity_2m, dew_point_c: now.dew_point_2m,
    weather_code: now.weather_code, is_day: now.is_day === 1, time: now.time };
}

// The forecast API's current conditions at `place`; an Error of one line for any failure.
export async function ask(api, place, fetcher = fetch) {
  const url = `${api.replace(/\/+$/, "")}/v1/forecast?latitude=${place.latitude.toFixed(1)}` +
    `&longitude=${place.longitude.toFixed(1)}&current=${CURRENT.join(",")}&timezone=auto`;
  const abort = new AbortController();
  const timer = setTimeout(() => abort.abort(), TIMEOUT_MS);
  let reply, body;
  try {
    reply = await fetcher(url, { signal: abort.signal, cache: "no-store", credentials: "omit", referrerPolicy: "no-referrer" });
    if (reply.status === 429) throw new Error(`${host(api)} refused: too many requests (HTTP 429)`);
    if (!reply.ok) throw new Error(`${host(api)} answered HTTP ${reply.status} ${reply.statusText || ""}`.trimEnd());
    body = await reply.text();
  } catch (err) {
    if (err.name === "AbortError") throw new Error(`${host(api)} did not answer within ${TIMEOUT_MS / 1000} s`);
    if (err instanceof TypeError) throw new Error(`cannot reach ${host(api)}`);  // (offline, refused, no CORS)
    throw err;
  } finally {
    clearTimeout(timer);
  }
  if (body.length > MOST_BYTES) throw new Error(`${host(api)} answered more than ${MOST_BYTES} bytes: too large for the API's JSON`);
  let data;
  try {
    data = JSON.parse(body);
  } catch {
    throw new Error(`${host(api)} answered something that is not JSON: ${short(body)}`);
  }
  return readingOf(data, place, api);
}

// The place and the last reading kept on the phone, or null.
export function kept(storage = globalThis.localStorage) {
  try {
    const k = JSON.parse(storage.getItem(KEPT));
    return k && k.place && number(k.place.latitude) && number(k.place.longitude) ? k : null;
  } catch {
    return null;
  }
}

function keep(value, storage = globalThis.localStorage) {
  try {
    storage.setItem(KEPT, JSON.stringify(value));
  } catch { /* (storage full or refused: the weather goes on, unkept) */ }
}

// When a kept reading was read, in words: "23:00" of the API's local time, and its age.
function age(k) {
  const minutes = Math.round((Date.now() - k.at) / 60000);
  const ago = minutes < 90 ? `${minutes} min ago` : minutes < 48 * 60 ? `${Math.round(minutes / 60)} h ago` : `${Math.round(minutes / 1440)} days ago`;
  return `${k.reading.time.slice(11, 16)}, read ${ago}`;
}

// The phone's weather: one a page. `page`, window.frost (its `alone` runs the worker, its
// status line says what happens).
export class LocalWeather {
  constructor(page, { status, apis = () => ({}), storage = globalThis.localStorage, win = globalThis } = {}) {
    Object.assign(this, { page, status, apis, storage, win });
    this.place = null;  // {latitude, longitude} asked for
    this.reading = null;  // the reading applied
    this.message = null;  // the worker's last weather message
    this.now = null;  // {outside, glass, state}
    this.timer = 0;
    this.asked = 0;  // readings asked (the tests read it)
    this.seq = 0;
  }

  // The forecast API's address: the site's (window.frost.site, or the static site's
  // params.json, `frost web --weather-api`), else Open-Meteo's.
  async api() {
    const site = this.apis() || {};
    if (site.weather_api) return site.weather_api;
    if (this.config === undefined) {
      this.config = null;
      try {
        const token = new URLSearchParams(this.win.location.search).get("token");
        const r = await fetch(new URL(`local/params.json${token ? `?token=${encodeURIComponent(token)}` : ""}`, import.meta.url));
        if (r.ok) this.config = await r.json();
      } catch { /* (none: Open-Meteo's) */ }
    }
    return (this.config && this.config.weather_api) || FORECAST_API;
  }

  // Follow `spec`'s weather ("here" or {lat, lon}) from now on; a promise of the first
  // reading's outcome (true: a reading applied, fresh or kept).
  async start(spec) {
    let place;
    try {
      place = placeOf(spec);
    } catch (err) {
      return this.fail(err.message);
    }
    const seq = ++this.seq;
    clearInterval(this.timer);
    if (place === "here") {
      const problem = placeProblem(this.win);
      if (problem) return this.fail(problem);
      this.say("finding where the phone is…");
      try {
        const p = await new Promise((resolve, reject) =>
          this.win.navigator.geolocation.getCurrentPosition(resolve, reject, ASK));
        place = { latitude: rounded(p.coords.latitude), longitude: rounded(p.coords.longitude) };
      } catch (err) {
        return seq === this.seq && this.fail(positionProblem(err));
      }
      if (seq !== this.seq) return false;
    }
    this.place = place;
    this.timer = setInterval(() => this.read(), READ_MS);
    return this.read();
  }

  stop() {
    this.seq++;
    clearInterval(this.timer);
    this.place = null;
  }

  // A reading of the place now: applied and kept, or (the API failing) the line says why
  // and the kept reading of the same place, if any, is applied.
  async read() {
    const place = this.place, seq = this.seq;
    if (!place) return false;
    this.asked++;
    this.say(`asking the weather at ${placeName(place)}…`);
    let reading;
    try {
      reading = await ask(await this.api(), place);
    } catch (err) {
      if (seq !== this.seq) return false;
      const k = kept(this.storage);
      const same = k && k.reading && k.place.latitude === place.latitude && k.place.longitude === place.longitude;
      if (same) {
        this.apply(k.reading);
        this.say(`weather: ${err.message}: the frost goes on with the reading of ${age(k)} (kept on this phone)`);
        return true;
      }
      this.fail(`weather: ${err.message}`);
      return false;
    }
    if (seq !== this.seq) return false;
    keep({ place, reading, at: Date.now() }, this.storage);
    this.apply(reading);
    this.say("");
    return true;
  }

  // `reading` to the frost, the status line, frost.local.weather and the lock screen.
  apply(reading) {
    const f = frostOf(reading.temperature_c);
    this.reading = reading;
    this.now = { outside: reading.temperature_c, glass: f.glass, state: f.state };
    this.message = { type: "weather", temperature: f.state === "grows" ? f.temperature : null, supply: f.supply };
    this.page.weatherLocal = this.now;
    if (this.page.local) this.page.local.weather = this.now;
    if (this.page.alone) this.page.alone.send(this.message);
    if (this.status) this.status.setIdle(`${reading.place}: ${describe(reading)}`);
    if (this.page.clock && this.page.clock.outside) this.page.clock.outside(reading.temperature_c);
  }

  say(text) {
    if (this.status) this.status.say(text);
  }

  // A failure: one line, said until something else is.
  fail(text) {
    this.last = text;
    this.say(text.split("\n")[0]);
    return false;
  }
}

// The page's LocalWeather, made on the first call from window.frost.
export function localWeather(page = globalThis.frost) {
  if (!page.localWeather) {
    page.localWeather = new LocalWeather(page, {
      status: page.alone && page.alone.status,
      apis: () => page.site || {},
    });
  }
  return page.localWeather;
}

// Follow the weather of `spec` ("here", or {lat, lon}) on this phone's own frost.
export function startWeather(spec) {
  return localWeather().start(spec);
}
