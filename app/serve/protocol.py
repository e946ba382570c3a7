"""The phone protocol, version 1 (docs/protocol.md): geometry deltas packed into binary
WebSocket messages, the hello/state JSON, and the page's input messages checked.

No GL and no networking here: `Encoder` turns the simulation thread's `GeometryDelta`s
into bytes (once a tick, for every page), `decode_geometry` reads them back (the bench's
clients and the tests), `parse_input` checks what a page sends.
"""

from __future__ import annotations

import json
import math
import struct
from dataclasses import dataclass
from typing import Any

import numpy as np

from sim.look.geometry import VERTEX_FLOATS, GeometryDelta

VERSION = 1
GEOMETRY = 1  # the binary message type
# flags of a geometry message
RESET, CLEAR_BOX, SNAPSHOT, LAST_PART = 1, 2, 4, 8
ALL_FLAGS = RESET | CLEAR_BOX | SNAPSHOT | LAST_PART
LOOKS = ("paper", "glass")  # the look byte: its index here
# u8 version, u8 type, u8 flags, u8 look; u32 tick; u16 cols, u16 rows (the grid);
# f32 height_scale; u32 runs, u32 vertices; f32 x 4 clear box (x0, y0, x1, y1 px).
HEADER = struct.Struct("<4BI2HfII4f")
RUN = struct.Struct("<II")  # start (flat index into the grid, row-major), count
# A feature vertex, 12 bytes: x, y in 1/16 px, z (px) as a half float, 2 bytes of padding,
# the normal times 127, a padding byte.
VERTEX = np.dtype([("xy", "<i2", 2), ("z", "<f2"), ("pad", "<u2"), ("n", "i1", 3), ("pad2", "u1")])
SUBPIXEL = 16
# Unchanged heights between two changed ones are sent along (2 bytes each) rather than
# starting a new run (8 bytes) when there are at most this many.
RUN_GAP = 4
# A snapshot's features are cut into messages of at most this many vertices (768 kB), so
# a page's queue fills by parts and a stalled page is seen within one part; whole
# triangles each.
PART_VERTICES = 3 * 21845

# The lock screen's clock box at a new minute (docs/protocol.md): u8 version, u8 type 2;
# u16 x, y, w, h (px, y down: where the picture goes on the backdrop); the minute as 16
# ASCII bytes ("YYYY-MM-DDTHH:MM"); 2 zero bytes; then the box's pixels as a PNG (RGB,
# w x h: lossless, so the page's backdrop is the server's pixel for pixel).
CLOCK = 2
CLOCK_HEADER = struct.Struct("<2B4H16s2x")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

# Page -> server
MAX_INPUT_BYTES = 1024
RATE_TEXT = 200  # messages a second a page may send (app.serve.pages.TokenBucket)
FINGERS = 32  # finger ids 0..31
PHASES = ("down", "move", "up")
POINTER_KINDS = ("touch", "melt")
NAMED_KINDS = ("preset", "look", "backdrop", "key")  # each carries a "name" ("key": "key")
BARE_KINDS = ("pause", "step", "clear")
MAX_NAME = 64
# WebSocket close codes: 1008 policy violation (malformed), 1009 message too big, 1011 the
# server failed on a message (a bug of its own), 1013 try again later (every page's place
# is taken).
POLICY, TOO_BIG, INTERNAL_ERROR, TRY_AGAIN_LATER = 1008, 1009, 1011, 1013


class ProtocolError(ValueError):
    """A page's message that breaks the protocol: its socket is closed with `code`."""

    def __init__(self, reason: str, code: int = POLICY):
        super().__init__(reason)
        self.code, self.reason = code, reason


@dataclass(frozen=True)
class Input:
    """One checked page message."""

    kind: str  # touch, melt, preset, look, backdrop, key, pause, step, clear, ping
    x: float = 0.0
    y: float = 0.0
    phase: str = "down"
    finger: int = 0
    name: str = ""
    stamp: float | None = None  # a ping's number, echoed in the pong


# ---- server -> page: geometry ---------------------------------------------------------

def pack_vertices(features: np.ndarray) -> bytes:
    """(n x 6 float32: x, y, z, nx, ny, nz) feature vertices as n 12-byte records."""
    out = np.zeros(len(features), VERTEX)
    xy = np.rint(features[:, :2].astype(np.float64) * SUBPIXEL)
    out["xy"] = np.clip(xy, -32768, 32767)
    out["z"] = features[:, 2]
    out["n"] = np.clip(np.rint(features[:, 3:6].astype(np.float64) * 127), -127, 127)
    return out.tobytes()


def height_runs(old: np.ndarray, new: np.ndarray, gap: int = RUN_GAP) -> list[tuple[int, int]]:
    """(start, count) runs covering every index where flat arrays `old` and `new` differ;
    changed values at most `gap` apart share a run."""
    idx = np.flatnonzero(old != new)
    if len(idx) == 0:
        return []
    cut = np.flatnonzero(np.diff(idx) > gap + 1)
    starts = idx[np.concatenate(([0], cut + 1))]
    ends = idx[np.concatenate((cut, [len(idx) - 1]))] + 1
    return [(int(s), int(e - s)) for s, e in zip(starts, ends, strict=True)]


def _message(flags: int, look: str, tick: int, grid: tuple[int, int], height_scale: float,
             runs: list[tuple[int, int]], values: np.ndarray, verts: bytes,
             box: tuple[float, float, float, float] | None) -> bytes:
    if box is not None:
        flags |= CLEAR_BOX
    head = HEADER.pack(VERSION, GEOMETRY, flags, LOOKS.index(look), tick & 0xFFFFFFFF, *grid,
                       height_scale, len(runs), len(verts) // VERTEX.itemsize,
                       *(box if box is not None else (0.0, 0.0, 0.0, 0.0)))
    heights = values.astype("<f2").tobytes()
    heights += bytes(-len(heights) % 4)
    return b"".join((head, *(RUN.pack(*r) for r in runs), heights, verts))


class Encoder:
    """The height grid as the pages hold it (half floats), kept to diff each delta
    against: a delta's heights go out as runs of the values that changed."""

    def __init__(self, cols: int, rows: int):
        self.grid = (cols, rows)
        self.heights = np.zeros(rows * cols, np.float16)  # row-major, as the pages'
        self.look, self.height_scale = "paper", 16.0

    def reset(self) -> None:
        self.heights[:] = 0

    def delta(self, delta: GeometryDelta, reset: bool = False) -> bytes:
        """One message for `delta` (`reset`: the pages clear first, as for a rebuild)."""
        if reset or delta.reset:
            self.reset()
        self.look, self.height_scale = delta.look, delta.height_scale
        cols = self.grid[0]
        lo, hi = delta.rows.start * cols, delta.rows.stop * cols
        new = np.asarray(delta.heights, np.float32).reshape(-1).astype(np.float16)
        runs = [(s + lo, n) for s, n in height_runs(self.heights[lo:hi], new)]
        self.heights[lo:hi] = new
        values = np.concatenate([self.heights[s:s + n] for s, n in runs]) if runs else new[:0]
        flags = RESET if reset or delta.reset else 0
        return _message(flags, delta.look, delta.tick, self.grid, delta.height_scale, runs,
                        values, pack_vertices(delta.features), delta.clear_box)

    def bare(self, tick: int, reset: bool) -> bytes:
        """A message with no change (a reset alone: a rebuild that sent no delta)."""
        if reset:
            self.reset()
        return _message(RESET if reset else 0, self.look, tick, self.grid, self.height_scale,
                        [], self.heights[:0], b"", None)

    def snapshot(self, tick: int, features: np.ndarray, look: str, height_scale: float,
                 heights: np.ndarray | None = None) -> list[bytes]:
        """The whole frost a page must hold: a reset, every height (one run; `heights`,
        half floats as the pages hold them, default this grid's now) and `features`, cut
        into parts of at most PART_VERTICES vertices."""
        heights = self.heights if heights is None else heights
        verts = pack_vertices(features)
        step = PART_VERTICES * VERTEX.itemsize
        chunks = [verts[i:i + step] for i in range(0, len(verts), step)] or [b""]
        whole = [(0, len(heights))]
        parts = []
        for i, chunk in enumerate(chunks):
            flags = SNAPSHOT | (RESET if i == 0 else 0) | (LAST_PART if i == len(chunks) - 1 else 0)
            runs, values = (whole, heights) if i == 0 else ([], heights[:0])
            parts.append(_message(flags, look, tick, self.grid, height_scale, runs, values,
                                  chunk, None))
        return parts


def decode_geometry(data: bytes) -> dict[str, Any]:
    """A geometry message's fields: runs as (start, count), heights as float32 values in
    run order, vertices as n x 6 float32 (x, y, z, nx, ny, nz); ValueError if malformed."""
    if len(data) < HEADER.size:
        raise ValueError(f"geometry message of {len(data)} bytes is shorter than its header")
    (version, kind, flags, look, tick, cols, rows, scale, nruns, nverts,
     *box) = HEADER.unpack_from(data)
    if version != VERSION or kind != GEOMETRY:
        raise ValueError(f"not a version {VERSION} geometry message")
    if look >= len(LOOKS) or flags & ~ALL_FLAGS:
        raise ValueError(f"geometry message with look {look} and flags {flags}: unknown")
    runs = _runs(data, nruns, cols * rows)
    nvalues = sum(n for _s, n in runs)
    at = HEADER.size + nruns * RUN.size
    verts_at = at + 2 * nvalues + (-2 * nvalues) % 4
    if verts_at + nverts * VERTEX.itemsize != len(data):
        raise ValueError(f"geometry message of {len(data)} bytes, not the "
                         f"{verts_at + nverts * VERTEX.itemsize} its header says")
    if nverts % 3:
        raise ValueError(f"geometry message of {nverts} vertices: not whole triangles")
    values = np.frombuffer(data, "<f2", nvalues, at).astype(np.float32)
    rec = np.frombuffer(data, VERTEX, nverts, verts_at)
    verts = np.empty((nverts, VERTEX_FLOATS), np.float32)
    verts[:, :2] = rec["xy"] / SUBPIXEL
    verts[:, 2] = rec["z"]
    verts[:, 3:] = rec["n"] / 127.0
    return {"flags": flags, "look": LOOKS[look], "tick": tick, "grid": (cols, rows),
            "height_scale": scale, "runs": runs, "heights": values, "vertices": verts,
            "clear_box": tuple(box) if flags & CLEAR_BOX else None}


def clock_message(box: tuple[int, int, int, int], minute: str, png: bytes) -> bytes:
    """The clock message: the PNG `png` of the box (x0, y0, x1, y1) at `minute`."""
    x0, y0, x1, y1 = box
    return CLOCK_HEADER.pack(VERSION, CLOCK, x0, y0, x1 - x0, y1 - y0, minute.encode("ascii")) + png


def decode_clock(data: bytes) -> dict[str, Any]:
    """A clock message's fields: x, y, w, h, minute, png (bytes); ValueError if malformed."""
    if len(data) < CLOCK_HEADER.size + len(PNG_SIGNATURE):
        raise ValueError(f"clock message of {len(data)} bytes is too short")
    version, kind, x, y, w, h, minute = CLOCK_HEADER.unpack_from(data)
    if version != VERSION or kind != CLOCK:
        raise ValueError(f"not a version {VERSION} clock message")
    png = data[CLOCK_HEADER.size:]
    if not png.startswith(PNG_SIGNATURE):
        raise ValueError("a clock message's picture is not a PNG")
    return {"x": x, "y": y, "w": w, "h": h, "minute": minute.decode("ascii"), "png": png}


def message_type(data: bytes) -> int:
    """The type byte of a binary message (GEOMETRY or CLOCK); 0 if too short to have one."""
    return data[1] if len(data) > 1 else 0


def _runs(data: bytes, nruns: int, cells: int) -> list[tuple[int, int]]:
    """The `nruns` runs after the header, each inside a grid of `cells` values; ValueError
    if the message is too short to hold them (checked first: a header may ask for 2**32
    of them) or one leaves the grid."""
    end = HEADER.size + nruns * RUN.size
    if end > len(data):
        raise ValueError(f"geometry message of {len(data)} bytes is shorter than its {nruns} runs")
    runs = list(RUN.iter_unpack(data[HEADER.size:end]))
    outside = next(((s, n) for s, n in runs if s + n > cells), None)
    if outside is not None:
        raise ValueError(f"a run of {outside[1]} heights at {outside[0]} leaves the grid of "
                         f"{cells}")
    return runs


def apply_geometry(heights: np.ndarray, message: dict[str, Any]) -> None:
    """Write a decoded message's heights into a page's flat height grid (a reset zeroes
    it first): what a page does with the heights."""
    if message["flags"] & RESET:
        heights[:] = 0
    at = 0
    for start, count in message["runs"]:
        heights[start:start + count] = message["heights"][at:at + count]
        at += count


# ---- server -> page: JSON -------------------------------------------------------------

def text(kind: str, **fields: Any) -> str:
    """A JSON message of type `kind`."""
    return json.dumps({"type": kind, **fields}, separators=(",", ":"))


# ---- page -> server -------------------------------------------------------------------

def parse_input(message: str | bytes) -> Input:
    """A page's message checked; ProtocolError saying what is wrong (code 1009 if it is
    over MAX_INPUT_BYTES)."""
    if isinstance(message, bytes):
        raise ProtocolError("binary messages are not accepted")
    try:
        size = len(message.encode())
    except UnicodeEncodeError:  # a lone surrogate: aiohttp never hands one over
        raise ProtocolError("not UTF-8 text") from None
    if size > MAX_INPUT_BYTES:
        raise ProtocolError(f"message over {MAX_INPUT_BYTES} bytes", TOO_BIG)
    try:
        data = json.loads(message, parse_constant=_no_constant)
    except ValueError as err:
        raise ProtocolError(f"not JSON: {str(err)[:80]}") from None
    except RecursionError:  # "[" * 1000 is under 1 KiB, and deeper than json can go
        raise ProtocolError("not JSON: nested too deep") from None
    if not isinstance(data, dict) or not isinstance(data.get("type"), str):
        raise ProtocolError("a message must be a JSON object with a string 'type'")
    kind = data["type"]
    if kind in POINTER_KINDS:
        return _pointer(kind, data)
    if kind in NAMED_KINDS:
        field = "key" if kind == "key" else "name"
        return Input(kind, name=_name(data, field))
    if kind in BARE_KINDS:
        return Input(kind)
    if kind == "ping":
        return Input(kind, stamp=_number(data, "t"))
    raise ProtocolError(f"unknown message type {kind[:MAX_NAME]!r}")


def _pointer(kind: str, data: dict) -> Input:
    phase = data.get("phase", "down")
    if phase not in PHASES:
        raise ProtocolError(f"'phase' must be one of {', '.join(PHASES)}")
    finger = data.get("id", 0)
    if not isinstance(finger, int) or isinstance(finger, bool) or not 0 <= finger < FINGERS:
        raise ProtocolError(f"'id' must be a whole number in 0..{FINGERS - 1}")
    if phase == "up" and "x" not in data:
        return Input(kind, phase=phase, finger=finger)
    return Input(kind, _number(data, "x"), _number(data, "y"), phase, finger)


def _number(data: dict, key: str) -> float:
    value = data.get(key)
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ProtocolError(f"{key!r} must be a finite number")
    try:
        number = float(value)  # a whole number of 400 digits overflows
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        raise ProtocolError(f"{key!r} must be a finite number")
    return number


def _name(data: dict, key: str) -> str:
    value = data.get(key)
    if not isinstance(value, str) or not 0 < len(value) <= MAX_NAME:
        raise ProtocolError(f"{key!r} must be a string of 1 to {MAX_NAME} characters")
    return value


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number")
