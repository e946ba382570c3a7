// The page's service worker, served as /sw.js (its scope: the whole site) after a first
// line the server writes (app/serve/install.py): SHELL, the files of the page's shell and
// the hash of their bytes. It keeps the shell in a cache named by that hash, so the page
// opens when `frost serve` cannot be reached; the socket, /meta, the manifest and the
// worker itself always go to the network. The static site (`frost web`,
// app/tools/web_site.py) writes the same first line into its own sw.js, and beside it
// SHELL.version, a file that says the site's hash (`{"build": HASH}`): a static host sends
// no header of ours.
//
// Never a mix of two versions of the page: the page's own request decides where every
// file of that page comes from. Answered by the server, its X-Frost-Shell header (on the
// static site, the version file, asked right after) says the hash of the server's shell:
// the same as this worker's, the files come from the cache (they are those bytes); another
// (the server was upgraded, the site built again), all come from the network while the
// browser installs the new worker, whose new cache replaces this one whole. Not answered
// (the server is gone, or silent for NAVIGATION_WAIT ms: a phone away from the LAN), the
// page and all its files come from the cache. What comes from the network is asked past
// the browser's HTTP cache (`no-cache`: a static host lets a browser keep files a while,
// and a kept file of the old build beside the new ones would be a mix).
/* global SHELL */

const CACHE = `frost-shell-${SHELL.hash}`;
const QUERY = self.location.search;  // ?token=T, where one is in force
const ROOT = new URL("./", self.location.href);
const PATHS = new Set(SHELL.files.map((file) => new URL(file, ROOT).pathname));
const NAVIGATION_WAIT = 4000;
const VERSION = SHELL.version ? new URL(SHELL.version, ROOT) : null;  // the static site's
const sources = new Map();  // a page (client id) -> "cache" | "network"
const unanswered = new Set();  // the pages opened from the cache as the server did not answer

self.addEventListener("install", (event) => {
  event.waitUntil(fill().then(() => self.skipWaiting()));
});

// The shell into a new cache; the page's own request last: its hash must still be this
// worker's, or the files fetched may be of two versions (the install fails; the browser
// tries again at the next visit, and the next worker to take over deletes what is left:
// never deleted here, as a worker of the same hash under another token's address fills
// the cache the active one serves, with the same bytes).
async function fill() {
  const cache = await caches.open(CACHE);
  const files = SHELL.files.filter((f) => f !== "").concat([""]);
  for (const file of files) {
    const response = await fetch(new Request(new URL(file + QUERY, ROOT), { cache: "no-store" }));
    if (!response.ok) throw new Error(`${file || "/"}: HTTP ${response.status}`);
    if (file === "" && await shellOf(response) !== SHELL.hash) {
      throw new Error("the page changed while it was being cached");
    }
    await cache.put(new URL(file, ROOT).href, response);
  }
}

// The hash of the shell whose page `response` is: the server's header, else (a static
// host) what the site's version file says now; null where neither says.
async function shellOf(response) {
  const header = response.headers.get("X-Frost-Shell");
  if (header !== null || !VERSION) return header;
  try {
    const version = await fetch(VERSION, { cache: "no-store" });
    return version.ok ? (await version.json()).build : null;
  } catch {
    return null;
  }
}

// A request of the page's, to the network past the HTTP cache.
function fresh(request) {
  if (request.mode !== "navigate") return fetch(request, { cache: "no-cache" });
  // (a navigation's request cannot be given another cache mode: asked anew by its address)
  return fetch(request.url, { cache: "no-cache", credentials: "same-origin" }).then((r) =>
    (r.redirected ? Response.redirect(r.url, 302) : r));
}

self.addEventListener("activate", (event) => {
  event.waitUntil((async () => {
    for (const name of await caches.keys()) {
      if (name.startsWith("frost-shell-") && name !== CACHE) await caches.delete(name);
    }
    await self.clients.claim();
  })());
});

self.addEventListener("fetch", (event) => {
  const request = event.request;
  const url = new URL(request.url);
  if (request.method !== "GET" || url.origin !== ROOT.origin || !PATHS.has(url.pathname)) return;
  event.respondWith((request.mode === "navigate" ? page(event) : file(event)).then(unkept));
});

// `response` as the page is given it: never kept by the browser beyond the page (no-cache),
// so that each page's files come through this worker, by the page's own choice, and never
// from the browser's memory of another page's (a static host's max-age kept the old build's
// modules beside a new build's page).
function unkept(response) {
  if (response.status !== 200 || (response.type !== "basic" && response.type !== "default")) return response;
  const headers = new Headers(response.headers);
  headers.set("Cache-Control", "no-cache");
  return new Response(response.body, { status: 200, statusText: response.statusText, headers });
}

function cached(request) {
  // The cache's keys have no token: the page's requests carry one.
  return caches.open(CACHE).then((cache) => cache.match(request, { ignoreSearch: true }));
}

async function page(event) {
  const network = fresh(event.request);
  network.catch(() => {});  // (answered by the cache meanwhile: no unhandled rejection)
  const late = new Promise((resolve) => setTimeout(resolve, NAVIGATION_WAIT, null));
  let response = null;
  try {
    response = await Promise.race([network, late]);
  } catch { /* the server is not reachable */ }
  const client = event.resultingClientId;
  await forgetClosed();
  if (response) {
    const same = await shellOf(response) === SHELL.hash;
    if (client) sources.set(client, same ? "cache" : "network");
    return response;
  }
  const kept = await cached(event.request);
  if (!kept) return network;  // nothing cached yet: the network's answer, or its error
  if (client) {
    sources.set(client, "cache");
    unanswered.add(client);
  }
  return kept;
}

// The pages gone since (a page's id is never used again).
async function forgetClosed() {
  if (sources.size < 32) return;
  const open = new Set((await self.clients.matchAll()).map((c) => c.id));
  for (const id of sources.keys()) if (!open.has(id)) sources.delete(id);
  for (const id of unanswered) if (!open.has(id)) unanswered.delete(id);
}

// A page asks how it was opened (install.js): from the cache because the server did not
// answer, or not.
self.addEventListener("message", (event) => {
  if (event.data === "opened-how?" && event.source) {
    event.source.postMessage({ openedOffline: unanswered.has(event.source.id) });
  }
});

async function file(event) {
  const source = sources.get(event.clientId);
  if (source === "network") return fresh(event.request);
  if (source === "cache") return (await cached(event.request)) || fresh(event.request);
  // A page this worker did not open (opened before it took over): the network, else the cache.
  try {
    return await fresh(event.request);
  } catch (err) {
    const kept = await cached(event.request);
    if (kept) return kept;
    throw err;
  }
}
