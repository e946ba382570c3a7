// What the Node tick benchmarks share (bench/local_ticks.mjs, bench/window_ticks.mjs):
// each tick timed by the wall clock and by the process's CPU clock, and a quantile.

/** Runs `step` `n` times, pushing each call's wall-clock and CPU milliseconds. */
export function timeTicks(step, n, wall = [], cpu = []) {
  for (let t = 0; t < n; t++) {
    const t0 = performance.now(), c0 = process.cpuUsage();
    step();
    const c = process.cpuUsage(c0);
    wall.push(performance.now() - t0);
    cpu.push((c.user + c.system) / 1000);
  }
  return { wall, cpu };
}

/** The `q` quantile of ascending `sorted` (the nearest rank). */
export function quantile(sorted, q) {
  return sorted[Math.min(sorted.length - 1, Math.ceil(q * sorted.length) - 1)];
}
