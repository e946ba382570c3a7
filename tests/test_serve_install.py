"""The page as an installed app, the server's side (app/serve/install.py): the shell the
worker caches holds every file the page loads, its hash changes whenever one of them
changes (and only then), the worker's bytes carry it, the manifest keeps the token, and
the icons are what assets/make_icons.py draws."""

from __future__ import annotations

import asyncio
import importlib.util
import io
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from aiohttp.test_utils import TestClient, TestServer
from PIL import Image

from app.backdrops import BACKDROPS
from app.resources import ASSET_DIR, SHADER_DIR, WEB_DIR
from app.serve.feed import Feed
from app.serve.install import HEADER, ICONS, Shell
from app.serve.server import make_app
from sim import Params

ROOT = Path(__file__).resolve().parent.parent


def _icons_script():
    spec = importlib.util.spec_from_file_location("make_icons", ROOT / "assets" / "make_icons.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def copy(tmp_path) -> Shell:
    """A shell of copies of the page's, shaders' and backdrops' folders."""
    for folder in (WEB_DIR, SHADER_DIR, ASSET_DIR):
        shutil.copytree(folder, tmp_path / folder.name, ignore=shutil.ignore_patterns("__pycache__"))
    return Shell(tmp_path / WEB_DIR.name, tmp_path / SHADER_DIR.name, tmp_path / ASSET_DIR.name)


def test_the_shell_holds_every_file_the_page_loads():
    urls = {url for url, _ in Shell(WEB_DIR).files()}
    html = (WEB_DIR / "index.html").read_text(encoding="utf-8")
    modules = json.loads(re.search(r"const MODULES = (\[.*?\]);", html).group(1))
    shaders = json.loads(re.search(r"export const SHADERS = (\[.*?\]);",
                                   (WEB_DIR / "programs.js").read_text(encoding="utf-8"), re.S).group(1))
    wanted = {"", "web/page.css", *(f"web/{m}.js" for m in modules), *(f"shaders/{s}" for s in shaders),
              *(f"backdrops/{b}.png" for b in BACKDROPS), *(f"web/{f}" for f in ICONS.values())}
    assert wanted - urls == set()
    assert "web/sw.js" not in urls  # the worker is never its own cache's


def test_the_hash_changes_when_any_shell_file_changes_and_only_then(copy):
    first = copy.digest()
    files = copy.files()
    assert len(files) > 20
    for url, path in files:
        data = path.read_bytes()
        path.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))  # one bit of its last byte
        changed = copy.digest()
        path.write_bytes(data)
        assert changed != first, url
        assert copy.digest() == first, url  # the same bytes again: the same hash
    new = copy.web_dir / "extra.js"
    new.write_text("export const x = 1;\n", encoding="utf-8")  # a new module is in the shell too
    assert copy.digest() != first
    new.unlink()
    assert copy.digest() == first


def test_the_hash_changes_when_a_shell_file_is_renamed_with_the_same_bytes(copy):
    """A file's address is part of the shell: the same bytes under another name (a module
    renamed, that index.html asks for by its new name) are another shell."""
    first, contents = copy.digest(), [path.read_bytes() for _, path in copy.files()]
    (copy.web_dir / "fit.js").rename(copy.web_dir / "fitted.js")
    # (the same bytes in the same order: only an address differs)
    assert [path.read_bytes() for _, path in copy.files()] == contents
    assert "web/fitted.js" in dict(copy.files())
    assert copy.digest() != first


def test_the_worker_carries_the_hash_and_the_shell(copy):
    body = copy.worker().decode()
    head, code = body.split("\n", 1)
    shell = json.loads(head.removeprefix("const SHELL = ").removesuffix(";"))
    assert shell == {"hash": copy.digest(), "files": [url for url, _ in copy.files()]}
    assert code == (copy.web_dir / "sw.js").read_text(encoding="utf-8")
    (copy.web_dir / "page.css").write_text("body { color: red; }\n", encoding="utf-8")
    assert copy.worker() != body.encode()  # a changed page: the browser installs the worker anew


def _serve(test, token=None, web_dir=WEB_DIR):
    async def main():
        async with TestClient(TestServer(make_app(Feed(Params.preset("c-2"), seed=1), token,
                                                  web_dir=web_dir))) as client:
            await test(client)
    asyncio.run(main())


def test_the_manifest_keeps_the_token_and_every_app_file_needs_it():
    async def test(client):
        for path in ("/sw.js", "/manifest.webmanifest", "/web/icons/icon-192.png", "/web/install.js", "/"):
            assert (await client.get(path)).status == 403, path
            assert (await client.get(path + "?token=wrong")).status == 403, path
            assert (await client.get(path + "?token=s3cret")).status == 200, path
        resp = await client.get("/manifest.webmanifest?token=s3cret")
        assert resp.content_type == "application/manifest+json"
        m = json.loads(await resp.text())
        assert m["start_url"] == "/?token=s3cret" and m["scope"] == "/"
        assert (m["name"], m["display"], m["orientation"]) == ("frost", "standalone", "any")
        assert {"short_name", "theme_color", "background_color"} <= set(m)
        assert {i["purpose"] for i in m["icons"]} == {"any", "maskable"}
        for icon in m["icons"]:
            assert icon["src"].endswith("?token=s3cret")
            resp = await client.get("/" + icon["src"])
            assert resp.status == 200 and resp.content_type == "image/png", icon
            with Image.open(io.BytesIO(await resp.read())) as im:
                assert f"{im.width}x{im.height}" == icon["sizes"], icon
        worker = await client.get("/sw.js?token=s3cret")
        assert worker.content_type == "text/javascript"
        shell = json.loads((await worker.text()).split("\n", 1)[0][len("const SHELL = "):-1])
        page = await client.get("/?token=s3cret")
        assert page.headers[HEADER] == shell["hash"]  # the page says the shell it is of
    _serve(test, token="s3cret")


def test_without_a_token_the_start_url_is_the_root(tmp_path):
    async def test(client):
        m = json.loads(await (await client.get("/manifest.webmanifest")).text())
        assert m["start_url"] == "/" and all("token" not in i["src"] for i in m["icons"])
        before = (await client.get("/")).headers[HEADER]
        main_js = web / "main.js"
        main_js.write_text(main_js.read_text(encoding="utf-8") + "\n// changed\n", encoding="utf-8")
        assert (await client.get("/")).headers[HEADER] != before  # read again, while it runs
    web = tmp_path / "web"
    shutil.copytree(WEB_DIR, web)
    _serve(test, web_dir=web)


@pytest.mark.parametrize("purpose,size", list(ICONS))
def test_the_icons_are_what_the_script_draws(purpose, size):
    drawn = np.asarray(_icons_script().make(purpose, size)).astype(int)
    with Image.open(WEB_DIR / ICONS[purpose, size]) as im:
        kept = np.asarray(im).astype(int)
    assert kept.shape == drawn.shape
    # (one level of rounding where another machine's floating point differs)
    assert np.abs(kept - drawn).max() <= 1, "run: python3 assets/make_icons.py"


def test_the_maskable_flake_lies_inside_the_safe_zone():
    icons = _icons_script()
    for size in (192, 512):
        image = np.asarray(icons.make("maskable", size)).astype(int)
        yy, xx = np.mgrid[0:size, 0:size] + 0.5
        outside = np.hypot(xx - size / 2, yy - size / 2) > 0.4 * size
        assert (image[outside] == icons.NIGHT).all()  # only the background beyond 40 %
        assert (image[~outside] == icons.ICE).all(axis=1).mean() > 0.05  # the flake within
        assert image.shape == (size, size, 3)  # opaque: a launcher's mask cuts it


def test_the_flake_has_six_arms():
    # Six-fold: turned by 60 degrees it is itself (up to resampling); by 30 it is not.
    flake = Image.fromarray((_icons_script().flake_coverage(512, 0.37, 0.05) * 255).astype(np.uint8))
    base = np.asarray(flake, float)
    turned = {a: np.abs(np.asarray(flake.rotate(a, Image.Resampling.BILINEAR), float) - base).mean()
              for a in (60, 120, 30, 90)}
    assert turned[60] < 2 and turned[120] < 2, turned
    assert turned[30] > 10 and turned[90] > 10, turned


def test_the_any_icons_corners_are_clear_and_its_centre_is_ice():
    image = np.asarray(_icons_script().make("any", 512))
    assert image[0, 0, 3] == 0 and image[-1, -1, 3] == 0
    assert tuple(image[256, 256]) == (*_icons_script().ICE, 255)
