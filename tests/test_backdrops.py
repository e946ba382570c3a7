"""Backdrops: built-in by name or any image file, scaled to cover the screen and
centre-cropped; a bad one is refused in one line; the name rides in PNGs and sessions."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image
from support.cli import assert_refused_in_one_line, run_main

from app.backdrops import BACKDROPS, load_backdrop, next_backdrop
from sim.io.session import check_view

LIGHT = {"light": [0.0, 0.0, 1.0], "features": True, "bumps": True}


def test_a_wide_image_covers_the_height_and_keeps_its_centre(tmp_path):
    # 200 x 100: scaled by max(760 / 200, 1280 / 100) = 12.8 to 2560 x 1280, cropped to
    # x 900 ... 1660, i.e. columns 70.3 ... 129.7 of the original. Columns 0-79 red,
    # 80-119 green, 120-199 blue: 9.7 / 59.4 = 16 % red on the left, as much blue on the
    # right, green between.
    img = np.zeros((100, 200, 3), np.uint8)
    img[:, :80, 0], img[:, 80:120, 1], img[:, 120:, 2] = 255, 255, 255
    Image.fromarray(img).save(tmp_path / "wide.png")
    out = load_backdrop(str(tmp_path / "wide.png"))
    assert out.shape == (1280, 760, 3)
    row = out[640] > 128
    assert row[:, 0].mean() == pytest.approx(9.7 / 59.4, abs=0.01) and row[:120, 0].all()
    assert row[:, 2].mean() == pytest.approx(9.7 / 59.4, abs=0.01) and row[-120:, 2].all()
    assert (out[0] == out[-1]).all()  # the height fits exactly: nothing cropped there


def test_a_screen_sized_image_is_taken_as_it_is(tmp_path):
    img = np.random.default_rng(0).integers(0, 256, (1280, 760, 3), dtype=np.uint8)
    Image.fromarray(img).save(tmp_path / "same.png")
    np.testing.assert_array_equal(load_backdrop(str(tmp_path / "same.png")), img)


def test_builtins_load_and_the_key_cycles_them():
    for name in BACKDROPS:
        assert load_backdrop(name).shape == (1280, 760, 3)
    assert next_backdrop("dusk") == "lockscreen" and next_backdrop("lockscreen") == "dusk"
    assert next_backdrop("lockscreen", "me.jpg") == "me.jpg"
    assert next_backdrop("me.jpg", "me.jpg") == "dusk"


@pytest.mark.parametrize("what", ["missing", "garbage", "empty"])
def test_a_bad_background_is_one_line_and_status_2(tmp_path, what):
    path = tmp_path / "bg.jpg"
    if what != "missing":
        path.write_bytes(b"" if what == "empty" else b"not an image at all")
    for command in (["render", "--ticks", "1"], ["figure8", str(tmp_path / "f.png")],
                    ["bench", "render"]):
        status, err = run_main([*command, "--background", str(path)])
        assert_refused_in_one_line(status, err, "background")
    assert list(tmp_path.iterdir()) == ([] if what == "missing" else [path])


def test_the_background_rides_in_the_png_and_a_replay_shows_it(tmp_path):
    out = tmp_path / "f.png"
    status, err = run_main(["render", "--touch", "380,640", "--ticks", "3", "--background",
                            "lockscreen", "--out", str(out)])
    assert status == 0, err
    view = json.loads(Image.open(out).info["view"])
    assert view["background"] == "lockscreen"
    assert check_view(view) == view


def test_check_view_takes_old_views_and_refuses_a_bad_background():
    assert check_view(LIGHT) == LIGHT  # no background: the default (dusk)
    for bad in (3, "", None, ["dusk"]):
        with pytest.raises(ValueError, match="background"):
            check_view({**LIGHT, "background": bad})


def test_a_session_whose_background_is_gone_is_refused_before_replaying(tmp_path):
    # Headless: the one-line error, status 2. Windowed: the same SessionError before the
    # window opens (the window's set-up is not reached, so no display is needed here).
    from argparse import Namespace

    from app.cli.commands import _windowed_replay
    from sim.io.session import SessionError, SessionLog

    log_ = SessionLog(0, {}, view={**LIGHT, "background": str(tmp_path / "gone.png")})
    path = log_.save(tmp_path / "s.json")
    status, err = run_main(["replay", str(path), "--out", str(tmp_path / "o.png")])
    assert_refused_in_one_line(status, err, "gone.png")
    with pytest.raises(SessionError, match="gone.png"):
        _windowed_replay(Namespace(replay=str(path), background=None))
    assert _windowed_replay(Namespace(replay=str(path), background="dusk")) is not None


@pytest.mark.parametrize("argv, look", [(["--preset", "c-2"], "paper"), (["--preset", "fern"], "glass"),
                                        (["--preset", "c-2", "--look", "glass"], "glass"),
                                        (["--preset", "window", "--look", "paper"], "paper")])
def test_the_look_comes_from_the_preset_or_look_and_rides_in_the_png(tmp_path, argv, look):
    out = tmp_path / "f.png"
    status, err = run_main(["render", *argv, "--touch", "380,640", "--ticks", "2", "--out", str(out)])
    assert status == 0, err
    assert json.loads(Image.open(out).info["parameters"])["look"] == look
