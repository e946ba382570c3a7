"""`frost web DIR` (docs/phone.md, Without a computer): the phone page as a static site that
any static web server serves as it is, at its root or under a sub-path (/frost/).

The site holds the page `frost serve` serves, file for file at the same addresses
(index.html, web/ with its modules, the page's own simulation and its parameters, the
icons; shaders/; the built-in backdrops as backdrops/NAME.png), and what the server made
at each request made once: the web app manifest with relative addresses, and sw.js, the
service worker with its first line (the shell's files and hash, as app.serve.install
writes it) naming the site's version file. Its own files are site.js (the page has no
server: it grows its frost at once; the weather APIs it asks itself) and version.json
(`{"build": HASH}`, the shell's hash: the worker compares it, as frost serve's page's
X-Frost-Shell header, so that a new build replaces the old one after one reload, whole).
A site built again replaces the old one in DIR at once (built beside it, then swapped)."""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
from pathlib import Path

from app.resources import WEB_DIR
from app.serve.install import WORKER, Shell, manifest, shell_hash
from app.serve.routes import backdrop_png
from sim import Params
from sim.io.files import one_line

SITE_MODULE = "web/site.js"  # the page's own word on how it was served
VERSION = "version.json"  # the build's hash, for the service worker
MARKS = (VERSION, WORKER, "index.html")  # what a folder frost web wrote holds


def site_module(weather_api: str, geocoding_api: str) -> bytes:
    """site.js of the static site: no server; the weather APIs the page asks itself."""
    site = {"static": True, "weather_api": weather_api, "geocoding_api": geocoding_api}
    return ("// How the page was served: as a static site, by `frost web` (app/tools/web_site.py).\n"
            f"export const SITE = {json.dumps(site)};\n").encode()


def site_files(weather_api: str, geocoding_api: str, web_dir: Path = WEB_DIR) -> list[tuple[str, bytes]]:
    """The shell's files as the site holds them: (address, bytes), the page first."""
    files = []
    for url, path in Shell(web_dir).files():
        if url == SITE_MODULE:
            data = site_module(weather_api, geocoding_api)
        elif url.startswith("backdrops/"):
            data = backdrop_png(url.removeprefix("backdrops/").removesuffix(".png"))
        else:
            data = path.read_bytes()
        files.append((url, data))
    return files


def write_site(folder: Path, weather_api: str, geocoding_api: str, web_dir: Path = WEB_DIR) -> int:
    """Every file of the site into `folder` (new, empty); how many bytes in all."""
    files = site_files(weather_api, geocoding_api, web_dir)
    for url, data in files:
        path = folder / (url or "index.html")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    digest = shell_hash([(url, folder / (url or "index.html")) for url, _ in files])
    head = json.dumps({"hash": digest, "files": [url for url, _ in files], "version": VERSION})
    extra = {WORKER: f"const SHELL = {head};\n".encode() + (web_dir / WORKER).read_bytes(),
             VERSION: json.dumps({"build": digest}).encode() + b"\n",
             "manifest.webmanifest": json.dumps(manifest("", static=True), indent=1).encode()}
    for name, data in extra.items():
        (folder / name).write_bytes(data)
    return sum(len(d) for _, d in files) + sum(len(d) for d in extra.values())


def folder_problem(folder: Path) -> str | None:
    """Why the site cannot go into `folder`: a folder with files that frost web did not
    write (a build replaces what is there, so it must be a site of its own)."""
    if not folder.is_dir():
        return None
    names = {p.name for p in folder.iterdir()}
    if names and not all(m in names for m in MARKS):
        return "is not empty and holds no site of frost web (it would be replaced): " \
               "choose an empty or new folder"
    return None


def build(folder: Path, weather_api: str, geocoding_api: str, web_dir: Path = WEB_DIR) -> int:
    """The site of the page in `web_dir` into `folder` (made, or replaced whole); its size
    in bytes."""
    target = Path(os.path.realpath(folder))
    target.parent.mkdir(parents=True, exist_ok=True)
    new = target.parent / f".{target.name}.new-{os.getpid()}"
    old = target.parent / f".{target.name}.old-{os.getpid()}"
    shutil.rmtree(new, ignore_errors=True)
    new.mkdir()
    try:
        size = write_site(new, weather_api, geocoding_api, web_dir)
        if target.exists():
            target.rename(old)
        new.rename(target)
    finally:
        shutil.rmtree(new, ignore_errors=True)
        shutil.rmtree(old, ignore_errors=True)
    return size


def run(args: argparse.Namespace, params: Params) -> int:
    """frost web DIR: one line on what it wrote, or why not (exit status 2)."""
    folder = Path(args.site_dir)
    problem = folder_problem(folder)
    try:
        size = None if problem else build(folder, args.weather_api, args.geocoding_api)
    except OSError as err:
        problem = err.strerror or str(err)
    if problem or size is None:
        print(f"frost: error: {one_line(str(folder))}: {problem} (see frost web --help)", file=sys.stderr)
        return 2
    print(f"frost web: wrote the static site to {one_line(str(folder))} ({size / 1e6:.1f} MB): "
          "any static web server serves it as it is, at its root or under a sub-path")
    return 0
