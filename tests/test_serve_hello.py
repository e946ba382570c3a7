"""The hello (app/serve/hello.py), built in one place: what `frost serve` sends a page and
what the benches hand theirs are the same, and it holds what docs/protocol.md says."""

from __future__ import annotations

import dataclasses
import json

import pytest

from app.serve.feed import Feed
from bench.page import hello as bench_hello
from sim import Params
from sim.look.material import Material


@pytest.mark.parametrize("spacing, backdrop", [(4, "dusk"), (6, "lockscreen")])
def test_the_benches_hello_is_the_one_the_server_sends(spacing, backdrop):
    params = dataclasses.replace(Params.preset("fern"), grid_spacing=spacing)
    served = json.loads(Feed(params, 1, backdrop=backdrop).hello())
    bench = bench_hello(params, backdrop)
    assert {k: served[k] for k in bench} == bench


def test_the_hello_holds_the_grid_and_material_worked_by_hand():
    params = dataclasses.replace(Params.preset("fern"), grid_spacing=5)
    hello = json.loads(Feed(params, 1, melt_radius=30.0, backdrop="dusk").hello())
    # 760 x 1280 px at a vertex every 5 px: 153 columns and 257 rows, ends included.
    assert (hello["type"], hello["protocol"], hello["screen"]) == ("hello", 1, [760, 1280])
    assert (hello["grid"], hello["spacing"], hello["melt_radius"]) == ([153, 257], 5, 30.0)
    m = Material()
    assert hello["uniforms"]["u_ice_color"] == list(m.ice_color)
    assert hello["uniforms"]["u_refraction"] == m.refraction
    assert hello["view"]["background"] == "dusk" and hello["backdrop"] == "dusk"
    assert hello["defines"]["glass"]["feature"] == ["EDGE_AA"]
    assert hello["tick"] == 0 and hello["paused"] is False
