"""`frost web DIR` (app/tools/web_site.py): the phone page as a static site. What it writes
(the page's files as frost serve serves them, byte for byte; the built-in backdrops as
their pixels; the manifest and worker made once; the site's config and version), every
address relative (the site works under a sub-path), a rebuild that replaces the old site
whole, and a DIR it cannot take refused in one line with exit status 2. The site in a
browser: tests/test_site_e2e.py."""

from __future__ import annotations

import hashlib
import io
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.backdrops import BACKDROPS, load_backdrop
from app.cli.commands import main as frost
from app.resources import SHADER_DIR, WEB_DIR

ROOT = Path(__file__).resolve().parent.parent
TEXT = (".html", ".js", ".css", ".json", ".webmanifest")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("web") / "site"
    assert frost(["web", str(folder), "--weather-api", "https://weather.test/",
                  "--geocoding-api", "http://places.test:8080"]) == 0
    return folder


def shell(site: Path) -> dict:
    first = (site / "sw.js").read_text(encoding="utf-8").split("\n", 1)[0]
    return json.loads(first.removeprefix("const SHELL = ").removesuffix(";"))


def written(site: Path) -> set[str]:
    return {p.relative_to(site).as_posix() for p in site.rglob("*") if p.is_file()}


def test_the_site_holds_the_pages_files_as_frost_serve_serves_them(site):
    files = shell(site)["files"]
    # the worker's files and its own three: nothing more, nothing less
    assert written(site) == {f or "index.html" for f in files} | {"sw.js", "version.json",
                                                                  "manifest.webmanifest"}
    for page_file in WEB_DIR.rglob("*"):
        rel = page_file.relative_to(WEB_DIR).as_posix()
        if not page_file.is_file() or "__pycache__" in rel or rel in ("sw.js", "site.js"):
            continue
        at = site / ("index.html" if rel == "index.html" else f"web/{rel}")
        assert at.read_bytes() == page_file.read_bytes(), rel
    for shader in SHADER_DIR.iterdir():
        assert (site / "shaders" / shader.name).read_bytes() == shader.read_bytes()
    for name in BACKDROPS:  # a file, of the pixels frost serve draws
        image = np.asarray(Image.open(io.BytesIO((site / "backdrops" / f"{name}.png").read_bytes())))
        assert np.array_equal(image, load_backdrop(name, minute=None)), name
    worker = (site / "sw.js").read_text(encoding="utf-8").split("\n", 1)[1]
    assert worker == (WEB_DIR / "sw.js").read_text(encoding="utf-8")


def test_the_version_is_the_hash_of_every_cached_file(site):
    """The worker's hash and version.json's are one, of every file the worker caches (its
    address, length and bytes: 16 hex digits of SHA-256, as frost serve's), so any change
    to the site changes both."""
    h = hashlib.sha256()
    for url in shell(site)["files"]:
        data = (site / (url or "index.html")).read_bytes()
        h.update(url.encode() + b"\0" + str(len(data)).encode() + b"\0" + data)
    digest = h.hexdigest()[:16]
    assert shell(site)["hash"] == digest
    assert json.loads((site / "version.json").read_text(encoding="utf-8")) == {"build": digest}
    assert shell(site)["version"] == "version.json"
    assert "version.json" not in shell(site)["files"]  # (asked of the network, never cached)


def test_the_config_says_static_and_names_the_weather_apis(site):
    text = (site / "web" / "site.js").read_text(encoding="utf-8")
    config = json.loads(re.search(r"export const SITE = (\{.*\});", text).group(1))
    assert config == {"static": True, "weather_api": "https://weather.test",
                      "geocoding_api": "http://places.test:8080"}
    assert "static: false" in (WEB_DIR / "site.js").read_text(encoding="utf-8")  # frost serve's


def test_the_default_weather_apis_are_open_meteos(tmp_path):
    assert frost(["web", str(tmp_path / "s")]) == 0
    text = (tmp_path / "s" / "web" / "site.js").read_text(encoding="utf-8")
    assert '"weather_api": "https://api.open-meteo.com"' in text
    assert '"geocoding_api": "https://geocoding-api.open-meteo.com"' in text


def test_every_address_is_relative(site):
    """No file names an address from the host's root: the site works under /frost/."""
    for rel in written(site):
        if rel.endswith(TEXT):
            text = (site / rel).read_text(encoding="utf-8")
            for absolute in ('src="/', "href=\"/", "href='/", "src='/", "url(/", 'url("/', "url('/"):
                assert absolute not in text, (rel, absolute)
    manifest = json.loads((site / "manifest.webmanifest").read_text(encoding="utf-8"))
    assert (manifest["start_url"], manifest["scope"], manifest["id"]) == ("./", "./", "./")
    assert manifest["display"] == "standalone"
    for icon in manifest["icons"]:
        assert not icon["src"].startswith("/") and (site / icon["src"]).is_file()
    assert {(i["purpose"], i["sizes"]) for i in manifest["icons"]} >= {("any", "192x192"), ("any", "512x512")}


def test_a_rebuild_replaces_the_old_site_whole(tmp_path):
    folder = tmp_path / "site"
    assert frost(["web", str(folder)]) == 0
    (folder / "web" / "old.js").write_text("// of an older build\n", encoding="utf-8")
    first = (folder / "version.json").read_text(encoding="utf-8")
    assert frost(["web", str(folder), "--weather-api", "https://elsewhere.test"]) == 0
    assert not (folder / "web" / "old.js").exists()
    assert (folder / "version.json").read_text(encoding="utf-8") != first  # site.js changed: a new build
    assert sorted(p.name for p in tmp_path.iterdir()) == ["site"]  # nothing left beside it


@pytest.mark.parametrize("case", ["a file", "a foreign folder", "an api"])
def test_a_dir_it_cannot_take_is_one_line_and_exit_status_2(tmp_path, capsys, case):
    folder = tmp_path / "x"
    args = ["web", str(folder)]
    if case == "a file":
        folder.write_text("not a folder", encoding="utf-8")
    elif case == "a foreign folder":
        folder.mkdir()
        (folder / "notes.txt").write_text("mine", encoding="utf-8")
    else:
        args += ["--weather-api", "ftp://weather.test"]
    try:
        status = frost(args)
    except SystemExit as end:
        status = end.code
    err = capsys.readouterr().err
    assert status == 2
    assert len(err.strip().splitlines()) == 1 and err.startswith("frost: error: "), err
    if case == "a foreign folder":  # untouched
        assert sorted(p.name for p in folder.iterdir()) == ["notes.txt"]
        assert sorted(p.name for p in tmp_path.iterdir()) == ["x"]
    else:
        assert not (tmp_path / "x").is_dir()


def test_make_web_writes_site_which_git_ignores(tmp_path):
    from support.make import planned

    assert planned("web", tmp_path / "venv").strip().endswith("-m app web site")
    git = shutil.which("git")
    if git and (ROOT / ".git").exists():
        done = subprocess.run([git, "check-ignore", "-q", "site/index.html"], cwd=ROOT, timeout=30)
        assert done.returncode == 0, "site/ is not git-ignored"


def test_the_pages_workflow_builds_the_site_with_frost_web_and_deploys_it():
    """.github/workflows/pages.yml (read as text: no YAML parser among the dependencies):
    on a push to main it runs `frost web site`, uploads site/ as the Pages artifact and
    deploys it, with the permissions Pages needs."""
    text = (ROOT / ".github" / "workflows" / "pages.yml").read_text(encoding="utf-8")
    lines = [line.split("#")[0].rstrip() for line in text.splitlines()]
    assert "  push:" in lines and "    branches: [main]" in lines
    build = lines.index("        run: frost web site")
    upload = lines.index("      - uses: actions/upload-pages-artifact@v3")
    assert lines[upload + 1:upload + 3] == ["        with:", "          path: site"]
    assert build < upload < lines.index("        uses: actions/deploy-pages@v4")
    assert {"  pages: write", "  id-token: write"} <= set(lines)
