"""The tuning panel without a window: its widgets against Params' own fields and checks,
a slider dragged with ImGui's input queue (no GL: the draw lists are built, not drawn),
the panel's changes through the keys' path into a real simulation thread's session, and
parameter sets on disk and on the command line."""

from __future__ import annotations

import dataclasses
import json

import pytest
from imgui_bundle import imgui

from app.cli import main
from app.simthread.thread import SimThread
from app.window.actions import Actions
from app.window.panel import BUTTONS, FIELDS, GROUPS, SPECS, TuningPanel, tooltip, why_off
from app.window.view import cursor_to_phone
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
            thread._tick()
    panel.run("set_param", ("hc", 8.0))
    keys.run("shift", ("hc", 1.0))  # what `]` does twice
    for thread in (by_panel, by_key):
        for _ in range(5):
            thread._tick()
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
    assert any("grid_spacing stays 4" in line for line in said.lines)
    actions.run("load_params", str(tmp_path / "missing.json"))
    assert said.lines[-1].startswith("params NOT loaded: ") and "\n" not in said.lines[-1]
    assert actions.params == wanted.replace(grid_spacing=4)


# ---- where the phone is when the panel is shown -----------------------------------------


@pytest.mark.parametrize("panel, cursor, want", [
    (400, (380, 640), (380.0, 640.0)),  # 760 + 400 px wide: the phone at the left edge
    (400, (759, 0), (759.0, 0.0)),
    (400, (760, 640), None),  # the panel's first column
    (400, (1100, 100), None),
    (0, (580, 640), (380.0, 640.0)),  # the same window with no panel: letterboxed, centred
])
def test_a_click_maps_to_the_phone_left_of_the_panel_and_never_on_it(panel, cursor, want):
    assert cursor_to_phone(cursor, (1160, 1280), (1160, 1280), panel=panel) == want


def test_on_a_hidpi_screen_the_panel_is_counted_in_framebuffer_px():
    # Window 580x640 (half the framebuffer), panel 400 framebuffer px: phone 760 fb px wide.
    assert cursor_to_phone((190, 320), (580, 640), (1160, 1280), panel=400) == (380.0, 640.0)
    assert cursor_to_phone((385, 320), (580, 640), (1160, 1280), panel=400) is None


# ---- parameter sets --------------------------------------------------------------------


def test_a_saved_set_loads_back_equal(tmp_path):
    for params in LOOKS.values():
        path = save_params(tmp_path / "set.json", params.replace(hc=7.25, step=3.5))
        assert load_params(path) == params.replace(hc=7.25, step=3.5)
    assert json.loads(path.read_text())["params"] == load_params(path).as_dict()


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
        path.write_text(text)
    with pytest.raises(ParamsFileError) as err:
        load_params(path)
    assert why in str(err.value) and "\n" not in str(err.value) and "set.json" in str(err.value)


@pytest.mark.parametrize("command", [["render"], ["maps", "MAPS"], ["figure", "fern", "F.png"], []])
def test_params_on_the_command_line_refuses_a_bad_file_in_one_line(tmp_path, capsys, command):
    bad = tmp_path / "bad.json"
    bad.write_text('{"params": {"hc": 0.5}}')
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
