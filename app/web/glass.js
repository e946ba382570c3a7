// The glass between the room and the night, and what it does to the frost: sim/weather/
// glass.py ported (docs/method.md, section 12), its constants from local/shared.js. The
// inner surface sits at room - U R_si (room - outside); frost grows on glass below 0 C
// and below the room's frost point (Magnus over ice), with the window preset's
// `temperature` set to the glass's undercooling; glass at or above 0 C thaws ("melts"), and
// glass below 0 C but above the frost point (a dry room) fades. Held to the Python one by
// tests/web/glass.test.mjs.

import {
  E0, ICE, LEAST_UNDERCOOLING, MOST_UNDERCOOLING, R_SI, ROOM_C, ROOM_HUMIDITY, SUPPLY_RANGE,
  U_VALUES, WATER,
} from "./local/shared.js";

// The stated window: old single glazing, a room of 20 C at 40 %.
export const GLASS = Object.freeze({ glazing: "single", room_c: ROOM_C, room_humidity: ROOM_HUMIDITY });

// The inner surface's temperature, degrees C.
export function glassTemperature(outside, roomC = ROOM_C, glazing = "single") {
  const u = U_VALUES[glazing];
  if (u === undefined) throw new Error(`glazing ${JSON.stringify(glazing)} must be one of ${Object.keys(U_VALUES).join(", ")}`);
  return roomC - u * R_SI * (roomC - outside);
}

// Saturation vapour pressure at `t` C, hPa (Magnus).
export function saturation(t, [a, b] = WATER) {
  return E0 * Math.exp(a * t / (b + t));
}

function inverse(e, [a, b]) {
  const x = Math.log(e / E0);
  return b * x / (a - x);
}

// Where the air's vapour saturates over ice, degrees C.
export function frostPoint(t, humidity) {
  return inverse(humidity / 100 * saturation(t), ICE);
}

const clamp = (v, lo, hi) => Math.min(Math.max(v, lo), hi);

// What `outside` C does to the frost on `glass`: {glass, state: "grows" | "melts" |
// "fades", temperature (the preset's, while it grows; else null), supply}.
export function frostOf(outside, glass = GLASS) {
  if (!Number.isFinite(outside)) throw new Error(`the temperature outside must be a number, not ${outside}`);
  const g = glassTemperature(outside, glass.room_c, glass.glazing);
  const onset = Math.min(0, frostPoint(glass.room_c, glass.room_humidity));
  const vapour = glass.room_humidity * saturation(glass.room_c);
  const stated = ROOM_HUMIDITY * saturation(ROOM_C);
  const supply = clamp(vapour / stated, SUPPLY_RANGE[0], SUPPLY_RANGE[1]);
  if (g >= 0) return { glass: g, state: "melts", temperature: null, supply };
  if (g >= onset) return { glass: g, state: "fades", temperature: null, supply };
  return { glass: g, state: "grows", temperature: clamp(onset - g, LEAST_UNDERCOOLING, MOST_UNDERCOOLING), supply };
}

export const WORDS = { grows: "frost grows", melts: "frost melts", fades: "frost fades (the room is dry)" };

// `value` to `digits` decimals as Python's format does: toFixed rounds a tie (an exact
// half) away from zero, Python to even; anything else both round to the nearest.
export function fixed(value, digits) {
  const text = value.toFixed(digits);
  const exact = Math.abs(value).toFixed(100);  // (every digit of a double this size)
  const cut = exact.indexOf(".") + 1 + digits;
  if (!/^50*$/.test(exact.slice(cut)) || Number(exact[cut - 1 - (digits ? 0 : 1)]) % 2) return text;
  const kept = exact.slice(0, digits ? cut : cut - 1);  // (the tie's even neighbour, towards 0)
  return (value < 0 ? "-" : "") + kept;
}

// `value` to `digits` decimals, never "-0".
function signed(value, digits) {
  const text = fixed(value, digits);
  return Number(text) === 0 ? text.replace(/^-/, "") : text;
}

// The glass's temperature in words, never read across 0 C from where it is (glass.py's
// glass_words).
export function glassWords(g) {
  if (g === 0) return "0";
  for (const digits of [0, 1]) {
    const text = signed(g, digits);
    if (Number(text) !== 0) return text;
  }
  return g < 0 ? "just below 0" : "just above 0";
}

// A reading's line, as frost serve's (glass.py's describe without "weather: "):
// "-25.0 C, 80 %, dew point -27.6 C at 23:00: glass -14 C, frost grows".
export function describe(reading, glass = GLASS) {
  const frost = frostOf(reading.temperature_c, glass);
  return `${signed(reading.temperature_c, 1)} C, ${fixed(reading.humidity_pct, 0)} %, ` +
    `dew point ${signed(reading.dew_point_c, 1)} C at ${reading.time.slice(11, 16)}: ` +
    `glass ${glassWords(frost.glass)} C, ${WORDS[frost.state]}`;
}
