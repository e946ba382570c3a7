// The page's geometry (app/web/local/geometry.js, ridges.js, heightgrid.js) and its
// encoding (encode.js) held to sim/'s: Python grows a real FrostSim (the fern preset in
// the glass look, b-2 in the paper's), melts it and redraws it (tests/support/
// geometry_oracle.py), and writes what the geometry read at each step with its
// FrostGeometry's delta and the Encoder's bytes; here the page's geometry reads the same
// arrays and must give the same deltas and the same bytes.

import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { test } from "node:test";
import { fileURLToPath } from "node:url";

import { Encoder } from "../../app/web/local/encode.js";
import { FrostGeometry } from "../../app/web/local/geometry.js";

const ROOT = process.env.FROST_ROOT || path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
const PYTHON = process.env.FROST_PYTHON || path.join(ROOT, ".venv/bin/python");

// Python's scenarios (run once for every test here).
function oracle() {
  const dir = mkdtempSync(path.join(tmpdir(), "frost-geometry-"));
  try {
    const out = path.join(dir, "oracle.json");
    execFileSync(PYTHON, [path.join(ROOT, "tests/support/geometry_oracle.py"), out], { stdio: "inherit" });
    return JSON.parse(readFileSync(out, "utf-8"));
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

const TYPES = { "<f4": Float32Array, "<i4": Int32Array, "|b1": Uint8Array, "<f2": Uint16Array };

// A numpy array packed by the oracle, as the typed array of its dtype.
function unpack({ dtype, b64 }) {
  const bytes = Buffer.from(b64, "base64");
  const Type = TYPES[dtype];
  assert.ok(Type, `unknown dtype ${dtype}`);
  const copy = new Uint8Array(bytes.length);
  copy.set(bytes);
  return new Type(copy.buffer);
}

// A stand-in for the page's Frost: the arrays Python's geometry read, and its
// segments_near answers in the order it asked (a call for another box fails).
function frostOf(state, near) {
  const a = Object.fromEntries(Object.entries(state).map(([k, v]) => [k, v.b64 ? unpack(v) : v]));
  const calls = near.map((call) => ({ ...call, ids: unpack(call.ids) }));
  return {
    tick: a.tick, width: a.width, height: a.height, count: a.parents.length,
    crystals: a.crystals, parents: a.parents, crystalAlive: a.crystal_alive,
    upsampled: a.upsampled, upsampledLink: a.upsampled_link, upsampledAlive: a.upsampled_alive,
    upsampledCount: a.upsampled_link.length, segments: a.segments, segmentsLink: a.segments_link,
    segmentsAlive: a.segments_alive, segmentCount: a.segments_link.length,
    segmentsNear(box, reach) {
      const call = calls.shift();
      assert.ok(call, `segmentsNear(${box}, ${reach}) asked once too often`);
      assert.deepEqual([...box, reach], [...call.box, call.reach], "segmentsNear's box");
      return call.ids;
    },
  };
}

// Float32 values equal within float32 rounding (libm's hypot and V8's may differ by an ulp).
function close(actual, expected, what) {
  assert.equal(actual.length, expected.length, `${what}: length`);
  for (let i = 0; i < expected.length; i++) {
    const tol = 2e-7 * Math.max(1, Math.abs(expected[i]));
    if (!(Math.abs(actual[i] - expected[i]) <= tol)) {
      assert.fail(`${what}[${i}] (of ${expected.length}): ${actual[i]}, sim/ ${expected[i]}`);
    }
  }
}

function sameDelta(js, py, what) {
  assert.equal(js.tick, py.tick, `${what}: tick`);
  assert.deepEqual(js.rows, py.rows, `${what}: dirty rows`);
  close(js.heights, unpack(py.heights), `${what}: heights`);
  close(js.features, unpack(py.features), `${what}: features`);
  assert.equal(js.reset, py.reset, `${what}: reset`);
  assert.deepEqual(js.clearBox, py.clear_box, `${what}: clear box`);
  assert.equal(js.look, py.look, `${what}: look`);
  assert.equal(js.heightScale, py.height_scale, `${what}: height scale`);
}

function sameBytes(buffer, b64, what) {
  const want = Buffer.from(b64, "base64"), got = Buffer.from(buffer);
  if (!got.equals(want)) {
    const at = got.findIndex((b, i) => b !== want[i]);
    assert.fail(`${what}: ${got.length} bytes, sim/'s ${want.length}; first difference at byte ${at}`);
  }
}

// Every event of a scenario replayed through the page's geometry and encoder.
function replay(scenario, check) {
  const geometry = new FrostGeometry(scenario.params);
  const encoder = new Encoder(...scenario.grid);
  let last = null;
  for (const [i, event] of scenario.events.entries()) {
    const frost = frostOf(event.state, event.near);
    const what = `${scenario.name} event ${i} (${event.kind}, tick ${event.state.tick})`;
    let delta;
    if (event.kind === "reset") delta = geometry.reset();
    else if (event.kind === "update") delta = geometry.update(frost, { start: event.added[0], end: event.added[1] });
    else if (event.kind === "melt") {
      const melted = Object.fromEntries(Object.entries(event.melted).map(([k, v]) => [k, unpack(v)]));
      delta = geometry.melt(frost, melted);
    } else delta = geometry.redraw(frost);
    check(delta, event, encoder, what);
    last = delta;
  }
  return { encoder, last };
}

const SCENARIOS = oracle();

for (const scenario of SCENARIOS) {
  test(`${scenario.name}: every delta as sim/'s FrostGeometry gives it`, () => {
    const kinds = new Set();
    replay(scenario, (delta, event, _encoder, what) => {
      sameDelta(delta, event.delta, what);
      kinds.add(event.kind);
      if (event.kind === "melt") assert.ok(delta.clearBox, `${what}: a melt without its box`);
    });
    assert.deepEqual([...kinds].sort(), ["melt", "redraw", "reset", "update"]);
  });

  test(`${scenario.name}: every message byte for byte as app/serve/protocol.py's`, () => {
    const { encoder, last } = replay(scenario, (delta, event, encoder, what) => {
      sameBytes(encoder.delta(delta), event.bytes, what);
    });
    const { tick, parts, part_vertices: size } = scenario.snapshot;
    const js = encoder.snapshot(tick, last.features, last.look, last.heightScale, null, size);
    assert.ok(parts.length > 1, "the oracle's snapshot comes in one part: make its parts smaller");
    assert.equal(js.length, parts.length, "snapshot parts");
    js.forEach((part, i) => sameBytes(part, parts[i], `${scenario.name} snapshot part ${i}`));
    // After them, a tick with no change, a reset alone, then the redraw's heights again.
    sameBytes(encoder.bare(tick + 1, false), scenario.bare[0], `${scenario.name} a bare tick`);
    sameBytes(encoder.bare(tick + 2, true), scenario.bare[1], `${scenario.name} a bare reset`);
    sameBytes(encoder.delta({ ...last, reset: false }), scenario.bare[2], `${scenario.name} after a bare reset`);
  });
}
