"""`frost render --weather` against a stand-in API (issue 48's `weather` check): -25 C outside
frosts the window preset's pane, +6 C leaves it clear, and an API out of reach still renders,
saying so in one line. The frosted share is counted as the issue states it: pixels where a
channel differs by more than 12 from the same render's tick 1 without --weather."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from support.weather_api import StandIn

ROOT = Path(__file__).resolve().parent.parent
PANE = ["--preset", "window", "--seed", "2"]
TICKS = "900"


def render(tmp_path: Path, name: str, *args: str) -> tuple[np.ndarray, list[str]]:
    """The render's pixels and its lines, in a config folder of the test's own."""
    out = tmp_path / f"{name}.png"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "XDG_CONFIG_HOME": str(tmp_path / name)}
    run = subprocess.run([sys.executable, "-m", "app", "render", *PANE, "--out", str(out), *args],
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    lines = [line for line in (run.stdout + run.stderr).splitlines() if not line.startswith("tick ")]
    return np.asarray(Image.open(out).convert("RGB")).astype(int), lines


def frosted(image: np.ndarray, bare: np.ndarray) -> float:
    return float((np.abs(image - bare) > 12).any(axis=2).mean())


@pytest.mark.usefixtures("subprocesses")
def test_minus_25_outside_frosts_the_pane_and_plus_6_leaves_it_clear(gl_ctx, tmp_path):
    bare, _ = render(tmp_path, "bare", "--ticks", "1")
    with StandIn(-25.0) as api:
        cold, cold_said = render(tmp_path, "cold", "--ticks", TICKS, "--weather", "59.33,18.07",
                                 "--weather-api", api.url)
        api.current["temperature_2m"] = 6.0
        warm, warm_said = render(tmp_path, "warm", "--ticks", TICKS, "--weather", "59.33,18.07",
                                 "--weather-api", api.url)
    assert cold_said[0] == ("weather: -25.0 C, 80 %, dew point -27.6 C at 23:00: glass -14 C, "
                            "frost grows")
    assert warm_said[0].startswith("weather: 6.0 C") and warm_said[0].endswith("glass 9 C, frost melts")
    assert frosted(cold, bare) >= 0.10
    assert frosted(warm, bare) <= 0.02


@pytest.mark.usefixtures("subprocesses")
def test_an_api_out_of_reach_still_renders_and_says_so_in_one_line(gl_ctx, tmp_path):
    with StandIn() as api:
        closed = api.url  # (nothing listens there once it has stopped)
    image, said = render(tmp_path, "offline", "--ticks", "5", "--weather", "Oslo",
                         "--weather-api", closed, "--geocoding-api", closed)
    weather = [line for line in said if "weather" in line]
    assert len(weather) == 1 and weather[0].startswith("weather: cannot reach 127.0.0.1:")
    assert weather[0].endswith("Connection refused: the frost grows by the preset's own temperature")
    assert image.shape == (1280, 760, 3)
