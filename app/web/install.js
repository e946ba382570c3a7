// The page as an app (docs/phone.md, Installing the page): its service worker (/sw.js, the
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

register();
