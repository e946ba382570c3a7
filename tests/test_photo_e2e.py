"""A photo from the phone end to end: `frost serve` in a subprocess, two pages in headless
Chromium. One chooses a file through the menu's "Use a photo…" (the browser's file
chooser); the other shows it behind the frost. Oracles: the file's own colours (a picture
of four coloured quadrants), the photo the server kept as Pillow decodes it, /meta, and
what the second page held before."""

from __future__ import annotations

import io
import json
import os
import urllib.request

import numpy as np
import pytest
from PIL import Image
from test_phone_e2e import PROBLEM, grown, open_page, pause_and_settle, phones, pixels, tap  # noqa: F401, F811

from app import photos
from app.backdrops import load_backdrop
from sim.screen import HEIGHT, WIDTH

pytestmark = [pytest.mark.browser, pytest.mark.skipif(PROBLEM is not None, reason=str(PROBLEM))]

QUADRANTS = {(0.25, 0.25): (220, 30, 30), (0.75, 0.25): (30, 200, 40),
             (0.25, 0.75): (30, 40, 210), (0.75, 0.75): (240, 240, 240)}


def quadrant_photo(path, w: int = 1200, h: int = 1600) -> None:
    """A picture of four coloured quadrants (QUADRANTS) at `path`, as a phone's JPEG."""
    a = np.zeros((h, w, 3), np.uint8)
    for (fx, fy), colour in QUADRANTS.items():
        x0, y0 = int((fx - 0.25) * 2 * (w // 2)), int((fy - 0.25) * 2 * (h // 2))
        a[y0:y0 + h // 2, x0:x0 + w // 2] = colour
    Image.fromarray(a).save(path, "JPEG", quality=92)


def test_the_page_makes_a_photo_cover_the_pane_as_pillow_does(browser):
    """A wide picture (thirds of red, green, blue, and a gradient down it) becomes a JPEG
    covering the pane, centred: what Pillow's cover gives (the oracle), so the middle of
    the green third fills it, top to bottom, with no bar."""
    from app.images import cover
    from bench.page import Page, hello
    from sim import Params

    a = np.zeros((400, 1600, 3), np.uint8)
    for k, colour in enumerate(((220, 30, 30), (30, 200, 40), (30, 40, 210))):
        a[:, k * 533:(k + 1) * 533 + (k == 2)] = colour
    a[..., 2] = np.linspace(0, 255, 400, dtype=np.uint8)[:, None]
    png = io.BytesIO()
    Image.fromarray(a).save(png, "PNG")
    with Page(hello(Params.preset("fern")), [], browser=browser) as page:
        jpeg = page.page.evaluate("""async (bytes) => {
            const { paneJpeg } = await import('./web/photo.js');
            const blob = await paneJpeg(new Blob([new Uint8Array(bytes)], { type: 'image/png' }));
            return Array.from(new Uint8Array(await blob.arrayBuffer())); }""", list(png.getvalue()))
    got = np.asarray(Image.open(io.BytesIO(bytes(jpeg))).convert("RGB")).astype(int)
    want = np.asarray(cover(Image.fromarray(a), (WIDTH, HEIGHT))).astype(int)
    assert got.shape == want.shape == (HEIGHT, WIDTH, 3)
    assert np.abs(got - want).mean() < 6, np.abs(got - want).mean()


def choose(page, path) -> dict:
    """`path` chosen through the menu's "Use a photo…"; how the upload went."""
    before = page.evaluate("frost.photo.last")
    page.click("#open")
    with page.expect_file_chooser() as chooser:
        page.click("#photo")
    chooser.value.set_files(str(path))
    page.click("#open")
    page.wait_for_function(f"JSON.stringify(frost.photo.last) !== {json.dumps(json.dumps(before))}"
                           " && !frost.photo.sending", timeout=60_000)
    return page.evaluate("frost.photo.last")


def meta(s) -> dict:
    with urllib.request.urlopen(f"http://127.0.0.1:{s.port}/meta", timeout=30) as r:
        return json.loads(r.read())


def test_a_photo_chosen_on_one_page_is_behind_the_frost_on_another(serve, phones, tmp_path):  # noqa: F811
    s = serve("--look", "glass")
    a, b = phones(s.local), phones(s.local)
    tap(a, 380, 640)  # frost to see the photo through
    grown(a, 100)
    pause_and_settle([a, b])
    before = pixels(b)
    clear = (before == load_backdrop("dusk")).all(axis=2)  # no ice there
    assert clear.mean() > 0.5

    # A page named like a photo: the browser cannot decode it, the server says why; to
    # that page alone, and nothing changes.
    hostile = tmp_path / "holiday.jpg"
    hostile.write_bytes(b"<html><script>alert(1)</script></html>")
    last = choose(a, hostile)
    assert last["status"] == 415 and "not a PNG, JPEG or WebP" in last["error"]
    assert "not a PNG, JPEG or WebP" in a.inner_text("#status")
    assert b.inner_text("#status") == ""
    assert b.evaluate("frost.shownBackdrop") == "dusk" and np.array_equal(pixels(b), before)
    assert meta(s)["background"] == "dusk" and not (tmp_path / photos.FOLDER).exists()

    a.wait_for_timeout(photos_gap_ms())  # (one photo every 5 s from one address)
    good = tmp_path / "photo.jpg"
    quadrant_photo(good)
    last = choose(a, good)
    assert last["status"] == 200, last
    name = last["backdrop"]
    assert photos.is_photo(name) and last["bytes"] <= 1 << 20
    # (in the backdrop texture, which pixels() draws the pane with: no frame waited for)
    b.wait_for_function(f"frost.shownBackdrop === {json.dumps(name)}", timeout=30_000)
    after = pixels(b)
    # Away from the ice the second page shows the photo: its quadrants' colours, and the
    # file the server kept as Pillow decodes it (to a decoder's rounding).
    kept = load_backdrop(name, photos=tmp_path / photos.FOLDER).astype(int)
    for (fx, fy), colour in QUADRANTS.items():
        y, x = int(fy * HEIGHT), int(fx * WIDTH)
        patch = after[y - 20:y + 20, x - 20:x + 20][clear[y - 20:y + 20, x - 20:x + 20]]
        assert len(patch) > 100 and np.abs(np.median(patch, axis=0) - colour).max() < 20, (fx, fy)
    assert np.percentile(np.abs(after[clear].astype(int) - kept[clear]), 99) <= 3
    assert meta(s)["background"] == name
    assert a.evaluate("frost.shownBackdrop") == name
    labels = b.eval_on_selector("#backdrop", "s => [...s.options].map(o => o.text)")
    assert labels == ["dusk", "lockscreen", "photo 1"]
    # The frost refracts it: where there is ice the pane is not the bare photo.
    assert not np.array_equal(after[~clear], kept[~clear].astype(np.uint8))

    out = os.environ.get("FROST_PHOTO_SHOTS")  # to look at them: a folder outside the checkout
    for label, page in (("chooser", a), ("other", b)):
        shot = page.screenshot()
        Image.open(io.BytesIO(shot)).save(tmp_path / f"page-{label}.png")
        if out:
            Image.open(io.BytesIO(shot)).save(os.path.join(out, f"page-{label}.png"))


def photos_gap_ms() -> int:
    from app.serve.photo import MIN_GAP_S
    return int(MIN_GAP_S * 1000) + 300


def test_the_installed_pages_worker_never_answers_or_keeps_a_photo(pw, serve, tmp_path):
    from test_phone_install_e2e import persistent, wait_for_shell, worker_shell

    s = serve()
    good = tmp_path / "photo.jpg"
    quadrant_photo(good, 300, 400)
    ctx = persistent(pw, tmp_path / "profile")
    try:
        page = open_page(ctx, s.local)
        wait_for_shell(page)
        answered: list = []
        page.on("response", lambda r: "/backdrops/" in r.url and answered.append(
            (r.url, r.from_service_worker)))
        name = choose(page, good)["backdrop"]
        page.wait_for_function(f"frost.shownBackdrop === {json.dumps(name)}", timeout=30_000)
        photo = [by_worker for url, by_worker in answered if f"/backdrops/{name}.jpg" in url]
        assert photo == [False]  # from the server, past the worker
        kept = page.evaluate("""async () => {
            const [name] = (await caches.keys()).filter((n) => n.startsWith('frost-shell-'));
            return (await (await caches.open(name)).keys()).map((r) => new URL(r.url).pathname);
        }""")
        assert sorted(kept) == sorted(f"/{f}" for f in worker_shell(s)["files"])
        assert not [p for p in kept if p.startswith("/backdrops/photo") or p.endswith(".jpg")]
    finally:
        ctx.close()
