// The page's own frost end to end: Frost (frost.js) grows the fern from three touches and
// a warm finger melts some, FrostGeometry turns each tick into a delta, the Encoder packs
// it, and the page's own decoder (app/web/protocol.js) reads it back into the grid and
// features the renderer would hold.

import assert from "node:assert/strict";
import { test } from "node:test";

import { Encoder, encodeDelta } from "../../app/web/local/encode.js";
import { Frost } from "../../app/web/local/frost.js";
import { FrostGeometry } from "../../app/web/local/geometry.js";
import { decodeDelta, floatToHalf, halfToFloat } from "../../app/web/protocol.js";
import { presetParams } from "./simoracle.mjs";

const FERN = presetParams("fern");
const TOUCHES = [[380, 640], [300, 560], [470, 700]];

// What a page holds: the height grid, and the features it was sent since the last reset.
class Page {
  constructor(cols, rows) {
    this.heights = new Float32Array(cols * rows);
    this.vertices = 0;
  }

  apply(buffer, delta) {
    const message = decodeDelta(buffer, "view");
    if (typeof Float16Array === "function") assert.deepEqual(decodeDelta(buffer, "typed"), message);
    assert.equal(message.tick, delta.tick);
    assert.equal(message.reset, delta.reset);
    assert.deepEqual(message.clearBox, delta.clearBox && delta.clearBox.map(Math.fround));
    if (message.reset) this.heights.fill(0);
    let at = 0;
    for (const [start, count] of message.runs) {
      this.heights.set(message.heights.subarray(at, at + count), start);
      at += count;
    }
    this.vertices = (message.reset ? 0 : this.vertices) + message.features.length / 6;
    const sent = delta.features, got = message.features;
    assert.equal(got.length, sent.length);
    for (let i = 0; i < got.length; i++) {
      const k = i % 6;  // x, y in 1/16 px; z a half float; the normal in 1/127
      const tol = k < 2 ? 1 / 32 : k === 2 ? 1e-3 * Math.abs(sent[i]) + 1e-7 : 0.5 / 127;
      assert.ok(Math.abs(got[i] - sent[i]) <= tol + 1e-6, `vertex value ${i}: sent ${sent[i]}, read ${got[i]}`);
    }
  }
}

function grown() {
  const frost = new Frost(FERN, { seed: 1 });
  const geometry = new FrostGeometry(FERN);
  const encoder = new Encoder(geometry.cols, geometry.rows);
  const page = new Page(geometry.cols, geometry.rows);
  const send = (delta) => page.apply(encodeDelta(delta, encoder), delta);
  send(geometry.reset());
  for (const [x, y] of TOUCHES) assert.ok(frost.touch(x, y));
  const tick = () => send(geometry.update(frost, frost.step()));
  for (let i = 0; i < 150; i++) tick();
  const melted = frost.melt(380, 668, 6);
  assert.ok(melted.length > 0, "the warm finger melted nothing");
  const delta = geometry.melt(frost, melted);
  assert.ok(delta.clearBox, "a melt without its box");
  send(delta);
  for (let i = 0; i < 20; i++) tick();
  return { frost, geometry, page };
}

test("the page's frost through its geometry and encoding reads back as the renderer's grid", () => {
  const { frost, geometry, page } = grown();
  assert.ok(frost.count > 100, `only ${frost.count} crystals grew`);
  const want = geometry.grid.heights.map((h) => halfToFloat(floatToHalf(h)));
  assert.deepEqual(page.heights, want);
  assert.ok(page.heights.some((h) => h > 0));
});

test("a tick's heights after growth and a melt are the whole ice's, raised afresh", () => {
  const { frost, geometry } = grown();
  const fresh = new FrostGeometry(FERN).redraw(frost);
  const kept = geometry.grid.heights;
  assert.equal(fresh.heights.length, kept.length);
  for (let i = 0; i < kept.length; i++) {
    assert.ok(Math.abs(fresh.heights[i] - kept[i]) < 1e-5, `vertex ${i}: ${kept[i]}, afresh ${fresh.heights[i]}`);
  }
  // One ridge of 24 vertices for every live crystal with a parent.
  let links = 0;
  for (let i = 0; i < frost.count; i++) if (frost.crystalAlive[i] && frost.parents[i] >= 0) links++;
  assert.equal(fresh.features.length, links * 24 * 6);
});

test("a melt that took nothing and a tick that added nothing change nothing", () => {
  const frost = new Frost(FERN, { seed: 1 });
  const geometry = new FrostGeometry(FERN);
  const none = geometry.melt(frost, frost.melt(NaN, 10, 5));
  assert.deepEqual([none.rows, none.features.length, none.clearBox], [[0, 0], 0, null]);
  const idle = geometry.update(frost, frost.step());
  assert.deepEqual([idle.rows, idle.features.length], [[0, 0], 0]);
});

test("a melt's crystals that are not the frost's last melt are refused, saying so", () => {
  const frost = new Frost(FERN, { seed: 1 });
  const geometry = new FrostGeometry(FERN);
  assert.ok(frost.touch(380, 640));
  assert.throws(() => geometry.melt(frost, Int32Array.of(0)), /not the frost's last melt/);
});
