"""Where the files beside the code are: the GLSL shaders and the background image.

In a checkout they are the top-level `shaders/` and `assets/` folders; an installed
wheel carries them inside the package, as `app/_data/shaders` and `app/_data/assets`
(copied there by setup.py)."""

from __future__ import annotations

from pathlib import Path

_HERE = Path(__file__).resolve().parent


def resource_dir(name: str) -> Path:
    """The folder `name` ("shaders" or "assets"), installed or in the checkout."""
    installed = _HERE / "_data" / name
    return installed if installed.is_dir() else _HERE.parent / name


SHADER_DIR = resource_dir("shaders")
ASSET_DIR = resource_dir("assets")
# The phone page (HTML, ES modules, CSS): inside the package, installed or not.
WEB_DIR = _HERE / "web"
