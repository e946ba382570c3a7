// The page's glass model (app/web/glass.js) against sim/weather/glass.py, asked through the
// checkout's Python: for a grid of readings outside (-40 to +15 C, exact halves and the
// turns at 0 C and at the frost point included) on single and double glazing, in a stated,
// a dry and a damp room, the same glass temperature, state, preset temperature and supply,
// and the same line for the status line.

import assert from 'node:assert/strict';
import test from 'node:test';

import { describe, frostOf } from '../../app/web/glass.js';
import { python } from './simoracle.mjs';

const OUTSIDE = [-40, -25, -13.25, -10, -6.6, -6.5, -6.4, -2.5, -0.05, 0, 0.25, 0.35, 2.5, 6, 15];
const GLASSES = [];
for (const glazing of ['single', 'double']) {
  for (const [room_c, room_humidity] of [[20, 40], [20, 10], [22.5, 60], [0, 100], [40, 1]]) {
    GLASSES.push({ glazing, room_c, room_humidity });
  }
}

function reading(t, humidity) {
  return { place: '59.3,18.1', latitude: 59.3, longitude: 18.1, temperature_c: t, humidity_pct: humidity,
    dew_point_c: t - 2.75, weather_code: 71, is_day: false, time: '2026-01-10T23:00' };
}

test('the glass, its state, the preset temperature, the supply and the line are sim/weather\'s', () => {
  const cases = [];
  for (const glass of GLASSES) {
    OUTSIDE.forEach((t, i) => cases.push({ reading: reading(t, [80.5, 81.5, 79, 100][i % 4]), glass }));
  }
  const want = python({ kind: 'glass', readings: cases });
  assert.equal(want.length, cases.length);
  const states = new Set();
  cases.forEach((c, i) => {
    const got = frostOf(c.reading.temperature_c, c.glass), at = JSON.stringify(c);
    assert.ok(Math.abs(got.glass - want[i].glass) <= 1e-12, `glass ${got.glass} vs ${want[i].glass} at ${at}`);
    assert.equal(got.state, want[i].state, at);
    if (want[i].temperature === null) assert.equal(got.temperature, null, at);
    else assert.ok(Math.abs(got.temperature - want[i].temperature) <= 1e-12, at);
    assert.ok(Math.abs(got.supply - want[i].supply) <= 1e-12, at);
    assert.equal(describe(c.reading, c.glass), want[i].line.replace(/^weather: /, ''), at);
    states.add(got.state);
  });
  assert.deepEqual([...states].sort(), ['fades', 'grows', 'melts']);  // (every state met)
});

test('-25 C on the stated window grows as temperature 13.9; +6 C thaws', () => {
  const cold = frostOf(-25), warm = frostOf(6);
  assert.equal(cold.state, 'grows');
  assert.ok(Math.abs(cold.glass + 13.93) < 0.01 && Math.abs(cold.temperature - 13.93) < 0.01, `${cold.glass}`);
  assert.equal(cold.supply, 1);
  assert.equal(warm.state, 'melts');
  assert.equal(warm.temperature, null);
  assert.throws(() => frostOf(NaN), /must be a number/);
});
