"""The page's own simulation reads its parameters from one source (issue 49, item 2):
app/web/local/params.json is what app/serve/local_params.py makes of sim/params.py and the
server's hello, and the service worker's shell carries it."""

from __future__ import annotations

import json

from app.resources import WEB_DIR
from app.serve import local_params
from app.serve.hello import hello_fields
from app.serve.install import Shell
from sim import Params, all_presets
from sim.params import LOOKS


def test_the_file_is_what_the_parameters_make_now():
    # (after a change to sim/params.py or the hello: python -m app.serve.local_params)
    assert local_params.FILE.read_text(encoding="utf-8") == local_params.text(), \
        "app/web/local/params.json is out of date: run python -m app.serve.local_params"


def test_every_preset_is_the_simulations_own():
    data = json.loads(local_params.FILE.read_text(encoding="utf-8"))
    assert list(data["presets"]) == list(all_presets())
    for name, values in data["presets"].items():
        assert Params(**values) == Params.preset(name)  # (each a whole, valid parameter set)
    assert data["presets"][data["default_preset"]]["look"] in LOOKS
    hc = data["limits"]["hc"]
    assert (hc["default"], hc["lo"], hc["hi"]) == (Params.hc, 1.0, 16.0)
    assert data["limits"]["look"]["choices"] == list(LOOKS)


def test_the_hello_is_the_servers_for_the_default_preset():
    data = json.loads(local_params.FILE.read_text(encoding="utf-8"))
    fern = Params.preset("fern")
    hello = data["hello"]
    server = json.loads(json.dumps(hello_fields(fern, "dusk", tuple(hello["grid"]))))
    assert {k: hello[k] for k in server} == server
    assert hello["grid"] == [760 // fern.grid_spacing + 1, 1280 // fern.grid_spacing + 1]
    assert "lockscreen" not in hello["backdrops"]  # (its clock is the server's)


def test_the_installed_app_caches_it_and_the_local_modules():
    urls = {url for url, _ in Shell(WEB_DIR).files()}
    assert "web/local/params.json" in urls
    assert {f"web/local/{p.name}" for p in (WEB_DIR / "local").glob("*.js")} <= urls
