// "Make it an app": how a phone comes to trust this computer, so that the page can be
// opened over HTTPS (docs/phone.md, HTTPS on your network). Over plain HTTP a browser
// withholds what an app needs (installing, the wake lock, motion sensors); over HTTPS it
// gives them once the phone trusts the local certificate authority `frost serve` keeps.
//
// The page asks the server for its ports (GET /app.json). On the HTTP page the menu gets a
// "Make it an app" button that shows the steps: the authority's certificate to download,
// how Android and iOS install and trust it, then the HTTPS address. A page loaded over
// HTTPS whose socket never opens shows the same steps by itself: a page cannot learn that a
// certificate was the cause, only that nothing connected.

const NEVER_OPENED_MS = 8000;  // an HTTPS page with no hello this long after it loaded

export function makeApp(menu, query, state) {
  const info = { ports: null, httpsUrl: null, httpUrl: null, shown: null };
  state.makeApp = info;
  const css = document.createElement("link");
  css.rel = "stylesheet";
  css.href = "web/makeapp.css" + query;
  document.head.append(css);
  const sheet = buildSheet();
  document.body.append(sheet.root);
  const secure = location.protocol === "https:";

  const show = (why) => {
    info.shown = why;
    sheet.fill(why, info);
    sheet.root.hidden = false;
  };
  const hide = () => {
    info.shown = null;
    sheet.root.hidden = true;
  };
  sheet.close.addEventListener("click", hide);

  fetch(new URL("app.json" + query, location.href), { cache: "no-store" })
    .then((r) => (r.ok ? r.json() : null))
    .then((ports) => {
      if (!ports) return;
      info.ports = ports;
      info.httpsUrl = addressOn("https:", ports.https);
      info.httpUrl = addressOn("http:", ports.http);
      // Over HTTP, with HTTPS and an authority to trust: the menu offers the steps.
      if (!secure && ports.https && ports.ca) {
        const button = document.createElement("button");
        button.id = "makeapp-open";
        button.textContent = "Make it an app";
        button.addEventListener("click", () => show("menu"));
        menu.querySelector("#panel").append(button);
      }
      if (info.shown) sheet.fill(info.shown, info);
    })
    .catch(() => {});  // no server: the page's own status says so

  if (secure) {
    setTimeout(() => {
      // (the cache opened it: install.js; refused: the page says why, connection.js)
      if (state.hellos || state.refused || window.frostInstall?.openedOffline) return;
      show("never-opened");
      // Hidden again by itself once the socket opens after all (trusted, or the server back),
      // or the server refused the page (its status line says why).
      const watch = setInterval(() => {
        if (!state.hellos && !state.refused) return;
        clearInterval(watch);
        if (info.shown === "never-opened") hide();
      }, 500);
    }, NEVER_OPENED_MS);
  }
}

// This page's address on another scheme and port, the token kept; null without a port.
function addressOn(protocol, port) {
  if (!port) return null;
  const url = new URL(location.href);
  url.protocol = protocol;
  url.port = String(port);
  url.pathname = "/";
  url.hash = "";
  return url.href;
}

function el(tag, props = {}, ...children) {
  const node = Object.assign(document.createElement(tag), props);
  node.append(...children);
  return node;
}

function buildSheet() {
  const root = el("div", { id: "makeapp", hidden: true });
  root.setAttribute("role", "dialog");
  root.setAttribute("aria-labelledby", "makeapp-title");
  const body = el("div", { className: "sheet" });
  const close = el("button", { id: "makeapp-close", textContent: "Close" });
  root.append(body);

  function fill(why, info) {
    const failed = why === "never-opened";
    const title = el("h2", { id: "makeapp-title",
      textContent: failed ? "No connection to frost serve" : "Make it an app" });
    const intro = el("p", { textContent: failed
      ? "This page came over HTTPS, but its connection to the server never opened. If this "
        + "phone does not trust this computer's certificate yet, that is the likely cause "
        + "(a page cannot tell): the steps below fix it. Else check that frost serve still runs."
      : "Over plain HTTP the browser keeps back what an app needs: adding it to the home "
        + "screen, keeping the screen on, the tilt. Over HTTPS it gives them, once this phone "
        + "trusts the certificate authority that frost made for this computer alone." });
    const cert = el("a", { id: "makeapp-cert", href: "frost-ca.crt", download: "frost-ca.crt",
      textContent: "Download the certificate (frost-ca.crt)" });
    const steps = el("ol", {},
      el("li", {}, cert),
      el("li", {}, "Install it, and trust it:", el("ul", {},
        el("li", {}, el("b", { textContent: "Android: " }),
          "Settings → Security → Encryption & credentials → Install a certificate → CA "
          + "certificate, then pick frost-ca.crt from Downloads. Android 11 and later install "
          + "an authority only from there (opening the file says so). The menus' names vary a "
          + "little by maker: search Settings for \"CA certificate\"."),
        el("li", {}, el("b", { textContent: "iPhone, iPad: " }),
          "download it in Safari and allow the configuration profile. Then Settings → Profile "
          + "Downloaded → Install. Then Settings → General → About → Certificate Trust "
          + "Settings: switch on full trust for \"frost\"."))),
    );
    const last = el("li", { id: "makeapp-next" });
    if (failed) {
      last.append("Then reload this page.");
      if (info.httpUrl) {
        last.append(" Meanwhile the plain page works without it: ",
          el("a", { href: info.httpUrl, textContent: info.httpUrl }));
      }
    } else if (info.httpsUrl) {
      last.append("Then open the app's address, and add it to the home screen: ",
        el("a", { id: "makeapp-https", href: info.httpsUrl, textContent: info.httpsUrl }));
    }
    steps.append(last);
    const note = el("p", { className: "note", textContent: "The authority's private key "
      + "stays in a file on this computer that only its user can read. Remove the "
      + "certificate from the phone (the same settings) when you no longer use frost." });
    body.replaceChildren(title, intro, steps, note, close);
  }

  return { root, close, fill };
}
