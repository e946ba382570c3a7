"""The tuning panel without a window: its widgets against Params' own fields and checks,
a slider dragged with ImGui's input queue (no GL: the draw lists are built, not drawn),
the panel's changes through the keys' path into a real simulation thread's session, and
parameter sets on disk and on the command line."""

from __future__ import annotations

import dataclasses
import json
import types

import glfw
import numpy as np
import pytest
from imgui_bundle import imgui
from PIL import Image

from app.cli import main
from app.simthread.thread import SimThread
from app.window.actions import Actions
from app.window.panel import BUTTONS, FIELDS, GROUPS, SPECS, TuningPanel, tooltip, why_off
from sim import Params, tuning
from sim.io.paramsets import ParamsFileError, load_params, save_params
from sim.io.session import SessionLog
from sim.params import _validate

LOOKS = {"paper": Params(), "fern": Params.preset("fern"), "window": Params.preset("window"),
         "c-2": Params.preset("c-2")}


# ---- the widgets against Params --------------------------------------------------------


def test_every_parameter_has_one_widget_in_one_group():
    listed = [name for names in GROUPS.values() for name in names]
    assert sorted(listed) == sorted(f.name for f in dataclasses.fields(Params))


@pytest.mark.parametrize("name", [n for n, s in SPECS.items() if s.kind == "slider"])
def test_a_sliders_ends_are_values_params_accepts_and_its_range_is_the_fields(name):
    f, s = FIELDS[name], SPECS[name]
    for end in (s.lo, s.hi):
        _validate(f, int(end) if s.whole else float(end))  # raises if Params would refuse it
    meta = f.metadata
    assert s.hi == meta["hi"]
    assert s.lo == meta["lo"] if not meta["lo_open"] else meta["lo"] < s.lo < meta["hi"] / 100
    assert s.whole == isinstance(f.default, int)


@pytest.mark.parametrize("name", list(FIELDS))
def test_a_tooltip_is_the_fields_help_its_range_and_the_presets_value(name):
    f = FIELDS[name]
    text = tooltip(f, "window")
    assert text.startswith(f.metadata["doc"] + "\n")
    value = getattr(Params.preset("window"), name)
    if SPECS[name].kind == "slider":
        assert f"{f.metadata['lo']:g}, {f.metadata['hi']:g}]" in text
        assert text.endswith(f"preset window: {value}")
    elif SPECS[name].kind == "toggle":
        assert text.endswith(f"on or off; preset window: {'on' if value else 'off'}")
    else:
        assert all(str(c) in text for c in f.metadata["choices"]) and text.endswith(str(value))


def other_values(name: str, params: Params) -> list:
    s, now = SPECS[name], getattr(params, name)
    if s.kind != "slider":
        return [c for c in s.choices if c != now]
    mid = (s.lo + s.hi) / 2
    values = [s.lo, s.hi, mid, 1.0]
    return [v for v in ({int(v) for v in values} if s.whole else set(values)) if v != now]


def accepted(params: Params, name: str) -> bool:
    """Does Params take some other value of `name` here (the oracle: its own checks)?"""
    for value in other_values(name, params):
        try:
            params.replace(**{name: value})
            return True
        except ValueError:
            continue
    return False


@pytest.mark.parametrize("look", list(LOOKS))
def test_a_widget_is_off_exactly_where_params_refuses_every_change(look):
    params = LOOKS[look]
    for name in FIELDS:
        if name == "grid_spacing":  # Params takes it; a session's params event does not
            assert why_off(params, name)
            continue
        assert (why_off(params, name) is None) == accepted(params, name), name


def test_every_button_and_list_of_the_panel_is_an_action_of_the_window():
    actions = Actions(Params(), *[None] * 8)
    used = {action for _, action in BUTTONS} | {"preset", "set_backdrop", "set_param",
                                                "save_params", "load_params"}
    assert used <= set(actions.table)
    assert {"pause", "single_step", "clear", "screenshot", "record", "export_maps"} <= used


# ---- a slider dragged: one change, when let go ------------------------------------------


class FakeActions:
    def __init__(self, params: Params):
        self.params, self.preset, self.calls = params, "fern", []

    def backdrop(self) -> str:
        return "dusk"

    def run(self, action, arg=None) -> None:
        self.calls.append((action, arg))


@pytest.fixture
def gui():
    context = imgui.create_context()
    io = imgui.get_io()
    io.set_ini_filename(None)
    io.backend_flags |= imgui.BackendFlags_.renderer_has_textures  # the atlas is ours to upload
    io.display_size = imgui.ImVec2(400, 1400)
    yield io
    imgui.destroy_context(context)


def frame(io, panel: TuningPanel) -> None:
    io.delta_time = 0.04
    imgui.new_frame()
    imgui.set_next_window_pos((0, 0))
    imgui.set_next_window_size((400, 1400))
    imgui.begin("panel")
    panel.draw()
    imgui.end()
    imgui.render()


def test_a_dragged_slider_sends_one_change_when_let_go(gui):
    actions = FakeActions(Params.preset("fern"))
    panel = TuningPanel(actions)
    frame(gui, panel)
    x, y, w, h = panel.rects["hc"]
    gui.add_mouse_pos_event(x + w * 6 / 15, y + h / 2)  # hc 7 sits at 6/15 of [1, 16]
    frame(gui, panel)
    gui.add_mouse_button_event(0, True)
    frame(gui, panel)
    for step in range(1, 6):  # each frame a pixel-by-pixel drag would regrow on
        gui.add_mouse_pos_event(x + w * 6 / 15 + 10 * step, y + h / 2)
        frame(gui, panel)
        assert actions.calls == [], step
    gui.add_mouse_button_event(0, False)
    frame(gui, panel)
    frame(gui, panel)
    assert len(actions.calls) == 1
    action, (name, value) = actions.calls[0]
    assert (action, name) == ("set_param", "hc")
    assert 7.0 < value <= 16.0 and value == float(f"{value:.4g}")



def clicked(io, panel: TuningPanel, x: float, y: float) -> None:
    """A left click at (x, y) of the panel, a frame for each of its events."""
    io.add_mouse_pos_event(x, y)
    frame(io, panel)
    for down in (True, False):
        io.add_mouse_button_event(0, down)
        frame(io, panel)


def test_keys_typed_into_the_file_field_stay_there_and_others_are_the_phones(gui):
    """With the set's file field clicked (ImGui wants text), C, Backspace and Esc edit the
    field, none reaches the phone's keys (C would clear the frost, Esc quit); typing
    replaces the name. Esc leaves the field: C is then the phone's. The oracle: the field
    ImGui holds, and the keys the phone was given."""
    from app.window.panel_input import PanelInput, Redraws

    actions = FakeActions(Params.preset("fern"))
    panel = TuningPanel(actions)
    phone: list[tuple] = []
    keys = PanelInput(Redraws(), lambda *key: phone.append(key), lambda: None)
    frame(gui, panel)
    x, y, w, h = panel.rects["file"]
    clicked(gui, panel, x + w / 2, y + h / 2)
    assert gui.want_text_input
    for key, char in ((glfw.KEY_C, "c"), (glfw.KEY_BACKSPACE, None), (glfw.KEY_C, "c"),
                      (glfw.KEY_ESCAPE, None)):
        keys.on_key(None, key, 0, glfw.PRESS, 0)
        if char:
            keys.on_char(None, ord(char))
        frame(gui, panel)
        keys.on_key(None, key, 0, glfw.RELEASE, 0)
        frame(gui, panel)
        if key != glfw.KEY_ESCAPE:
            assert panel.path == (char or ""), (key, panel.path)
    assert phone == []
    assert not gui.want_text_input  # Esc left the field
    keys.on_key(None, glfw.KEY_C, 0, glfw.PRESS, 0)
    assert phone == [(glfw.KEY_C, 0, glfw.PRESS, 0)]

# ---- the panel's change takes the keys' path into the session --------------------------


class Said:
    def __init__(self):
        self.lines, self.hud_next = [], 1.0

    def say(self, text, *_):
        self.lines.append(text)


def actions_on(thread: SimThread, params: Params) -> tuple[Actions, Said]:
    said = Said()
    return Actions(params, thread, None, said, None, None, lambda: None, lambda: None,
                   lambda: None), said


def test_a_panel_change_is_a_key_change_recorded_at_its_tick():
    params = Params.preset("fern")
    by_panel, by_key = (SimThread(params, 0, [(380, 640)]) for _ in range(2))
    panel, said = actions_on(by_panel, params)
    keys, _ = actions_on(by_key, params)
    for thread in (by_panel, by_key):
        for _ in range(20):
            thread.tick()
    panel.run("set_param", ("hc", 8.0))
    keys.run("shift", ("hc", 1.0))  # what `]` does twice
    for thread in (by_panel, by_key):
        for _ in range(5):
            thread.tick()
    recorded = [t.session().events for t in (by_panel, by_key)]
    assert recorded[0] == recorded[1]
    change = [e for e in recorded[0] if e["kind"] == "params"]
    assert len(change) == 1 and change[0]["tick"] == 20 and change[0]["params"]["hc"] == 8.0
    assert panel.params == tuning.changed(params, "hc", 8.0)
    assert said.lines == ["params: hc=8"] and said.hud_next == 0.0  # the HUD at once


def test_a_refused_panel_value_changes_nothing_and_says_why():
    thread = SimThread(Params.preset("fern"), 0)
    actions, said = actions_on(thread, thread.params)
    actions.run("set_param", ("near_water", 0.5))  # needs window mode
    assert actions.params == Params.preset("fern") and thread.sent == 0
    assert said.lines[0].startswith("refused: near_water=0.5 needs window_frost=True")


def test_loading_a_set_keeps_the_sessions_grid_spacing(tmp_path):
    thread = SimThread(Params.preset("fern"), 0)
    actions, said = actions_on(thread, thread.params)
    wanted = Params.preset("window", grid_spacing=2, humidity=5000)
    save_params(tmp_path / "set.json", wanted)
    actions.run("load_params", str(tmp_path / "set.json"))
    assert actions.params == wanted.replace(grid_spacing=4)
    assert len(said.lines) == 1 and said.lines[0].startswith(
        f"params loaded from {tmp_path / 'set.json'} (grid_spacing stays 4, set at start): "
        "humidity=5000 ")
    actions.run("load_params", str(tmp_path / "set.json"))
    assert said.lines[-1].endswith("(grid_spacing stays 4, set at start): unchanged")
    actions.run("load_params", str(tmp_path / "missing.json"))
    assert said.lines[-1].startswith("params NOT loaded: ") and "\n" not in said.lines[-1]
    assert actions.params == wanted.replace(grid_spacing=4)


# ---- the panel's window: when it redraws, what its cost reads ---------------------------


class Backdrop(FakeActions):
    def __init__(self, params: Params):
        super().__init__(params)
        self.shown = "dusk"

    def backdrop(self) -> str:
        return self.shown


@pytest.fixture
def host():
    from app.window.panel_host import PanelHost

    made = PanelHost(None, Backdrop(Params.preset("fern")))  # no window: nothing drawn
    yield made
    imgui.destroy_context(made.context)


def test_the_panel_redraws_on_input_or_a_change_and_not_otherwise(host, monkeypatch):
    monkeypatch.setattr(glfw, "get_window_attrib", lambda *_: True)  # focused; no window here
    actions, redraws, t = host.actions, host.redraws, 100.0
    assert not host.due(t)  # hidden
    host.visible, redraws.wanted = True, 0
    redraws.drew(host.state(), t)
    assert not host.due(t + 5)  # idle: its pixels stay
    for change in (lambda: setattr(actions, "params", actions.params.replace(hc=8.0, step=5.0)),
                   lambda: setattr(actions, "preset", "c-2"),
                   lambda: setattr(actions, "shown", "lockscreen")):
        change()
        assert host.due(t)
        redraws.drew(host.state(), t)
        assert not host.due(t + 5)
    host.input.on_cursor(None, 10.0, 20.0)  # a hover: twice, not sooner than 0.1 s after the last
    assert redraws.wanted == 2 and not host.due(t + 0.05)
    assert host.due(t + 0.11)
    host.input.on_button(None, glfw.MOUSE_BUTTON_LEFT, glfw.PRESS, 0)  # a click: at once,
    assert redraws.wanted == 3 and host.due(t + 0.01)  # and the drag after it
    redraws.drew(host.state(), t)
    redraws.drew(host.state(), t)
    redraws.drew(host.state(), t)
    assert redraws.wanted == 0 and not redraws.hurry and not host.due(t + 0.01)
    host.input.on_cursor(None, 12.0, 20.0)
    assert redraws.wanted == 3 and host.due(t + 0.01)


def test_closing_the_panels_window_hides_it_and_keeps_it_for_later(host, monkeypatch):
    calls = []
    for name in ("set_window_should_close", "hide_window"):
        monkeypatch.setattr(glfw, name, lambda *a, name=name: calls.append((name, *a[1:])))
    host.window, host.visible = "the panel's window", True
    host.input.on_close(host.window)  # GLFW's close callback
    assert not host.visible and host.window is not None  # hidden, not destroyed: M shows it
    assert calls == [("set_window_should_close", False), ("hide_window",)]


PANEL_IDS = (0x40000D, 0x40000E)  # its X window and GLX window
PHONE_X_ID = 0x400007


def gone_window(host, monkeypatch, calls: list):
    """GLFW faked: the panel's window shown, destroyed from outside, so that reading its
    size meets the X error (the handler calls `host.lost`, as Xlib would inside the call)."""
    def size(window):
        calls.append(("get_window_size", window))
        host.lost(PANEL_IDS[0])
        return 0, 0

    monkeypatch.setattr(glfw, "get_window_size", size)
    for name in ("make_context_current", "destroy_window", "swap_buffers"):
        monkeypatch.setattr(glfw, name, lambda window, name=name: calls.append((name, window)))
    host.window, host.ids, host.visible = "the panel's window", PANEL_IDS, True


def test_a_panel_window_gone_is_only_marked_inside_xlib_and_names_its_ids(host, monkeypatch):
    calls: list = []
    gone_window(host, monkeypatch, calls)
    assert host.lost(PHONE_X_ID) == () and not host.gone  # not the panel's
    assert host.lost(PANEL_IDS[1]) == PANEL_IDS and host.gone  # its GLX window names it too
    assert calls == [] and host.window is not None  # no GLFW call from inside Xlib
    assert host.needs_frame()  # the frame loop comes back at once to forget it


def test_a_panel_window_gone_is_forgotten_at_the_next_frame_and_m_opens_a_new_one(
        host, monkeypatch):
    """The redraw due reads the size first and meets the window gone: the dead window's
    context is never made current (Mesa took seconds to refuse it); the GLFW window is
    destroyed, the phone's context current again, and the ImGui context is a new one (the
    old one counts its font texture as uploaded to the dead GL context)."""
    calls: list = []
    gone_window(host, monkeypatch, calls)
    host.redraws.want()
    host.deferred.run("clear")  # clicked before the window went: still done
    done: list = []
    monkeypatch.setattr(host.actions, "run", lambda *a: done.append(a), raising=False)
    imgui.get_io().mouse_drag_threshold = 99.0  # a mark in the old context's state
    host.frame(True)
    assert calls == [("get_window_size", "the panel's window"),
                     ("destroy_window", "the panel's window"), ("make_context_current", None)]
    assert done == [("clear", None)]
    assert host.window is None and host.ids == () and not host.visible and not host.gone
    io = imgui.get_io()  # a new context, made as the first was
    assert io.mouse_drag_threshold != 99.0 and not io.get_ini_filename()
    assert not io.config_flags & imgui.ConfigFlags_.nav_enable_keyboard
    assert host.input.redraws is host.redraws and not host.needs_frame()
    assert host.readout(25) is None
    opened: list = []
    monkeypatch.setattr(host, "_open", lambda: opened.append(1) or False)
    host.toggle()  # M: a new window (here one that cannot open)
    assert opened == [1]


def test_a_failing_redraw_is_no_loss_when_the_window_went_during_it(host, monkeypatch):
    """The window goes between its size read and the draw: the draw's failure (ImGui's
    check of the size the dead window read) is the loss already reported; a draw failing
    with its window alive is a real error and raised."""
    calls: list = []
    gone_window(host, monkeypatch, calls)
    monkeypatch.setattr(glfw, "get_window_size", lambda window: (400, 1280))

    def failing(_size):
        host.lost(PANEL_IDS[0])
        raise RuntimeError("IM_ASSERT( g.IO.DisplaySize.x >= 0.0f )")

    monkeypatch.setattr(host, "_draw", failing)
    host.redraws.want()
    host.frame(True)
    assert ("destroy_window", "the panel's window") in calls and host.window is None
    host.window, host.ids, host.visible = "the panel's window", PANEL_IDS, True
    monkeypatch.setattr(host, "_draw", lambda _size: 1 / 0)
    host.redraws.want()
    with pytest.raises(ZeroDivisionError):
        host.frame(True)


def test_the_panels_cost_is_its_recent_redraws_shared_among_the_phones_frames(host):
    import time

    from app.window.status import Status

    now = time.perf_counter()
    host.costs.add(now - 3.0, 100.0)
    assert host.readout(20) is None  # hidden: no cost shown
    host.visible = True
    assert host.readout(20) == "panel 0.00 ms/frame (0 redraws)"  # idle for over 2 s
    for age, ms in ((1.5, 6.0), (0.5, 4.0)):
        host.costs.add(now - age, ms)
    text = host.readout(20)
    assert text == "panel 0.50 ms/frame (2 redraws, 5.0 ms each)"  # (6 + 4) / 20 by hand
    lines = Status().lines(now, None, Params(), types.SimpleNamespace(
        show_features=True, show_bumps=True, light=(0.0, 0.0, 1.0)), None, 3.0, text)
    assert lines[1].endswith("  " + text)  # the second line: in the log's stats lines too


# ---- parameter sets --------------------------------------------------------------------


def test_a_saved_set_loads_back_equal(tmp_path):
    for params in LOOKS.values():
        path = save_params(tmp_path / "set.json", params.replace(hc=7.25, step=3.5))
        assert load_params(path) == params.replace(hc=7.25, step=3.5)
    assert json.loads(path.read_text(encoding="utf-8"))["params"] == load_params(path).as_dict()


def test_a_session_file_is_a_set_of_its_first_parameters(tmp_path):
    log = SessionLog(3, Params.preset("c-3").as_dict())
    path = log.save(tmp_path / "session.json")
    assert load_params(path) == Params.preset("c-3")


BAD_SETS = {
    "missing": (None, "cannot read"),
    "text": ("hc = 7", "not JSON"),
    "list": ("[1, 2]", "no 'params' entry"),
    "range": ('{"params": {"hc": 50.0}}', "hc=50.0 is out of range"),
    "whole": ('{"params": {"humidity": 4.0}}', "humidity=4.0 must be a whole number"),
    "unknown": ('{"params": {"hc": 7.0, "colour": 1}}', "unknown parameter 'colour'"),
    "needs": ('{"params": {"drift": 3.0}}', "drift=3.0 needs grains=True"),
    "nan": ('{"params": {"D": NaN}}', "must be finite"),
}


@pytest.mark.parametrize("case", list(BAD_SETS))
def test_a_bad_set_is_one_line_naming_the_file_and_the_problem(tmp_path, case):
    text, why = BAD_SETS[case]
    path = tmp_path / f"{case}\nset.json"  # a newline in the name stays escaped
    if text is not None:
        path.write_text(text, encoding="utf-8")
    with pytest.raises(ParamsFileError) as err:
        load_params(path)
    assert why in str(err.value) and "\n" not in str(err.value) and "set.json" in str(err.value)


@pytest.mark.parametrize("command", [["render"], ["maps", "MAPS"], ["figure", "fern", "F.png"], [],
                                     ["figure8", "F.png"], ["bench", "render"],
                                     ["replay", "S.json"]])
def test_params_on_the_command_line_refuses_a_bad_file_in_one_line(tmp_path, capsys, command):
    bad = tmp_path / "bad.json"
    bad.write_text('{"params": {"hc": 0.5}}', encoding="utf-8")
    argv = [a.replace("MAPS", str(tmp_path / "maps")) for a in command]
    with pytest.raises(SystemExit) as stop:
        main([*argv, "--params", str(bad)])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1
    assert err.startswith("frost: error: ") and "hc=0.5 is out of range" in err


def test_params_with_overrides_on_top(tmp_path, monkeypatch):
    from app.cli import commands

    path = save_params(tmp_path / "set.json", Params.preset("window", humidity=5000))
    got = {}
    monkeypatch.setitem(commands.RUN, "render", lambda args, params: got.setdefault("p", params) and 0)
    assert main(["render", "--params", str(path), "--hc", "4", "--temperature", "12"]) == 0
    want = Params.preset("window", humidity=5000).replace(hc=4.0, step=4.0, temperature=12.0)
    assert got["p"] == want
    with pytest.raises(SystemExit) as stop:
        main(["render", "--params", str(path), "--preset", "c-2"])
    assert stop.value.code == 2


# ---- --params on the offline commands ------------------------------------------------------

TABLE1 = ("a-1", "a-2", "a-3", "b-1", "b-2", "b-3", "c-1", "c-2", "c-3")
A_SET = Params.preset("fern", bump=2.0, drift=4.0, humidity=5000, water_budget=7000)


class Stop(Exception):
    pass


def test_figure8_grows_each_preset_under_the_sets_other_fields(tmp_path, monkeypatch):
    from app.tools import figure8

    path = save_params(tmp_path / "set.json", A_SET)
    got = {}

    def grown(ctx, seed, ticks, touch, overrides, view):
        got.update(overrides)
        raise RuntimeError("stopped here")  # run reports it: status 1

    monkeypatch.setattr(figure8, "make_context", lambda: None)
    monkeypatch.setattr(figure8, "make_figure8", grown)
    assert main(["figure8", str(tmp_path / "f.png"), "--params", str(path), "--tip-hits", "7"]) == 1
    for name in TABLE1:  # by hand: Table 1's three, step fitted to hc, the set's rest
        table = Params.preset(name)
        want = {**A_SET.as_dict(), "D": table.D, "hc": table.hc, "humidity": table.humidity,
                "step": min(Params.step, table.hc), "tip_hits": 7}
        assert Params.preset(name, **got).as_dict() == want


@pytest.mark.parametrize("argv, want", [
    ([], Params.preset("c-2")),  # its own default, not the window's
    (["--preset", "b-1"], Params.preset("b-1")),
    (["--params", "SET"], A_SET),
])
def test_bench_render_grows_the_set_or_its_preset(tmp_path, monkeypatch, argv, want):
    from app.bench import render as bench

    path = save_params(tmp_path / "set.json", A_SET)
    seen = []

    def look(ctx, params, name, view):
        seen.append(params)
        raise Stop

    ctx = types.SimpleNamespace(simple_framebuffer=lambda *_, **__: None)
    monkeypatch.setattr(bench, "make_context", lambda: ctx)
    monkeypatch.setattr(bench, "Look", look)
    with pytest.raises(Stop):
        main(["bench", "render", *[str(path) if a == "SET" else a for a in argv]])
    assert seen == [want]


def test_a_what_if_replay_is_the_session_under_the_set(tmp_path, monkeypatch):
    from app.tools.replay import under

    looked = A_SET.replace(hc=5.0, step=5.0).as_dict()
    events = [{"tick": 3, "kind": "touch", "x": 100.0, "y": 200.0},
              {"tick": 9, "kind": "params", "params": Params.preset("c-2").as_dict()},
              {"tick": 4, "kind": "params", "params": Params.preset("c-2", look="paper").as_dict()},
              {"tick": 6, "kind": "clear"}]
    log = SessionLog(4, Params.preset("c-1", look="paper").as_dict(), events=events, steps=20)
    what_if = under(log, A_SET, "set.json")
    assert what_if.params == A_SET.replace(look="paper").as_dict() != looked
    assert what_if.events[1]["params"] == A_SET.replace(look=Params.look).as_dict()
    assert what_if.events[2]["params"] == A_SET.replace(look="paper").as_dict()
    assert [e for i, e in enumerate(what_if.events) if i in (0, 3)] == [events[0], events[3]]
    assert (what_if.seed, what_if.steps) == (4, 20)


def test_a_what_if_replay_draws_what_a_session_run_with_the_set_draws(tmp_path):
    """The oracle: the same session written by hand with the set's parameters (the look
    the session's)."""
    events = [{"tick": 2, "kind": "touch", "x": 380.0, "y": 640.0}]
    session = SessionLog(1, Params.preset("c-2").as_dict(), events=events, steps=40)
    twin = SessionLog(1, A_SET.replace(look="paper").as_dict(), events=events, steps=40)
    path = save_params(tmp_path / "set.json", A_SET)
    outs = []
    for name, log, extra in (("s", session, ["--params", str(path)]), ("t", twin, [])):
        out = tmp_path / f"{name}.png"
        assert main(["replay", str(log.save(tmp_path / f"{name}.json")), "--headless",
                     "--out", str(out), *extra]) == 0
        outs.append(np.asarray(Image.open(out).convert("RGB")))
    plain = tmp_path / "plain.png"
    assert main(["replay", str(tmp_path / "s.json"), "--headless", "--out", str(plain)]) == 0
    assert np.array_equal(outs[0], outs[1])
    assert not np.array_equal(outs[0], np.asarray(Image.open(plain).convert("RGB")))


@pytest.mark.parametrize("left_out", ["humidity", "frame_chill"])
def test_a_set_with_a_field_missing_is_refused_naming_it(tmp_path, capsys, left_out):
    values = Params.preset("window").as_dict()
    del values[left_out]
    path = tmp_path / "set.json"
    path.write_text(json.dumps({"format": "frost-params", "version": 1, "params": values}), encoding="utf-8")
    with pytest.raises(SystemExit) as stop:
        main(["render", "--params", str(path), "--out", str(tmp_path / "f.png")])
    err = capsys.readouterr().err
    assert stop.value.code == 2 and err.count("\n") == 1 and err.startswith("frost: error: ")
    assert f"{path}: not a parameter set: 'params' has no {left_out!r} entry;" in err


def test_a_set_missing_many_fields_names_the_first_and_counts_the_rest(tmp_path):
    path = tmp_path / "set.json"
    path.write_text('{"params": {"hc": 7.0, "step": 5.0}}', encoding="utf-8")
    with pytest.raises(ParamsFileError, match=f"has no 'D' entry \\(and {len(A_SET.as_dict()) - 3} "
                                              "more\\)"):
        load_params(path)


def test_a_session_file_lacking_newer_parameters_loads_with_them_off(tmp_path):
    log = SessionLog(3, {"D": 7.0, "hc": 7.0, "humidity": 500})  # a file older than most parameters
    assert load_params(log.save(tmp_path / "old.json")) == Params.preset("c-1")


@pytest.mark.parametrize("content_scale, ratio, ui", [(1.0, 1.0, 1.0), (1.5, 1.0, 1.5),
                                                      (2.0, 1.0, 2.0), (2.0, 2.0, 1.0),
                                                      (1.25, 1.0, 1.25)])
def test_the_panel_is_laid_out_at_the_screens_scale(monkeypatch, content_scale, ratio, ui):
    """Widgets and text times the content scale where window coordinates are pixels
    (Windows, X11 at 150 %: 1.5), once where they are points and the framebuffer is already
    that much denser (a Retina Mac: 2 and 2)."""
    import glfw

    from app.window import panel_host

    monkeypatch.setattr(glfw, "get_window_content_scale", lambda w: (content_scale,) * 2)
    monkeypatch.setattr(glfw, "get_window_size", lambda w: (400, 800))
    monkeypatch.setattr(glfw, "get_framebuffer_size", lambda w: (400 * ratio, 800 * ratio))
    assert panel_host.ui_scale(object()) == pytest.approx(ui)
