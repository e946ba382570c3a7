// The page's random numbers: a small seeded generator (sfc32), so a seed gives the same
// frost in every browser. `sim/` draws from numpy's PCG64; the two are compared by what
// the frost is, not number for number (docs/local-sim.md).

const TWO_32 = 4294967296;
const BELOW_ONE = Math.fround(1 - 2 ** -24);

/** sfc32's state and steps: a class, so that every frost's generator runs the same
 * compiled methods. (A generator made of closures compiled for the first frost alone, the
 * worker's warm-up: the next frost's ran uncompiled for as long as it grew, each of a
 * walk's 12 000 draws a tick boxed on the heap.) */
class Sfc32 {
  constructor(seed) {
    // splitmix32 spreads the seed over sfc32's four words (a zero state would stall it).
    let s = (seed >>> 0) ^ 0x9e3779b9;
    const mix = () => {
      s = (s + 0x9e3779b9) | 0;
      let z = s;
      z = Math.imul(z ^ (z >>> 16), 0x85ebca6b);
      z = Math.imul(z ^ (z >>> 13), 0xc2b2ae35);
      return (z ^ (z >>> 16)) >>> 0;
    };
    this.a = mix() | 0;
    this.b = mix() | 0;
    this.c = mix() | 0;
    this.d = mix() | 0;
    for (let i = 0; i < 12; i++) this.next();  // past the seed's first, correlated draws
  }

  next() {
    const { a, b, c, d } = this;
    const t = (((a + b) | 0) + d) | 0;
    this.d = (d + 1) | 0;
    this.a = b ^ (b >>> 9);
    this.b = (c + (c << 3)) | 0;
    this.c = (((c << 21) | (c >>> 11)) + t) | 0;
    return (t >>> 0) / TWO_32;
  }

  // next() n times, its four words kept in locals meanwhile (not loaded from and stored to
  // the generator at each of a walk's 12 000 draws).
  fill(array, n) {
    let { a, b, c, d } = this;
    for (let i = 0; i < n; i++) {
      const t = (((a + b) | 0) + d) | 0;
      d = (d + 1) | 0;
      a = b ^ (b >>> 9);
      b = (c + (c << 3)) | 0;
      c = (((c << 21) | (c >>> 11)) + t) | 0;
      const f = Math.fround((t >>> 0) / TWO_32);
      array[i] = f < 1 ? f : BELOW_ONE;
    }
    this.a = a;
    this.b = b;
    this.c = c;
    this.d = d;
  }
}

/** A function () => number in [0, 1) (multiples of 2^-32) for a whole-number `seed`; its
 * `fill(array, n)` writes n draws as float32 (`float32Of`) into a typed array, the same
 * draws in the same order, without a number boxed for each. */
export function seeded(seed = 1) {
  const generator = new Sfc32(seed);
  const next = generator.next.bind(generator);
  next.fill = generator.fill.bind(generator);
  return next;
}

/** A float32 draw in [0, 1), as numpy's `random(dtype=float32)` gives: rounding a double
 * draw to float32 may give 1, which is taken down to the largest float32 below it. */
export function float32Of(u) {
  const f = Math.fround(u);
  return f < 1 ? f : BELOW_ONE;
}

/** A standard normal draw (Box-Muller) from `uniform`. */
export function normal(uniform) {
  const u = 1 - uniform();  // (0, 1]: log stays finite
  return Math.sqrt(-2 * Math.log(u)) * Math.cos(2 * Math.PI * uniform());
}

/** Fills the typed array `array` with float32 draws of `uniform` (its own `fill` where it
 * has one). */
export function drawInto(uniform, array, n = array.length) {
  if (uniform.fill) {
    uniform.fill(array, n);
    return;
  }
  for (let i = 0; i < n; i++) array[i] = float32Of(uniform());
}
