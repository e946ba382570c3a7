"""The page as an installed app, end to end: `frost serve` in a subprocess, the page in
headless Chromium with a persistent profile (a service worker and the installability check
need one: incognito reports `in-incognito`). Chromium finds the page installable; with the
server gone the page opens from the worker's cache and grows its own frost ("on this
phone"), and joins the server again when it is back on the same port and the user says so;
a changed page replaces the cached one after one reload, whole."""

from __future__ import annotations

import base64
import io
import json
import os
import shutil
import socket
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support.phone import (
    PHONE,
    PROBLEM,
    WITH_WORKER,
    grown,
    open_page,
    persistent,
    synced,
    tap,
    token_needed,
    wait_for_shell,
    worker_shell,
)

from app.images import cover
from app.resources import ASSET_DIR
from bench.serve_process import ServeProcess

pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

ROOT = Path(__file__).resolve().parent.parent
ON_PHONE = "on this phone"


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def installability_errors(context, page) -> list[dict]:
    """What Chromium says stands between `page` and its installation (none: installable),
    once the page's service worker is active."""
    page.wait_for_function("navigator.serviceWorker && navigator.serviceWorker.controller", timeout=30_000)
    cdp = context.new_cdp_session(page)
    try:
        return cdp.send("Page.getInstallabilityErrors")["installabilityErrors"]
    finally:
        cdp.detach()


def installability(pw, url: str, profile: Path, **context) -> list[dict]:
    """Installability errors of the page at `url` (any address: loopback, HTTPS), opened
    in a fresh persistent profile (`context`: more of launch_persistent_context's options)."""
    ctx = persistent(pw, profile, **context)
    try:
        return installability_errors(ctx, open_page(ctx, url))
    finally:
        ctx.close()


def status(page) -> str:
    return page.evaluate("document.getElementById('status').textContent")


def shell_hash(s: ServeProcess) -> str:
    return worker_shell(s)["hash"]


@pytest.mark.parametrize("host", ["127.0.0.1", "0.0.0.0"])
def test_chromium_finds_the_page_installable(pw, serve, tmp_path, host):
    s = serve("--host", host, folder=tmp_path)
    assert (s.token is None) == (host == "127.0.0.1")
    assert installability(pw, s.local, tmp_path / "profile") == []
    if s.token:  # the app's files need the token like every request; the app keeps it
        token_needed(s, ("sw.js", "manifest.webmanifest", "web/icons/icon-192.png",
                         "web/icons/maskable-512.png"))
        bare = f"http://127.0.0.1:{s.port}/"
        with urllib.request.urlopen(f"{bare}manifest.webmanifest?token={s.token}", timeout=10) as r:
            assert json.loads(r.read())["start_url"] == f"/?token={s.token}"


@pytest.mark.usefixtures("subprocesses")
def test_chromium_finds_the_https_page_installable_and_it_opens_without_the_server(pw, tmp_path):
    """On the LAN's HTTPS address (the machine's host name, mapped to this machine: no
    loopback name), in a Chromium whose NSS database trusts the kept authority. Opened from
    the cache, the page says the server is not reachable, and not the certificate's steps
    an HTTPS page whose socket never opened shows (this phone trusted it, to cache it): it
    grows its own frost."""
    from support.https import browser_problem as https_problem
    from support.https import trusting_home
    from support.serve import lan_serve

    if https_problem() is not None:
        pytest.skip(str(https_problem()))
    s = lan_serve(tmp_path / "config")
    try:
        name = socket.gethostname().lower()
        home = trusting_home(tmp_path / "home", tmp_path / "config" / "frost" / "ca.crt")
        url = f"https://{name}:{s.https_port}/?token={s.token}"
        ctx = persistent(pw, tmp_path / "profile", env={**os.environ, "HOME": str(home)},
                         args=[f"--host-resolver-rules=MAP {name} 127.0.0.1"])
        try:
            page = open_page(ctx, url)
            assert installability_errors(ctx, page) == []
            wait_for_shell(page)
            s.stop()
            page.clock.install()  # (the page's timers on a clock the test moves on)
            page.reload()
            page.wait_for_function("window.frostInstall.openedOffline === true", timeout=30_000)
            page.clock.fast_forward(10_000)  # past makeapp.js's 8 s without a socket
            page.wait_for_function(f"document.getElementById('status').textContent === {ON_PHONE!r}",
                                   timeout=30_000)
            assert page.evaluate("window.frost.makeApp.shown") is None
            assert not page.locator("#makeapp").is_visible()
            page.screenshot(path=str(tmp_path / "https-offline.png"))
        finally:
            ctx.close()
    finally:
        s.stop()


# Loopback, and the LAN's server (its token kept across runs) opened on this machine.
@pytest.mark.parametrize("host", ["127.0.0.1", "0.0.0.0"])
def test_the_shell_opens_without_the_server_and_joins_it_when_it_is_back(pw, serve, tmp_path, host):
    port = str(free_port())
    s = serve("--port", port, "--host", host, "--no-https", folder=tmp_path)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = open_page(ctx, s.local)
        wait_for_shell(page)
        files = worker_shell(s)["files"]
        meta = "fetch('meta' + location.search).then((r) => r.ok, () => 'failed')"
        assert page.evaluate(meta) is True  # as the page's screenshot asks it
        s.stop()
        page.reload()  # no server: the page, its modules and shaders from the cache
        page.wait_for_function(f"document.getElementById('status').textContent === '{ON_PHONE}' && "
                               "frost.frames > 0", timeout=60_000)
        assert page.evaluate("window.frost.error") is None and page.evaluate("frost.sources") is not None
        # The cache holds the shell and nothing else; the live data is the server's alone.
        kept = page.evaluate("""async () => {
            const [name] = (await caches.keys()).filter((n) => n.startsWith('frost-shell-'));
            return (await (await caches.open(name)).keys()).map((r) => new URL(r.url).pathname);
        }""")
        assert sorted(kept) == sorted(f"/{f}" for f in files)
        assert page.evaluate(meta) == "failed"
        page.screenshot(path=str(tmp_path / "offline.png"))
        # Not a black screen: the phone's own pane over its backdrop (dusk), from the cache,
        # covering the screen (CSS's cover against Pillow's cover of the PNG)
        shot = np.asarray(Image.open(tmp_path / "offline.png").convert("RGB")).astype(int)
        want = np.asarray(cover(Image.open(ASSET_DIR / "background.png").convert("RGB"),
                                shot.shape[1::-1])).astype(int)
        below = slice(shot.shape[0] // 4, None)  # (under the status line and the menu)
        assert np.abs(shot[below] - want[below]).mean() < 6, np.abs(shot[below] - want[below]).mean()
        back = serve("--port", port, "--host", host, "--no-https", folder=tmp_path)
        assert (back.port, back.token) == (s.port, s.token)
        # the server back is offered (alone.js asks every 3 s), and joined: nothing reloaded
        page.wait_for_function("!document.getElementById('join').hidden", timeout=30_000)
        page.click("#join")
        synced(page, "frost.frames > 0 && frost.shownBackdrop && !frost.hello.local")
        # (nothing said but, for a few seconds, that the phone's own frost waits: alone.js's KEPT)
        assert status(page) in ("", "your frost waits on this phone (the menu saves it)")
        page.screenshot(path=str(tmp_path / "back.png"))
    finally:
        ctx.close()


WORKER_HARNESS = """async ([code, answers]) => {
  // The worker's code run against stand-ins: a cache that holds the whole shell, a network
  // that answers the page with the X-Frost-Shell header it is given (null: none).
  const listeners = {};
  const self = { location: new URL('http://pane.test/sw.js?token=T'), clients: { matchAll: async () => [] },
                 addEventListener: (name, f) => { listeners[name] = f; }, skipWaiting: async () => {} };
  let puts = 0;
  const cache = { match: async (r) => new Response('cache ' + new URL(r.url ?? r).pathname),
                  put: async () => { puts += 1; } };
  const caches = { open: async () => cache, keys: async () => [] };
  let header = null;
  const fetch = async (r) => new Response('network ' + new URL(r.url ?? r).pathname,
                                          { headers: header === null ? {} : { 'X-Frost-Shell': header } });
  new Function('self', 'caches', 'fetch', code)(self, caches, fetch);
  const ask = (path, mode, ids) => new Promise((resolve) => listeners.fetch({
    request: { url: 'http://pane.test/' + path + '?token=T', method: 'GET', mode }, ...ids,
    respondWith: (answer) => resolve(Promise.resolve(answer).then((r) => r.text())) }));
  const install = () => new Promise((resolve) => listeners.install({ waitUntil: (done) =>
    resolve(done.then(() => 'installed', (err) => err.message)) }));
  const pages = [], installs = [];
  for (const [n, said] of answers.entries()) {
    header = said;
    const id = 'page' + n;
    pages.push([await ask('', 'navigate', { resultingClientId: id }),
                await ask('web/main.js', 'cors', { clientId: id })]);
    puts = 0;
    installs.push([await install(), puts]);
  }
  return { pages, installs, files: SHELL_FILES };
}"""


def test_the_worker_serves_its_cache_only_to_a_page_of_its_own_hash(browser):
    """The worker's code (as the server serves it) with a stand-in cache and network: a page
    the server answers with the worker's own hash takes its files from the cache; one
    answered with another hash (the server was upgraded), or with none, from the network.
    And the worker installs only where the page, fetched last, is still of its hash (else
    the files cached may be of two versions)."""
    from app.resources import WEB_DIR
    from app.serve.install import Shell

    worker = Shell(WEB_DIR).worker().decode()
    shell = json.loads(worker.split("\n", 1)[0].removeprefix("const SHELL = ").removesuffix(";"))
    page = browser.new_page()
    try:
        got = page.evaluate(WORKER_HARNESS.replace("SHELL_FILES", str(len(shell["files"]))),
                            [worker, [shell["hash"], "0123456789abcdef", None]])
    finally:
        page.close()
    assert got["pages"] == [["network /", "cache /web/main.js"],  # the page itself always the network's
                            ["network /", "network /web/main.js"],
                            ["network /", "network /web/main.js"]]
    changed = "the page changed while it was being cached"
    files = got["files"]
    assert got["installs"] == [["installed", files], [changed, files - 1], [changed, files - 1]]


def test_a_first_visits_worker_takes_over_a_page_growing_frost(serve, browser):
    """A page's first visit (a new context: nothing cached) installs the worker while the
    page grows frost from a tap. The worker takes the page over (clients.claim) with the
    shell cached, and the page goes on as before: its ticks keep coming, a tap after the
    take-over grows frost, and neither the page nor a request of it says an error. (The
    other tests' pages block the worker: support.phone.PHONE.)"""
    s = serve()
    context = browser.new_context(**WITH_WORKER)
    try:
        page = open_page(context, s.local)
        errors: list[str] = []
        page.on("console", lambda m: m.type == "error" and errors.append(m.text))
        page.on("response", lambda r: r.status >= 400 and errors.append(f"{r.status} {r.url}"))
        tap(page, 380, 640)
        wait_for_shell(page, shell_hash(s))
        grown(page, 25)
        tap(page, 200, 300)
        page.wait_for_function("frost.frostLatencies.length >= 2", timeout=30_000)
        grown(page, 10)
        assert page.evaluate("[frost.error, frost.connected]") == [None, True]
        assert errors == []
    finally:
        context.close()


def marked_copy(folder: Path, mark: str) -> Path:
    """The package (app, sim, shaders, assets) copied to `folder`, every file of the page's
    shell marked with `mark`: each module sets it, the CSS, the HTML and each shader say it,
    and version B's dusk backdrop has a pixel of its own. `python -m app` run there runs it."""
    for name in ("app", "sim", "shaders", "assets"):
        shutil.copytree(ROOT / name, folder / name, ignore=shutil.ignore_patterns("__pycache__"))
    web = folder / "app" / "web"
    for js in web.glob("*.js"):
        if js.name != "sw.js":
            js.write_text(js.read_text(encoding="utf-8")
                          + f"\nglobalThis.frostMarks = [...(globalThis.frostMarks || []),"
                          f" '{js.stem}:{mark}'];\n", encoding="utf-8")
    css = web / "page.css"
    css.write_text(css.read_text(encoding="utf-8") + f'\n:root {{ --frost-mark: "{mark}"; }}\n',
                   encoding="utf-8")
    html = web / "index.html"
    meta = f'<meta name="frost-mark" content="{mark}">\n'
    html.write_text(html.read_text(encoding="utf-8").replace("<title>", meta + "<title>"), encoding="utf-8")
    for shader in (folder / "shaders").iterdir():
        shader.write_text(shader.read_text(encoding="utf-8") + f"\n// mark {mark}\n", encoding="utf-8")
    if mark == "B":
        png = folder / "assets" / "background.png"
        image = np.array(Image.open(png).convert("RGB"))
        image[0, 0] = (1, 2, 3)
        Image.fromarray(image).save(png)
    return folder


def versions(page) -> dict[str, str]:
    """Which version each file of the page's shell the page runs came from."""
    return page.evaluate("""() => {
        const found = {};
        for (const m of globalThis.frostMarks || []) {
            const [name, v] = m.split(':');
            found[name + '.js'] = v;
        }
        found.css = getComputedStyle(document.documentElement).getPropertyValue('--frost-mark').trim()
            .replaceAll('"', '');
        found.html = document.querySelector('meta[name=frost-mark]')?.content;
        for (const [name, text] of Object.entries(frost.sources || {})) {
            found[name] = (text.match(/\\/\\/ mark (\\w)/) || [])[1];
        }
        return found;
    }""")


def backdrop_pixel(page) -> tuple[int, ...]:
    """The first pixel of the dusk backdrop as the page fetches it now."""
    data = page.evaluate("""async () => {
        const r = await fetch('backdrops/dusk.png' + location.search);
        const bytes = new Uint8Array(await r.arrayBuffer());
        let s = '';
        for (const b of bytes) s += String.fromCharCode(b);
        return btoa(s);
    }""")
    return tuple(Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB").getpixel((0, 0)))


def test_a_changed_page_replaces_the_cached_one_after_one_reload(pw, serve, tmp_path):
    port = str(free_port())
    a = marked_copy(tmp_path / "a", "A")
    b = marked_copy(tmp_path / "b", "B")
    old = serve("--port", port, folder=a)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = open_page(ctx, old.local)
        shell = versions(page)
        modules = {f"{m}.js" for m in ("main", "protocol", "renderer", "input", "menu", "png", "install")}
        assert modules <= set(shell) and len(shell) >= len(modules) + 2 + 8, shell  # + css, html, shaders
        assert set(shell.values()) == {"A"}, shell
        wait_for_shell(page, shell_hash(old))
        old.stop()
        new = serve("--port", port, folder=b)  # an upgraded server
        page.reload()  # one reload: the new page, whole (from the network, the worker's
        synced(page, "frost.frames > 0")  # cache is A's)
        assert versions(page) == {**shell, **dict.fromkeys(shell, "B")}
        assert backdrop_pixel(page) == (1, 2, 3)
        wait_for_shell(page, shell_hash(new))  # the new worker's cache replaced A's
        new.stop()
        page.reload()  # and what opens without the server is B, whole
        page.wait_for_function(f"document.getElementById('status').textContent === '{ON_PHONE}' && "
                               "frost.frames > 0", timeout=60_000)
        assert versions(page) == dict.fromkeys(shell, "B")
        assert backdrop_pixel(page) == (1, 2, 3)
    finally:
        ctx.close()


def test_a_page_whose_token_was_replaced_says_so_and_its_app_opens_to_a_page_that_says_so(
        pw, serve, tmp_path):
    """The LAN server stopped and started again with `--new-token` on the same port: the
    open page's socket is refused (a browser learns only 1006, as from a server that is
    gone), and the page says that its token was replaced, and stops there: no retry. The
    installed app opened at its old address (its start_url, through its worker) shows the
    server's refusal as a page sized for the phone, saying the same; opened from the
    worker's cache (the server stopped), its socket is refused once a server is back, and
    it says so too."""
    port = str(free_port())
    old = serve("--port", port, "--host", "0.0.0.0", "--no-https", folder=tmp_path)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = open_page(ctx, old.local)
        wait_for_shell(page)
        old.stop()
        new = serve("--port", port, "--host", "0.0.0.0", "--no-https", "--new-token", folder=tmp_path)
        assert new.port == old.port and new.token != old.token
        page.wait_for_function("document.getElementById('status').textContent.includes('token')",
                               timeout=60_000)  # (reconnects back off up to 8 s apart)
        assert status(page) == "this page's link (its token) was replaced: scan the new QR code"
        # Stopped: no socket, none to come (a retry is a timer main.js keeps), no other word.
        assert page.evaluate("[frost.socket, frost.retry, frost.stopped]") == [None, None, True]
        assert page.evaluate("frost.local") is None  # (nor the phone's own frost, which ended)
        assert page.evaluate("window.frost.makeApp.shown") is None
        response = page.goto(old.local)  # the installed app opens its start_url
        assert response.status == 403
        assert page.evaluate("navigator.serviceWorker.controller !== null")  # (its worker's)
        said = page.inner_text("body")
        assert "token" in said and "replaced" in said and "QR code" in said, said
        # Sized for the phone (390 CSS px: without its viewport a phone lays a page out 980
        # wide and shrinks it) in type a person reads.
        assert page.evaluate("[innerWidth, document.documentElement.scrollWidth]") == [390, 390]
        size = "parseFloat(getComputedStyle(document.getElementById('refused')).fontSize)"
        assert page.evaluate(size) >= 16
        page.screenshot(path=str(tmp_path / "refused.png"))
        # Opened from the cache (no server), the app's socket is refused once one is back.
        new.stop()
        page.goto(old.local)
        page.wait_for_function(f"document.getElementById('status').textContent === '{ON_PHONE}' && "
                               "frost.frames > 0", timeout=60_000)
        back = serve("--port", port, "--host", "0.0.0.0", "--no-https", folder=tmp_path)
        assert back.token == new.token  # (kept)
        page.wait_for_function("document.getElementById('status').textContent.includes('token')",
                               timeout=60_000)
        assert page.evaluate("[frost.socket, frost.retry, frost.stopped]") == [None, None, True]
        # With the new token, the page again.
        page.goto(new.local)
        synced(page, "frost.frames > 0")
        assert status(page) == ""
    finally:
        ctx.close()


def test_a_page_without_a_token_refused_by_a_lan_server_says_the_servers_reason(pw, serve, browser,
                                                                                 tmp_path):
    """A page opened on loopback (no token) whose server comes back on the LAN (a token in
    force) on the same port: its socket and /meta are refused, and the status line says the
    server's own reason, once, and the page stops."""
    port = str(free_port())
    s = serve("--port", port, folder=tmp_path)
    context = browser.new_context(**PHONE)
    try:
        page = open_page(context, s.local)
        s.stop()
        lan = serve("--port", port, "--host", "0.0.0.0", "--no-https", folder=tmp_path)
        assert lan.token
        page.wait_for_function("frost.refused !== null", timeout=60_000)
        assert status(page) == "this server needs the token of the URL frost serve printed"
        assert page.evaluate("[frost.socket, frost.retry]") == [None, None]
    finally:
        context.close()
