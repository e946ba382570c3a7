"""A session records the backdrop it shows (version 11's "backdrop" events), a photo's
included: the thread records each change at its tick, a file checks them, a replay draws
each backdrop from its tick on (photos found beside the session file) or says which file
is missing, and a photo dropped on the window is kept and recorded."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app import photos
from sim import Params
from sim.io.session import SessionError, SessionLog

ROOT = Path(__file__).resolve().parent.parent
PARAMS = Params.preset("fern")


def photo_bytes(colour=(200, 30, 160)) -> bytes:
    out = io.BytesIO()
    Image.new("RGB", (380, 640), colour).save(out, "PNG")
    return out.getvalue()


def session(events, version=11, **extra) -> dict:
    return {"format": "frost-session", "version": version, "seed": 3,
            "params": PARAMS.as_dict(), "events": events, "steps": 40, **extra}


# ---- the file ------------------------------------------------------------------------

def test_backdrop_events_need_version_11_and_a_backdrops_name():
    ok = [{"kind": "touch", "tick": 0, "x": 380.0, "y": 640.0},
          {"kind": "backdrop", "tick": 5, "name": "photo-" + "a" * 32},
          {"kind": "backdrop", "tick": 9, "name": "lockscreen"}]
    assert SessionLog.from_json(session(ok)).events[1]["name"] == "photo-" + "a" * 32
    with pytest.raises(SessionError, match="a backdrop event needs version 11 or later "
                                           r"\(this file is version 10\)"):
        SessionLog.from_json(session(ok, version=10))
    for name in ("/etc/passwd", "../x", "", "a" * 65, "dusk\n", 7, None):
        bad = [{"kind": "backdrop", "tick": 0, "name": name}]
        with pytest.raises(SessionError, match="'name' must be a backdrop's name"):
            SessionLog.from_json(session(bad))
    # a session of backdrop changes alone has nothing to replay (no file is written)
    only = SessionLog.from_json(session([{"kind": "backdrop", "tick": 0, "name": "dusk"}]))
    assert not only.replayable()


# ---- the thread ----------------------------------------------------------------------

def backdrop_events(thread):
    return [(e["tick"], e["name"]) for e in thread.timeline.events if e["kind"] == "backdrop"]


def test_the_thread_records_each_backdrop_change_at_its_tick():
    from app.simthread.thread import SimThread

    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    thread.show_backdrop("dusk")  # the default, shown from the start: nothing to record
    thread.tick()
    assert backdrop_events(thread) == [] and thread.drain()[-1].backdrop is None
    for _ in range(3):
        thread.tick()
    thread.show_backdrop("lockscreen")
    thread.show_backdrop("lockscreen")  # (the same again: one event)
    thread.tick()
    thread.tick()
    thread.show_backdrop("photo-" + "b" * 32)
    thread.tick()
    snaps = thread.drain()
    assert backdrop_events(thread) == [(4, "lockscreen"), (6, "photo-" + "b" * 32)]
    assert [s.backdrop for s in snaps] == [None] * 3 + ["lockscreen"] * 2 + ["photo-" + "b" * 32]
    saved = SessionLog.from_json(json.loads(json.dumps(thread.session().as_json())))
    assert backdrop_events(type("T", (), {"timeline": saved})()) == backdrop_events(thread)


def test_an_older_version_replayed_shows_but_does_not_record_its_backdrop():
    from app.simthread.thread import SimThread

    thread = SimThread(PARAMS, 1, [(380.0, 640.0)], version=10)
    thread.show_backdrop("lockscreen")
    thread.tick()
    assert thread.drain()[-1].backdrop == "lockscreen"
    assert backdrop_events(thread) == []
    SessionLog.from_json(thread.session().as_json())  # (and it is still a valid version 10)


@pytest.mark.parametrize("path", ["{tmp}/mine.png", "cwdpic"])
def test_a_file_given_by_path_is_shown_and_not_recorded(tmp_path, path):
    from app.simthread.thread import SimThread

    path = path.format(tmp=tmp_path)  # ("cwdpic": a file of the working folder, name-like)
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    thread.show_backdrop(path)
    thread.tick()
    assert thread.drain()[-1].backdrop == path
    assert backdrop_events(thread) == []


@pytest.mark.usefixtures("subprocesses")
def test_a_replay_never_takes_a_backdrops_name_as_a_path(tmp_path):
    (tmp_path / "cwdpic").write_bytes(photo_bytes())  # (a picture a name could reach)
    path = tmp_path / "s.json"
    path.write_text(json.dumps(session([{"kind": "touch", "tick": 0, "x": 200.0, "y": 300.0},
                                        {"kind": "backdrop", "tick": 3, "name": "cwdpic"}])),
                    encoding="utf-8")
    done = subprocess.run([sys.executable, "-m", "app", "replay", str(path), "--out",
                           str(tmp_path / "out.png")], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "backdrop cwdpic: neither a built-in" in lines[0]
    assert not (tmp_path / "out.png").exists()


# ---- the replay ----------------------------------------------------------------------

def frames(ctx, log, steps, background=None, store=None):
    from app.tools.replay import replay_offscreen

    off = replay_offscreen(ctx, log, steps, background=background, photos=store)
    try:
        return off.frame()
    finally:
        off.release()


@pytest.mark.gl
def test_a_replay_shows_each_backdrop_from_its_tick(gl_ctx, tmp_path):
    store = photos.store_of(tmp_path)
    name = photos.keep(photo_bytes(), store)
    log = SessionLog.from_json(session(
        [{"kind": "touch", "tick": 0, "x": 380.0, "y": 640.0},
         {"kind": "backdrop", "tick": 10, "name": "lockscreen"},
         {"kind": "backdrop", "tick": 25, "name": name}],
        view={"light": [0.3, 0.5, 1.0], "features": True, "bumps": True, "background": name}))
    # the oracle: the same frost with one backdrop imposed throughout
    for steps, shown in ((8, "dusk"), (20, "lockscreen"), (40, name)):
        replayed = frames(gl_ctx, log, steps, store=store)
        imposed = frames(gl_ctx, log, steps, background=shown, store=store)
        assert np.array_equal(replayed, imposed), (steps, shown)
    # and the three differ (the oracle would pass a replay that ignored them otherwise)
    assert not np.array_equal(frames(gl_ctx, log, 8, background="lockscreen", store=store),
                              frames(gl_ctx, log, 8, background=name, store=store))


def run_replay(tmp_path, path, *more):
    return subprocess.run([sys.executable, "-m", "app", "replay", str(path), "--out",
                           str(tmp_path / "out.png"), *more], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)


@pytest.mark.usefixtures("subprocesses")
def test_frost_replay_draws_the_photo_kept_beside_the_session(tmp_path):
    store = photos.store_of(tmp_path)
    name = photos.keep(photo_bytes(), store)
    path = tmp_path / "s.json"
    path.write_text(json.dumps(session(
        [{"kind": "backdrop", "tick": 0, "name": name},
         {"kind": "touch", "tick": 0, "x": 200.0, "y": 300.0}], )), encoding="utf-8")
    done = run_replay(tmp_path, path)
    assert done.returncode == 0, done.stderr
    out = np.asarray(Image.open(tmp_path / "out.png").convert("RGB")).astype(int)
    # far from the one seed, the glass shows the photo's colour (refracted, lit: near it)
    corner = out[1200:1260, 680:740].reshape(-1, 3).mean(axis=0)
    assert np.abs(corner - (200, 30, 160)).max() < 40, corner
    # the photo gone: one line naming the file, exit 2, no picture
    photos.photo_file(name, store).unlink()
    (tmp_path / "out.png").unlink()
    done = run_replay(tmp_path, path)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and f"backdrop {name}: its file" in lines[0] and "is missing" in lines[0]
    assert str(photos.photo_file(name, store)) in lines[0]
    assert not (tmp_path / "out.png").exists()
    # ...unless a backdrop is imposed
    assert run_replay(tmp_path, path, "--background", "dusk").returncode == 0


# ---- a photo dropped on the window ---------------------------------------------------

class _Notes:
    def __init__(self, thread):
        self.thread = thread

    def said(self):
        out = []
        while not self.thread.notices.empty():
            out.append(self.thread.notices.get()[1])
        return out


def dropped(drop, paths):
    drop.on_drop(None, [str(p) for p in paths])
    deadline = time.monotonic() + 60
    while drop.worker is not None and drop.worker.is_alive() and time.monotonic() < deadline:
        drop.worker.join(0.1)


def test_a_photo_dropped_on_the_window_is_kept_recorded_and_shown(tmp_path):
    from app.simthread.thread import SimThread
    from app.window.drop import PhotoDrop

    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    store = photos.store_of(tmp_path / "sessions")
    drop = PhotoDrop(thread, store)
    notes = _Notes(thread)
    (tmp_path / "holiday.JPG").write_bytes(photo_bytes())  # a PNG, whatever its name says
    (tmp_path / "notes.txt").write_text("not a photo", encoding="utf-8")
    dropped(drop, [tmp_path / "notes.txt"])
    thread.tick()
    assert backdrop_events(thread) == [] and not store.exists()
    assert any("notes.txt: refused: not a PNG, JPEG or WebP" in n for n in notes.said())
    dropped(drop, [tmp_path / "holiday.JPG", tmp_path / "notes.txt"])
    thread.tick()
    (name,) = [p.stem for p in store.iterdir()]
    assert backdrop_events(thread) == [(1, "photo-" + name)]
    assert thread.drain()[-1].backdrop == "photo-" + name
    said = notes.said()
    assert any("2 files dropped: the first taken" in n for n in said)
    assert any(f"the photo holiday.JPG (photo-{name})" in n for n in said)
    dropped(drop, [tmp_path / "nowhere.png"])
    assert any("nowhere.png: refused: " in n and "cannot read it" in n for n in notes.said())


def test_a_drop_whose_reading_fails_unexpectedly_is_said_not_lost(tmp_path, monkeypatch):
    from app.simthread.thread import SimThread
    from app.window import drop as drop_module

    def broken(_data, _store):
        raise RuntimeError("a decoder's bug")

    monkeypatch.setattr(drop_module, "keep", broken)
    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    drop = drop_module.PhotoDrop(thread, photos.store_of(tmp_path))
    (tmp_path / "a.png").write_bytes(photo_bytes())
    dropped(drop, [tmp_path / "a.png"])
    assert any("a.png: refused: a decoder's bug" in n for n in _Notes(thread).said())
    dropped(drop, [tmp_path / "a.png"])  # (and the next drop is taken as the first)
    assert any("a.png: refused" in n for n in _Notes(thread).said())


# ---- the window follows the backdrop the thread says ---------------------------------

class _Renderer:
    """The renderer's backdrop alone: a photo named "photo-" and zeros is missing."""

    def __init__(self):
        self.backdrop, self.shown = "dusk", []

    def set_backdrop(self, name):
        if name == "photo-" + "0" * 32:
            raise ValueError(f"backdrop {name}: its file x.jpg is missing")
        self.backdrop = name
        self.shown.append(name)


def test_the_window_follows_a_photo_the_thread_shows_and_cycles_it_with_x():
    import glfw

    from app.simthread.thread import SimThread
    from app.window.actions import Actions
    from app.window.status import Status

    thread, status, renderer = SimThread(PARAMS, 0, [(380, 640)]), Status(), _Renderer()
    presenter = type("P", (), {"renderer": renderer})()
    actions = Actions(PARAMS, thread, presenter, status, None, None, lambda: None,
                      lambda: None, lambda: None)

    def tick_and_follow():
        thread.tick()
        snap = thread.drain()[-1]
        return actions.follow_backdrop(snap.backdrop, snap.stats.handled), snap

    def x():
        actions.on_key(None, glfw.KEY_X, 0, glfw.PRESS, 0)

    photo = "photo-" + "c" * 32
    x()  # dusk -> lockscreen, at once in the window
    assert renderer.backdrop == "lockscreen"
    thread.show_backdrop(photo)  # a page's photo (or a drop) after it, in the same tick
    followed, _ = tick_and_follow()
    assert followed and renderer.backdrop == photo
    assert backdrop_events(thread) == [(0, "lockscreen"), (0, photo)]
    # the photo joins X's cycle: lockscreen -> dusk -> ... -> the photo again
    seen = []
    for _ in range(3):
        x()
        seen.append(renderer.backdrop)
        tick_and_follow()
        assert renderer.backdrop == seen[-1]  # (the window's own choice is not undone)
    assert seen == ["dusk", "lockscreen", photo]
    # a snapshot from before the window's last choice is not followed
    x()
    assert renderer.backdrop == "dusk"
    assert not actions.follow_backdrop(photo, thread.handled)
    assert renderer.backdrop == "dusk"
    # a photo whose file is gone: said once, the backdrop kept
    thread.show_backdrop("photo-" + "0" * 32)
    for _ in range(3):
        _, snap = tick_and_follow()
    assert renderer.backdrop == "dusk"
    lines = status.lines(time.monotonic(), snap, PARAMS, _View, None, 1.0)
    assert sum("x.jpg is missing" in line for line in lines) == 1


_View = type("View", (), {"show_features": True, "show_bumps": False, "light": (0.0, 0.0, 1.0)})()


# ---- frost serve --window: the window's choice becomes every page's ------------------

def test_the_pages_follow_the_windows_backdrop_but_not_past_their_own_choice(tmp_path):
    from app.serve.feed import Feed
    from app.simthread.thread import SimThread

    thread = SimThread(PARAMS, 1, [(380.0, 640.0)])
    feed = Feed(PARAMS, 1, thread=thread)  # (the window's thread: frost serve --window)
    feed.controls.store = store = photos.store_of(tmp_path)

    def tick():
        thread.tick()
        for snap in thread.drain():
            feed._publish(snap)

    thread.show_backdrop("lockscreen")  # the window's X key
    tick()
    assert feed.controls.backdrop == "lockscreen" and feed.state()["backdrop"] == "lockscreen"
    name = photos.keep(photo_bytes(), store)
    thread.show_backdrop(name)  # a file dropped on the window: every page shows it, and
    tick()                      # may choose it again from the list
    assert feed.controls.backdrop == name and feed.state()["backdrops"][-1] == name
    thread.show_backdrop(str(tmp_path / "mine.png"))  # a path: the pages cannot load it
    tick()
    assert feed.controls.backdrop == name
    # the window chose the lock screen, and a page dusk while the tick that applied the
    # window's was on its way to the feed: that tick's snapshot is older than the page's
    # choice, and the pages keep dusk (never flicking back to the lock screen)
    thread.show_backdrop("lockscreen")
    thread.tick()
    older = thread.drain()
    feed.controls._backdrop("dusk")
    for snap in older:
        feed._publish(snap)
    assert feed.controls.backdrop == "dusk"
    tick()
    assert feed.controls.backdrop == "dusk" and thread.backdrop == "dusk"


# ---- a photo sent from a page, then replayed -----------------------------------------

@pytest.mark.usefixtures("subprocesses")
def test_a_served_sessions_photo_is_drawn_by_frost_replay(tmp_path):
    import asyncio

    import aiohttp
    from support.page_model import read_until
    from support.photos import page, run, upload

    saved = tmp_path / "session.json"

    async def test(port, _runner, feed, _store):
        async with aiohttp.ClientSession() as session:
            ws, model = await page(session, port)
            await ws.send_json({"type": "touch", "x": 200, "y": 300})
            await read_until(ws, model, lambda: model.tick >= 5)
            status, _, body = await upload(port, photo_bytes((30, 200, 90)))
            assert status == 200, body
            name = json.loads(body)["backdrop"]
            await read_until(ws, model, lambda: model.state("backdrop") == name)
            for _ in range(100):  # (the thread records it at its next tick)
                if feed.thread.backdrop == name:
                    break
                await asyncio.sleep(0.05)
            await ws.close()
        # the session as frost serve writes it, beside its photos' folder
        log = feed.thread.session()
        assert [e["name"] for e in log.events if e["kind"] == "backdrop"] == [name]
        log.save(saved)
    run(test, tmp_path)
    done = run_replay(tmp_path, saved)
    assert done.returncode == 0, done.stderr
    out = np.asarray(Image.open(tmp_path / "out.png").convert("RGB")).astype(int)
    corner = out[1200:1260, 680:740].reshape(-1, 3).mean(axis=0)
    assert np.abs(corner - (30, 200, 90)).max() < 40, corner
