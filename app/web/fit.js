// How the 760x1280 pane lies on the screen: "fill" scales it to cover the whole canvas,
// centred, as a wallpaper does (what falls outside is cropped), "pane" scales it to fit
// whole, centred, black bars around it (a letterbox). And the page's remembered choices
// (localStorage, where the browser allows it).

export const FITS = ["fill", "pane"];

// Where the pane lies on a w x h canvas (device px, y down): {x, y, w, h, scale}; x and y
// are negative where the pane is cropped. One scale for both axes, so a pane px is square.
export function paneRect(w, h, fit = "fill", size = [760, 1280]) {
  const pick = fit === "pane" ? Math.min : Math.max;
  const scale = pick(w / size[0], h / size[1]);
  const pw = Math.round(size[0] * scale), ph = Math.round(size[1] * scale);
  return { x: Math.floor((w - pw) / 2), y: Math.floor((h - ph) / 2), w: pw, h: ph, scale };
}

// The part of the pane a w x h canvas shows, in whole pane px: [x0, y0, x1, y1].
export function visiblePane(rect, w, h, size = [760, 1280]) {
  const clampX = (v) => Math.min(Math.max(v, 0), size[0]);
  const clampY = (v) => Math.min(Math.max(v, 0), size[1]);
  return [clampX(Math.floor(-rect.x / rect.scale)), clampY(Math.floor(-rect.y / rect.scale)),
    clampX(Math.ceil((w - rect.x) / rect.scale)), clampY(Math.ceil((h - rect.y) / rect.scale))];
}

// A choice kept across visits: `get` gives the stored value if it is one of `allowed`, else
// `fallback`; `set` stores it (silently nothing where storage is refused: a private tab).
export const prefs = {
  get(key, fallback, allowed = null) {
    let v = null;
    try { v = localStorage.getItem(`frost.${key}`); } catch { /* no storage */ }
    return v !== null && (!allowed || allowed.includes(v)) ? v : fallback;
  },
  set(key, value) {
    try { localStorage.setItem(`frost.${key}`, String(value)); } catch { /* no storage */ }
  },
};
