// Typed arrays that grow: the page's Growable (sim/core/buffers.py). No objects per
// particle: every row is a few numbers in flat arrays, copied to a larger one when full.

/** `array` (of rows of `width` numbers) with room for at least `rows` rows: itself, or
 * a copy at least twice as long. */
export function room(array, rows, width = 1) {
  if (rows * width <= array.length) return array;
  const bigger = new array.constructor(Math.max(rows * width, 2 * array.length));
  bigger.set(array);
  return bigger;
}

/** The first index of `sorted[0, n)` not below `value` (its lower bound). */
export function lowerBound(sorted, n, value) {
  let lo = 0, hi = n;
  while (lo < hi) {
    const mid = (lo + hi) >>> 1;
    if (sorted[mid] < value) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}
