// The page as an app (docs/phone-design.md, Installing: the shell and its worker): its service worker (/sw.js, the
// server's) registered, so the page installs to the home screen and opens when `frost
// serve` cannot be reached. Where there is none (a plain-HTTP address off this machine is
// no secure context), nothing happens.

const token = new URLSearchParams(location.search).get("token");
const query = token ? `?token=${encodeURIComponent(token)}` : "";

export async function register() {
  if (!("serviceWorker" in navigator)) return null;
  try {
    // Its script carries the token, as every request; its scope: the whole site.
    return await navigator.serviceWorker.register(`sw.js${query}`, { scope: "./" });
  } catch (err) {
    // The server not reachable (the page opened from the cache), or no worker allowed here.
    console.warn(`frost: no service worker: ${err.message}`);
    return null;
  }
}

// Whether the worker opened this page from its cache because the server did not answer:
// then `frostInstall.openedOffline` (the status line says the server is not reachable, and the
// HTTPS page's "no connection" steps stay hidden: a page the phone once cached over HTTPS
// trusts the certificate, so it is not the cause).
function askHowOpened() {
  const worker = navigator.serviceWorker && navigator.serviceWorker.controller;
  if (!worker) return;
  navigator.serviceWorker.addEventListener("message", (event) => {
    const data = event.data;
    if (data && "openedOffline" in data) window.frostInstall.openedOffline = data.openedOffline;
  });
  navigator.serviceWorker.startMessages();
  worker.postMessage("opened-how?");
}

window.frostInstall = { openedOffline: null };  // (main.js's `frost` may come later)
askHowOpened();
register();
