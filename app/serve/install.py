"""The page as an installed app (docs/phone-design.md, Installing: the shell and its
worker): its web app manifest, built for each request (its addresses carry the request's
token), and its service worker,
`/sw.js`, the worker's code (app/web/sw.js) after a first line the server writes: the
page's shell (the files it caches) and a hash of their bytes, so that any change to the
page changes the worker's bytes, the browser installs it anew and the worker's cache (its
name carries the hash) is replaced whole. The page's own response says the hash it is of
(X-Frost-Shell): the worker serves its cache only to a page of the same hash."""

from __future__ import annotations

import asyncio
import hashlib
import json
from pathlib import Path

from aiohttp import web

from app.backdrops import BACKDROPS
from app.resources import ASSET_DIR, SHADER_DIR
from app.serve import routes
from app.serve.appkeys import FEED, TOKEN

WORKER = "sw.js"  # in the web folder: the worker's code, without its first line
HEADER = "X-Frost-Shell"  # the shell's hash, on the page's own response
NAME = "frost"
# The page's black, as index.html's theme-color
THEME, BACKGROUND = "#000000", "#000000"
# (purpose, size) -> file under the web folder (drawn by assets/make_icons.py)
ICONS = {("any", 192): "icons/icon-192.png", ("any", 512): "icons/icon-512.png",
         ("maskable", 192): "icons/maskable-192.png", ("maskable", 512): "icons/maskable-512.png"}


class Shell:
    """The files the worker caches: (address relative to the root, the file whose bytes it
    serves), and their hash, of the files as they are now (read at every ask: 25 files,
    0.3 MB, about 10 ms)."""

    def __init__(self, web_dir: Path, shader_dir: Path = SHADER_DIR, asset_dir: Path = ASSET_DIR):
        self.web_dir, self.shader_dir, self.asset_dir = web_dir, shader_dir, asset_dir

    def files(self) -> list[tuple[str, Path]]:
        """The shell: the page ("" is the root, index.html), every file of the web folder
        (its modules, CSS, icons) but the worker's code, the shader files, the built-in
        backdrops (their PNG as assets/ holds it; the server serves its pixels)."""
        found = [("", self.web_dir / "index.html")]
        for path in sorted(p for p in self.web_dir.rglob("*") if p.is_file()):
            rel = path.relative_to(self.web_dir).as_posix()
            hidden = any(part.startswith(".") or part == "__pycache__" for part in rel.split("/"))
            if rel not in (WORKER, "index.html") and not hidden:
                found.append((f"web/{rel}", path))
        found += [(f"shaders/{p.name}", p) for p in sorted(self.shader_dir.iterdir()) if p.is_file()]
        found += [(f"backdrops/{name}.png", self.asset_dir / file)
                  for name, (file, _) in BACKDROPS.items()]
        return found

    def digest(self) -> str:
        """The shell's hash (16 hex digits of SHA-256 over each address and its bytes)."""
        return shell_hash(self.files())

    def worker(self) -> bytes:
        """The worker's bytes: the shell and its hash, then the worker's code."""
        files = self.files()
        head = json.dumps({"hash": shell_hash(files), "files": [url for url, _ in files]})
        return f"const SHELL = {head};\n".encode() + (self.web_dir / WORKER).read_bytes()


def shell_hash(files: list[tuple[str, Path]]) -> str:
    """16 hex digits of SHA-256 over each (address, file)'s address, length and bytes (a
    missing file counts as empty)."""
    h = hashlib.sha256()
    for url, path in files:
        try:
            data = path.read_bytes()
        except OSError:
            data = b""
        h.update(f"{url}\0{len(data)}\0".encode())
        h.update(data)
    return h.hexdigest()[:16]


def manifest(token: str, static: bool = False) -> dict:
    """The web app manifest, every address with `token` (where one is in force). `static`:
    the static site's (`frost web`), whose addresses are all relative, so that it installs
    from wherever it is served (a sub-path such as /frost/ too)."""
    query = f"?token={token}" if token else ""
    root = "./" if static else "/"
    return {
        "name": NAME, "short_name": NAME, "id": root,
        "description": "Window frost that grows under your finger" + (
            "" if static else ", shared by every phone of frost serve"),
        "start_url": f"{root}{query}", "scope": root, "display": "standalone", "orientation": "any",
        "theme_color": THEME, "background_color": BACKGROUND,
        "icons": [{"src": f"web/{file}{query}", "sizes": f"{size}x{size}", "type": "image/png",
                   "purpose": purpose} for (purpose, size), file in ICONS.items()],
    }


def routes_for(app: web.Application, web_dir: Path) -> None:
    """The page (with its shell's hash), the manifest and the worker, on `app`."""
    shell = Shell(web_dir)
    page = routes.folder_files(web_dir, "index.html")

    async def index(request: web.Request) -> web.StreamResponse:
        response = await page(request)
        response.headers[HEADER] = await asyncio.to_thread(shell.digest)
        # The page opens its socket once its modules are in, and the socket waits for a
        # snapshot: drawn now, while the page loads, it is kept for the socket (as for any
        # page within REDRAW_GAP; the feed draws one at a time, and not again while a kept
        # one is that fresh). A page from its service worker's cache asks nothing here.
        feed = request.app.get(FEED)
        if feed is not None:
            feed.ask_redraw()
        return response

    async def manifest_file(request: web.Request) -> web.Response:
        return web.Response(text=json.dumps(manifest(request.app[TOKEN]), indent=1),
                            content_type="application/manifest+json",
                            headers={"Cache-Control": "no-cache"})

    async def worker(request: web.Request) -> web.Response:
        return web.Response(body=await asyncio.to_thread(shell.worker),
                            content_type="text/javascript", charset="utf-8",
                            headers={"Cache-Control": "no-cache"})

    app.router.add_get("/", index)
    app.router.add_get("/manifest.webmanifest", manifest_file)
    app.router.add_get("/sw.js", worker)
