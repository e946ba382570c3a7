// How the 760x1280 pane lies on the screen: "fill" scales it to cover the whole canvas,
// centred, as a wallpaper does (what falls outside is cropped), "pane" scales it to fit
// whole, centred, black bars around it (a letterbox). And the page's remembered choices
// (localStorage, where the browser allows it).

export const FITS = ["fill", "pane"];

// Where the pane lies on a w x h canvas (canvas px, y down): {x, y, w, h, scale}; x and y
// are negative where the pane is cropped. One scale for both axes, so a pane px is square.
export function paneRect(w, h, fit = "fill", size = [760, 1280]) {
  const pick = fit === "pane" ? Math.min : Math.max;
  const scale = pick(w / size[0], h / size[1]);
  const pw = Math.round(size[0] * scale), ph = Math.round(size[1] * scale);
  return { x: Math.floor((w - pw) / 2), y: Math.floor((h - ph) / 2), w: pw, h: ph, scale };
}

// Canvas px for each CSS px of a cssW x cssH canvas: the screen's own (`dpr`), but never
// more than the pane has to show there. A pane px spread over several canvas px brings
// nothing new: the browser scales the canvas up to the screen as smoothly as a blit of
// the pane's texture would, and the page draws, and the browser copies and keeps, far
// fewer px (a covering pane on a phone of 390x844 CSS px at 3: 591x1280, not 1170x2532).
export function canvasScale(cssW, cssH, dpr, fit = "fill", size = [760, 1280]) {
  const pick = fit === "pane" ? Math.min : Math.max;
  const shown = pick(cssW / size[0], cssH / size[1]);  // CSS px per pane px
  return shown > 0 ? Math.min(dpr, 1 / shown) : dpr;
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
