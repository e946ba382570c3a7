"""What a user reads: the README stays short, and every link and file named in the README
and docs/ leads to something in this repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md")),
         *sorted((ROOT / "docs" / "results").glob("*.md"))]
README_MOST_WORDS = 1200  # \w+ tokens, code and links included: two minutes' reading
PICTURE_WITHIN = 3000  # characters: the frost is the first thing a reader sees
# A Markdown image of the frost: ![alt](path.png|webp|jpg|gif)
PICTURE = re.compile(r"!\[[^\]]*\]\(([^)\s]+\.(?:png|webp|jpg|gif))\)")
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")  # [text](target) and ![alt](target)
# A file of the repository named in the text, e.g. `app/tools/render_png.py` or docs/panel.webp.
NAMED_FILE = re.compile(r"\b((?:app|sim|tests|shaders|assets|docs)/[\w./-]*\w\.(?:py|md|frag|vert|"
                        r"webp|png|json))\b")


def page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def links(page: Path) -> list[str]:
    return LINK.findall(page.read_text(encoding="utf-8"))


def anchor(heading: str) -> str:
    """The anchor a Markdown heading gets (GitHub's rule): lower case, every character but
    letters, digits, `_`, `-` and spaces dropped, spaces made dashes."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(page: Path) -> set[str]:
    headings = [line.lstrip("#") for line in page.read_text(encoding="utf-8").splitlines()
                if re.match(r"#{1,6} ", line)]
    return {anchor(h) for h in headings}


def test_anchor_follows_githubs_rule_on_hand_worked_headings():
    assert anchor(" 5. Beyond the paper: limits the paper states") == \
        "5-beyond-the-paper-limits-the-paper-states"
    assert anchor(" 7. The frosted window (`window_frost`; `sim/rules/pane.py`)") == \
        "7-the-frosted-window-window_frost-simrulespanepy"


def test_the_readme_is_short():
    words = re.findall(r"\w+", (ROOT / "README.md").read_text(encoding="utf-8"))
    assert len(words) <= README_MOST_WORDS, f"README.md has {len(words)} words"


def test_the_readme_opens_with_a_picture_of_the_frost():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    found = PICTURE.search(text)
    assert found, "README.md shows no picture"
    assert found.start() < PICTURE_WITHIN, f"README.md's first picture is at character {found.start()}"
    assert (ROOT / found.group(1)).is_file(), found.group(1)


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_link_resolves_inside_the_repository(page):
    found = links(page)
    assert found or page.name != "README.md"  # the README links the docs
    for target in found:
        assert not re.match(r"[a-z]+:", target), f"{target}: points outside the repository"
        path, _, fragment = target.partition("#")
        where = (page.parent / path).resolve() if path else page
        assert where.is_relative_to(ROOT), f"{target}: outside the repository"
        assert where.is_file(), f"{target}: no such file"
        if fragment and where.suffix == ".md":
            assert fragment in anchors(where), f"{target}: no such heading in {where.name}"


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_no_address_outside_the_repository(page):
    """No address a reader would follow off this machine (this machine's own server, as
    `frost serve` prints it, is no outside address)."""
    addresses = re.findall(r"\b(?:https?|ftp)://\S+", page.read_text(encoding="utf-8"))
    assert [a for a in addresses if not re.match(r"https?://(127\.0\.0\.1|localhost)[:/]", a)] == []


@pytest.mark.parametrize("page", PAGES, ids=page_id)
def test_every_file_named_exists(page):
    missing = [name for name in NAMED_FILE.findall(page.read_text(encoding="utf-8"))
               if not (ROOT / name).exists() and not (page.parent / name).exists()]
    assert missing == []


def sentences(page: Path) -> list[str]:
    """The page's text but its headings, cut at each full stop or semicolon."""
    lines = page.read_text(encoding="utf-8").splitlines()
    text = " ".join(line for line in lines if not line.startswith("#"))
    return re.split(r"(?<=[.;])\s+", " ".join(text.split()))


def test_the_window_page_gives_recordings_the_size_and_the_cap_they_have():
    """docs/window.md against app/window/record.py: a sentence naming recordings and a
    size names the recordings' own (they are the phone downscaled, not its 760×1280),
    and the cap is MAX_FRAMES."""
    from app.window.record import FRAME_SIZE, MAX_FRAMES

    size, page = "{}×{}".format(*FRAME_SIZE), sentences(ROOT / "docs" / "window.md")
    told = [s for s in page if "recording" in s.lower() and re.search(r"\d+×\d+", s)]
    assert told, "docs/window.md says no recording's size"
    for sentence in told:
        assert size in sentence, sentence
    assert f"at {MAX_FRAMES} distinct frames" in " ".join(page)
