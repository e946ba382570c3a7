"""The phone protocol's bytes (docs/protocol.md) against messages taken apart by hand, and the
page's input checks."""

import json
import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from app.serve.protocol import (
    HEADER,
    MAX_INPUT_BYTES,
    PART_VERTICES,
    Encoder,
    ProtocolError,
    apply_geometry,
    decode_geometry,
    height_runs,
    parse_input,
)
from sim import Params
from sim.io.timeline import Timeline
from sim.look.geometry import GeometryDelta


def delta(tick, rows, heights, features=(), **more):
    feats = np.array(features, np.float32).reshape(-1, 6)
    return GeometryDelta(tick, rows, np.array(heights, np.float32), feats, **more)


def test_a_delta_unpacked_by_hand():
    enc = Encoder(cols=3, rows=4)
    d = delta(7, slice(1, 3), [[0, 0.5, 0], [0, 0, 0]],
              [[10.25, 20.5, 1.5, 0.0, 0.6, 0.8], [-3.0, 1279.9375, 0.0, 1.0, 0.0, 0.0]],
              look="glass", height_scale=24.0, clear_box=(1.0, 2.0, 30.5, 40.0))
    m = enc.delta(d)
    # header: 4 bytes, tick, cols, rows, height scale, runs, vertices, box
    assert struct.unpack("<BBBB", m[0:4]) == (1, 1, 2, 1)  # version, type, flags clear_box, glass
    assert struct.unpack("<I", m[4:8]) == (7,)
    assert struct.unpack("<HH", m[8:12]) == (3, 4)
    assert struct.unpack("<f", m[12:16]) == (24.0,)
    assert struct.unpack("<II", m[16:24]) == (1, 2)
    assert struct.unpack("<4f", m[24:40]) == (1.0, 2.0, 30.5, 40.0)
    # one run: row 1, column 1 is flat index 4, one value; 2 bytes, padded to 4
    assert struct.unpack("<II", m[40:48]) == (4, 1)
    assert struct.unpack("<e", m[48:50]) == (0.5,) and m[50:52] == b"\0\0"
    # vertices: x*16, y*16 as int16, z half, 2 pad, normal*127 as int8, 1 pad
    v0, v1 = m[52:64], m[64:76]
    assert struct.unpack("<hhe", v0[:6]) == (164, 328, 1.5)
    assert struct.unpack("<bbb", v0[8:11]) == (0, 76, 102)  # 0.6*127 = 76.2, 0.8*127 = 101.6
    assert struct.unpack("<hhe", v1[:6]) == (-48, 20479, 0.0)
    assert struct.unpack("<bbb", v1[8:11]) == (127, 0, 0)
    assert len(m) == 76


def test_runs_take_only_what_changed_and_bridge_small_gaps():
    old = np.zeros(30, np.float16)
    new = old.copy()
    new[[2, 3, 8, 20, 29]] = 1
    # 3 -> 8 is a gap of 4 unchanged values (sent along); 8 -> 20 is not
    assert height_runs(old, new) == [(2, 7), (20, 1), (29, 1)]
    assert height_runs(old, old) == []


def test_a_second_delta_sends_only_the_changes():
    enc = Encoder(cols=4, rows=3)
    enc.delta(delta(1, slice(0, 2), [[1, 1, 1, 1], [0, 0, 0, 0]]))
    m = enc.delta(delta(2, slice(0, 2), [[1, 1, 1, 2], [0, 0, 0, 0]]))
    assert struct.unpack("<I", m[16:20]) == (1,)
    assert struct.unpack("<II", m[40:48]) == (3, 1)
    assert struct.unpack("<e", m[48:50]) == (2.0,)


def test_reset_clears_the_encoders_grid():
    enc = Encoder(cols=2, rows=2)
    enc.delta(delta(1, slice(0, 2), [[1, 1], [1, 1]]))
    m = enc.delta(delta(0, slice(0, 2), [[0, 0], [0, 1]]), reset=True)
    assert m[2] == 1 and struct.unpack("<II", m[40:48]) == (3, 1)
    assert enc.bare(5, reset=True)[2] == 1 and not enc.heights.any()


def test_a_change_within_a_half_float_step_sends_nothing():
    """The pages hold half floats: near 1.0 they step by 1/1024, so 1.0001 is the 1.0 they
    hold already (no run), while 1.001 is the next step (a run)."""
    enc = Encoder(cols=2, rows=1)
    enc.delta(delta(1, slice(0, 1), [[1.0, 2.0]]))
    m = enc.delta(delta(2, slice(0, 1), [[1.0001, 2.0]]))
    assert struct.unpack("<I", m[16:20]) == (0,) and len(m) == 40
    m = enc.delta(delta(3, slice(0, 1), [[1.001, 2.0]]))
    assert struct.unpack("<III", m[16:28])[::2] == (1, 0)  # one run, of (0, 1)
    assert struct.unpack("<IIe", m[40:50]) == (0, 1, 1.0009765625)


def test_a_delta_that_resets_tells_the_pages_to_clear_first():
    """A rebuild's own delta (GeometryDelta.reset), not only the encoder's reset=True."""
    enc = Encoder(cols=2, rows=1)
    enc.delta(delta(1, slice(0, 1), [[1.0, 1.0]]))
    m = enc.delta(delta(0, slice(0, 1), [[0.0, 1.0]], reset=True))
    assert m[2] == 1  # flags: reset
    assert struct.unpack("<I", m[16:20]) == (1,) and struct.unpack("<II", m[40:48]) == (1, 1)
    page = np.array([1.0, 1.0], np.float32)
    apply_geometry(page, decode_geometry(m))
    assert page.tolist() == [0.0, 1.0]


def test_a_snapshot_is_every_height_and_the_features_in_parts():
    enc = Encoder(cols=2, rows=2)
    enc.delta(delta(1, slice(0, 2), [[1, 0], [0, 3]]))
    feats = np.zeros((PART_VERTICES + 5, 6), np.float32)
    feats[:, 0] = 1.0
    parts = enc.snapshot(9, feats, "paper", 16.0)
    assert PART_VERTICES % 3 == 0  # a part holds whole triangles
    assert [p[2] for p in parts] == [1 | 4, 4 | 8]
    assert struct.unpack("<II", parts[0][16:24]) == (1, PART_VERTICES)
    assert struct.unpack("<II", parts[0][40:48]) == (0, 4)
    assert struct.unpack("<4e", parts[0][48:56]) == (1.0, 0.0, 0.0, 3.0)
    assert struct.unpack("<II", parts[1][16:24]) == (0, 5)
    assert len(parts[1]) == 40 + 5 * 12


def test_the_pages_grid_follows_the_simulations():
    """Decoding every message of a run gives the geometry's heights (as half floats)."""
    tl = Timeline(Params.preset("c-2"), 3, 200, 160)
    tl.apply([{"kind": "touch", "x": 100.0, "y": 80.0}])
    g = tl.geometry
    enc, page = Encoder(g.cols, g.rows), np.zeros(g.rows * g.cols, np.float32)
    for _ in range(60):
        for d in tl.step():
            apply_geometry(page, decode_geometry(enc.delta(d)))
    assert g.heights.any()
    assert (page == g.heights.ravel().astype(np.float16)).all()


@pytest.mark.parametrize("message, kind, fields", [
    ('{"type":"touch","x":10,"y":20.5}', "touch", {"x": 10.0, "y": 20.5, "phase": "down"}),
    ('{"type":"melt","x":1,"y":2,"phase":"move","id":3}', "melt", {"finger": 3, "phase": "move"}),
    ('{"type":"touch","phase":"up","id":1}', "touch", {"phase": "up", "finger": 1}),
    ('{"type":"preset","name":"window"}', "preset", {"name": "window"}),
    ('{"type":"key","key":"SPACE"}', "key", {"name": "SPACE"}),
    ('{"type":"pause"}', "pause", {}),
    ('{"type":"ping","t":12.5}', "ping", {"stamp": 12.5}),
])
def test_good_input(message, kind, fields):
    got = parse_input(message)
    assert got.kind == kind
    for k, v in fields.items():
        assert getattr(got, k) == v


@pytest.mark.parametrize("message, code, says", [
    ("not json", 1008, "not JSON"),
    ("[1, 2]", 1008, "JSON object"),
    ('{"type":"warp"}', 1008, "unknown message type"),
    ('{"type":"touch","x":"1","y":2}', 1008, "'x'"),
    ('{"type":"touch","x":NaN,"y":2}', 1008, "not JSON"),
    ('{"type":"touch","x":1e999,"y":2}', 1008, "'x'"),
    ('{"type":"touch","x":true,"y":2}', 1008, "'x'"),
    ('{"type":"touch","x":1,"y":2,"id":32}', 1008, "'id'"),
    ('{"type":"touch","x":1,"y":2,"phase":"hover"}', 1008, "'phase'"),
    ('{"type":"preset","name":""}', 1008, "'name'"),
    ('{"type":"key"}', 1008, "'key'"),
    (b"\x00\x01", 1008, "binary"),
    (json.dumps({"type": "pause", "pad": "x" * MAX_INPUT_BYTES}), 1009, "over 1024 bytes"),
    # 628 characters, 1 228 bytes in UTF-8 (the bound is the socket's, in bytes)
    (json.dumps({"type": "pause", "pad": "é" * 600}, ensure_ascii=False), 1009, "over 1024 bytes"),
])
def test_bad_input_names_the_problem(message, code, says):
    with pytest.raises(ProtocolError, match=says) as err:
        parse_input(message)
    assert err.value.code == code


def parsed_or_refused(message) -> None:
    """parse_input's promise: an Input, or ProtocolError (which closes the socket with its
    code and a line): never another exception, which would reach aiohttp as a traceback."""
    try:
        got = parse_input(message)
    except ProtocolError as err:
        assert err.code in (1008, 1009) and err.reason
    else:
        assert got.kind in ("touch", "melt", "preset", "look", "backdrop", "key", "pause",
                            "step", "clear", "ping")


JSON = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=8)
    | st.sampled_from(["touch", "melt", "down", "move", "up", "ping", "key", "preset"]),
    lambda inner: st.lists(inner, max_size=4)
    | st.dictionaries(st.sampled_from(["type", "x", "y", "id", "phase", "name", "key", "t"])
                      | st.text(max_size=4), inner, max_size=5),
    max_leaves=20)


@given(st.text(max_size=1100))
def test_any_text_is_parsed_or_refused(message):
    parsed_or_refused(message)


@given(JSON)
def test_any_json_is_parsed_or_refused(value):
    parsed_or_refused(json.dumps(value, allow_nan=True))
    parsed_or_refused(json.dumps({"type": "touch", "x": value, "y": 1}, allow_nan=True))


@given(st.binary(max_size=64))
def test_any_bytes_are_refused(message):
    with pytest.raises(ProtocolError):
        parse_input(message)


@pytest.mark.parametrize("message", [
    "[" * 1000,  # json's RecursionError: a traceback per message, no close frame
    "[" * 1023,
    '{"type":"touch","x":' + "[" * 1000,
])
def test_nesting_too_deep_for_json_is_refused(message):
    with pytest.raises(ProtocolError, match="not JSON") as err:
        parse_input(message)
    assert err.value.code == 1008


def test_text_that_is_no_utf_8_is_refused():
    # A lone surrogate: no str aiohttp hands over holds one (it refuses such a frame with
    # 1007 itself), but parse_input takes any str.
    with pytest.raises(ProtocolError, match="UTF-8") as err:
        parse_input('{"type":"pause","pad":"\ud800"}')
    assert err.value.code == 1008


# ---- decode_geometry: the decoded message, or ValueError --------------------------------

def decoded_or_refused(data: bytes):
    """decode_geometry's promise: its fields, or ValueError (never struct.error, IndexError
    or a numpy error)."""
    try:
        return decode_geometry(data)
    except ValueError as err:
        assert type(err) is ValueError and str(err), repr(err)  # (not a subclass in disguise)
        return None


@st.composite
def messages(draw):
    """(message, the grid a page holds before it, the encoder's grid after it, features
    sent): a delta of a small grid encoded after a first one (so that its runs are of the
    values that changed), with or without a reset, a clear box, features."""
    cols, rows = draw(st.integers(1, 7)), draw(st.integers(1, 7))
    halves = st.sampled_from([0.0, 0.5, 1.0, 1.5, 2.25, 3.0])  # exact in half floats
    enc = Encoder(cols, rows)
    first = draw(st.lists(halves, min_size=cols * rows, max_size=cols * rows))
    enc.delta(delta(0, slice(0, rows), np.reshape(first, (rows, cols))))
    before = enc.heights.astype(np.float32)
    r0 = draw(st.integers(0, rows - 1))
    r1 = draw(st.integers(r0 + 1, rows))
    second = draw(st.lists(halves, min_size=(r1 - r0) * cols, max_size=(r1 - r0) * cols))
    nverts = 3 * draw(st.integers(0, 3))
    px = st.integers(-40, 800).map(lambda v: v / 16)  # on the 1/16 px the wire keeps
    unit = st.sampled_from([0.0, 1.0, -1.0])
    feats = np.array(draw(st.lists(st.tuples(px, px, halves, unit, unit, unit),
                                   min_size=nverts, max_size=nverts)), np.float32).reshape(-1, 6)
    d = delta(5, slice(r0, r1), np.reshape(second, (r1 - r0, cols)), feats,
              clear_box=draw(st.none() | st.tuples(px, px, px, px)),
              look=draw(st.sampled_from(["paper", "glass"])), height_scale=16.0,
              reset=draw(st.booleans()))
    return enc.delta(d), before, enc.heights.astype(np.float32), feats


@given(messages())
def test_a_message_decodes_to_what_was_sent(sent):
    data, before, after, feats = sent
    m = decode_geometry(data)
    page = before.copy()
    apply_geometry(page, m)
    assert np.array_equal(page, after)  # the page holds what the encoder says it holds
    assert np.array_equal(m["vertices"], feats)


@given(messages(), st.data())
def test_any_truncation_of_a_message_is_refused(sent, data):
    whole = sent[0]
    cut = data.draw(st.integers(0, len(whole) - 1))
    with pytest.raises(ValueError):
        decode_geometry(whole[:cut])
    with pytest.raises(ValueError):
        decode_geometry(whole + b"\0" * data.draw(st.integers(1, 13)))


@given(st.binary(max_size=200))
def test_any_bytes_decode_or_are_refused(data):
    decoded_or_refused(data)


@given(st.tuples(st.integers(0, 255), st.integers(0, 255), st.integers(0, 2**32 - 1),
                 st.integers(0, 2**16 - 1), st.integers(0, 2**16 - 1),
                 st.integers(0, 2**32 - 1), st.integers(0, 2**32 - 1)),
       st.binary(max_size=120))
def test_any_header_of_this_version_decodes_or_is_refused(fields, rest):
    """Headers that pass the version check, with any flags, look, grid and counts (a
    count of 2**32 - 1 runs asks for 32 GB), then any bytes."""
    flags, look, tick, cols, rows, nruns, nverts = fields
    head = HEADER.pack(1, 1, flags, look, tick, cols, rows, 16.0, nruns, nverts, 0, 0, 0, 0)
    m = decoded_or_refused(head + rest)
    if m is not None:
        assert len(m["vertices"]) == nverts and len(m["runs"]) == nruns


@pytest.mark.parametrize("damage, says", [
    (lambda m: m[:3] + b"\x07" + m[4:], "look"),  # look byte 7: IndexError before
    (lambda m: m[:16] + struct.pack("<I", 1000) + m[20:], "1000 runs"),  # struct.error before
    (lambda m: m[:20] + struct.pack("<I", 2) + m[24:-12], "whole triangles"),
    (lambda m: m[:40] + struct.pack("<II", 10, 3) + m[48:], "grid"),  # past 3 x 4 = 12
    (lambda m: m[:2] + b"\x30" + m[3:], "flags"),
])
def test_a_damaged_message_says_what_is_wrong(damage, says):
    enc = Encoder(cols=3, rows=4)
    good = enc.delta(delta(7, slice(1, 3), [[0, 0.5, 0], [0, 0, 0]], [[1, 2, 0, 0, 0, 1]] * 3))
    assert decode_geometry(good)["runs"] == [(4, 1)]
    with pytest.raises(ValueError, match=says):
        decode_geometry(damage(good))
