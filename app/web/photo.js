// "Use a photo…": a photo from the phone's gallery or camera behind everyone's frost. The
// page decodes it (turned as its EXIF says), draws it covering the 760x1280 pane, centred,
// and sends that as a JPEG of at most MAX_BYTES to the server (POST photo, with the token;
// the browser adds the page's Origin), which checks it again, keeps it and shows it on
// every page (docs/phone.md, A photo from the phone). A file the browser cannot decode is
// sent as it is (at most SERVER_MOST): the server says why it is refused.
// With no server (the phone's own frost, the static site) the photo goes nowhere: the same
// JPEG is kept on the phone (IndexedDB) and drawn behind the phone's frost, again after a
// reload, offline too, until a backdrop is chosen in the menu.

export const PANE = [760, 1280];
export const MAX_BYTES = 1 << 20;  // the JPEG sent: lower qualities until it fits
const QUALITIES = [0.9, 0.82, 0.74, 0.66, 0.58, 0.5, 0.42, 0.34, 0.26];
const SERVER_MOST = 8 << 20;  // app/photos.py MAX_BYTES
// frost.shownBackdrop while the phone's own photo is drawn.
export const LOCAL_PHOTO = "your photo";
const DB = "frost", STORE = "photo", KEY = "backdrop";  // IndexedDB: {blob, shown, at}
const WATCH_MS = 250;  // how often the page checks that the kept photo is what it draws

// `work(store)` in one transaction of the photo's store ("readonly" or "readwrite"); its
// request's result.
function stored(mode, work) {
  return new Promise((resolve, reject) => {
    const open = indexedDB.open(DB, 1);
    open.onupgradeneeded = () => open.result.createObjectStore(STORE);
    open.onerror = () => reject(open.error);
    open.onsuccess = () => {
      const db = open.result;
      const request = work(db.transaction(STORE, mode).objectStore(STORE));
      request.onsuccess = () => { db.close(); resolve(request.result); };
      request.onerror = () => { db.close(); reject(request.error); };
    };
  });
}

// The photo kept on this phone ({blob, shown, at}), or null.
export function keptPhoto() {
  return stored("readonly", (store) => store.get(KEY)).then((k) => k || null, () => null);
}

function keepPhoto(value) {
  return stored("readwrite", (store) => store.put(value, KEY));
}

// A photo's backdrop name (app/photos.py): photo- and 32 hex digits.
export function isPhoto(name) {
  return /^photo-[0-9a-f]{32}$/.test(name || "");
}

// Where a backdrop's picture is: a built-in's PNG, a photo's JPEG.
export function backdropUrl(name, query) {
  return `backdrops/${encodeURIComponent(name)}.${isPhoto(name) ? "jpg" : "png"}${query}`;
}

// What the menu calls each backdrop: a built-in by its name, photos "photo 1", "photo 2"...
export function backdropLabels(names) {
  let n = 0;
  return names.map((name) => (isPhoto(name) ? `photo ${++n}` : name));
}

// `file` covering the pane, centred, as a JPEG Blob of at most MAX_BYTES (the lowest
// quality's if none fits); null if the browser cannot decode it.
export async function paneJpeg(file) {
  let bitmap;
  try {
    bitmap = await createImageBitmap(file, { imageOrientation: "from-image" });
  } catch {
    return null;
  }
  const [W, H] = PANE;
  const canvas = document.createElement("canvas");
  [canvas.width, canvas.height] = PANE;
  const scale = Math.max(W / bitmap.width, H / bitmap.height);
  const w = bitmap.width * scale, h = bitmap.height * scale;
  const ctx = canvas.getContext("2d");
  ctx.imageSmoothingQuality = "high";
  ctx.drawImage(bitmap, (W - w) / 2, (H - h) / 2, w, h);
  bitmap.close();
  let blob = null;
  for (const quality of QUALITIES) {
    blob = await new Promise((resolve) => canvas.toBlob(resolve, "image/jpeg", quality));
    if (blob && blob.size <= MAX_BYTES) break;
  }
  return blob;
}

// The menu's "Use a photo…" button and its file input; `say(text)` the page's status
// line (it stays), `notice(text)` a line that goes after a while. `last` says how the last
// photo went (the tests and `python -m bench page --photo` read it): {status, backdrop, bytes,
// answered} or {status, error, answered} (`answered`: when the server's answer came, ms
// since the epoch; null if none came).
export class PhotoPicker {
  // page: window.frost (no server: its `alone` grows the frost, its renderer draws the photo).
  constructor(panel, query, say, notice, page = globalThis.frost) {
    this.query = query;
    this.say = say;
    this.notice = notice;
    this.page = page;
    this.last = null;
    this.sending = false;
    this.shown = null;  // the phone's own photo (an ImageBitmap) while it is the backdrop
    keptPhoto().then((k) => (k && k.shown && !this.shown ? this.decode(k.blob) : null))
      .then((image) => { if (image && !this.shown) this.shown = image; }, () => {});
    this.watch = setInterval(() => this.draw(), WATCH_MS);
    this.input = Object.assign(document.createElement("input"), {
      type: "file", accept: "image/*", hidden: true, id: "photo-file",
    });
    this.button = Object.assign(document.createElement("button"), { id: "photo", textContent: "Use a photo…" });
    this.button.addEventListener("click", () => this.input.click());
    this.input.addEventListener("change", () => {
      const file = this.input.files && this.input.files[0];
      this.input.value = "";  // (the same file chosen again is a change again)
      if (file) this.send(file).catch((err) => this.failed(0, err.message));
    });
    const backdrop = panel.querySelector("#backdrop");
    // A backdrop chosen on the phone's own frost replaces its photo (kept, not shown).
    if (backdrop) backdrop.addEventListener("change", () => this.local() && this.forget());
    const after = backdrop ? backdrop.closest("label") : null;
    if (after) after.after(this.button, this.input);
    else panel.append(this.button, this.input);
  }

  // No server: the phone grows its own frost, and a photo stays on the phone.
  local() {
    return !!(this.page && this.page.alone && this.page.alone.running);
  }

  decode(blob) {
    return createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
  }

  // The kept photo drawn behind the phone's frost, whenever another backdrop took its place
  // (the worker's hello after a reload, a lost GPU context, a return from the server's frost).
  draw() {
    const page = this.page;
    if (!this.shown || !this.local() || !page.renderer || !page.shownBackdrop || page.shownBackdrop === LOCAL_PHOTO) return;
    page.renderer.setBackgroundImage(this.shown);
    page.shownBackdrop = LOCAL_PHOTO;
  }

  // The photo is no longer the backdrop (kept on the phone all the same).
  forget() {
    if (!this.shown) return;
    this.shown = null;
    this.page.backdrop = null;  // (the worker's backdrop drawn again at its next word)
    keptPhoto().then((k) => k && keepPhoto({ ...k, shown: false })).catch(() => {});
  }

  // `file` covering the pane, kept on the phone and drawn behind its frost; sent nowhere.
  async keepHere(file) {
    this.say("putting your photo behind the frost…");
    const blob = await paneJpeg(file);
    if (!blob) return this.failed(0, "this browser cannot read the file as a picture");
    const image = await this.decode(blob);
    try {
      await keepPhoto({ blob, shown: true, at: Date.now() });
    } catch (err) {
      this.notice(`your photo is shown but not kept on the phone: ${err.message || err}`);
    }
    this.shown = image;
    if (this.page.shownBackdrop === LOCAL_PHOTO) this.page.shownBackdrop = "";  // (drawn again)
    this.draw();
    this.last = { status: 0, backdrop: LOCAL_PHOTO, bytes: blob.size, answered: null, local: true };
    this.say("");
  }

  async send(file) {
    if (this.sending) return this.notice("a photo is on its way already");
    this.sending = true;
    this.button.disabled = true;
    try {
      if (this.local()) return await this.keepHere(file);
      this.say("sending your photo…");
      let body = await paneJpeg(file);
      if (!body) {
        if (file.size > SERVER_MOST) return this.failed(0, "this browser cannot read the file, and it is over 8 MB");
        body = file;  // the server tells why it is not a photo
      }
      const response = await fetch(`photo${this.query}`, {
        method: "POST", body, headers: { "Content-Type": body.type || "application/octet-stream" },
      });
      let answer = {};
      try {
        answer = await response.json();
      } catch { /* not the server's JSON (a proxy's page) */ }
      const answered = performance.timeOrigin + performance.now();  // (ms since the epoch)
      if (!response.ok) return this.failed(response.status, answer.error || `HTTP ${response.status}`, answered);
      this.last = { status: response.status, backdrop: answer.backdrop, bytes: body.size, answered };
      this.say("");  // every page's state names the photo: it loads as any backdrop does
    } finally {
      this.sending = false;
      this.button.disabled = false;
    }
  }

  failed(status, text, answered = null) {
    this.last = { status, error: text, answered };
    this.say("");
    this.notice(this.local() ? `photo: ${text}` : `photo refused: ${text}`);
  }
}
