// With no server to answer before the first hello (the page opened from the cache while
// `frost serve` is not reachable), the page shows the backdrop it showed last, from the
// cache, lying as the pane would (covering the screen, or whole with "Whole pane"), under
// the status line, instead of a black screen. The frost comes back with the server. Only a
// built-in is remembered: a photo is never cached (it is the server's, and the user's).

import { prefs } from "./fit.js";

const BUILT_IN = /^[a-z]{1,32}$/;  // (a photo's name, photo-<hex>, has a hyphen)

// The backdrop a page shows, remembered for an offline start.
export function rememberBackdrop(name) {
  if (BUILT_IN.test(name)) prefs.set("backdrop", name);
}

// The remembered backdrop behind a hidden canvas (no renderer yet), or back to the canvas.
export function showOffline(on, canvas, query, fit) {
  const body = document.body.style;
  if (!on) {
    canvas.style.visibility = "";
    body.backgroundImage = "";
    return;
  }
  // (the lock screen without its clock, which the server draws, looks broken: dusk then)
  const name = prefs.get("backdrop", "dusk");
  const shown = BUILT_IN.test(name) && name !== "lockscreen" ? name : "dusk";
  body.backgroundImage = `url("backdrops/${shown}.png${query}")`;
  body.backgroundSize = fit === "pane" ? "contain" : "cover";
  body.backgroundPosition = "center";
  body.backgroundRepeat = "no-repeat";
  canvas.style.visibility = "hidden";
}
