"""Text files are read and written as UTF-8, said each time: without an encoding, Python
uses the locale's (cp1252 on Windows), and a session, a shader or a page with one non-ASCII
character reads wrong there or not at all. A scan of the source finds every call that
leaves it out, at once and on any machine (a run only meets the calls it makes)."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SOURCES = ("app", "sim", "tests", "assets")
# Path's methods of text that take an encoding: where, among positional arguments, it is.
TEXT_METHODS = {"read_text": 0, "write_text": 1}


def binary(mode: ast.expr | None) -> bool:
    """Whether `mode` (an open()'s mode argument, None: the default "r") is binary; a
    mode computed at run time counts as text (the encoding is then due)."""
    return isinstance(mode, ast.Constant) and isinstance(mode.value, str) and "b" in mode.value


def argument(call: ast.Call, keyword: str, position: int) -> ast.expr | None:
    """The argument `keyword` of `call`, given by name or at `position`; None if absent."""
    named = [k.value for k in call.keywords if k.arg == keyword]
    return named[0] if named else call.args[position] if len(call.args) > position else None


def unspoken(call: ast.Call) -> bool:
    """Whether `call` opens text with the locale's encoding: open(...) and Path.open(mode)
    in a text mode, Path.read_text() and Path.write_text(...), with no encoding."""
    func = call.func
    if isinstance(func, ast.Name) and func.id == "open":  # the builtin: encoding 4th
        return not binary(argument(call, "mode", 1)) and argument(call, "encoding", 3) is None
    if not isinstance(func, ast.Attribute):
        return False
    if func.attr in TEXT_METHODS:
        return argument(call, "encoding", TEXT_METHODS[func.attr]) is None
    # Path.open's mode comes first; a .open without one (Image.open(path), os.open(path,
    # flags), a queue's open()) is some other open, left alone.
    mode = argument(call, "mode", 0)
    return (func.attr == "open" and is_mode(mode) and not binary(mode)
            and argument(call, "encoding", 2) is None)


def is_mode(mode: ast.expr | None) -> bool:
    """Whether `mode` is written out as an open()'s mode ("w", "r+"; not "http://...")."""
    return (isinstance(mode, ast.Constant) and isinstance(mode.value, str)
            and bool(mode.value) and set(mode.value) <= set("rwaxbt+"))


def without_encoding(source: str, name: str = "<source>") -> list[str]:
    """"name:line: call" for each call in `source` that opens text with no encoding."""
    return [f"{name}:{node.lineno}: {ast.unparse(node)}" for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Call) and unspoken(node)]


@pytest.mark.parametrize("call", [
    "open(p)", "open(p, 'w')", "open(p, mode='a')", "open(p, m)", "open(p, 'r', 1)",
    "p.read_text()", "p.read_text(errors='replace')", "p.write_text(s)",
    "p.open('w')", "p.open(mode='r')", "json.load(open(p))"])
def test_the_scan_finds_text_opened_without_an_encoding(call):
    assert len(without_encoding(call)) == 1, call


@pytest.mark.parametrize("call", [
    "open(p, 'rb')", "open(p, mode='wb')", "open(p, encoding='utf-8')",
    "open(p, 'w', -1, 'utf-8')", "p.read_text(encoding='utf-8')", "p.read_text('utf-8')",
    "p.write_text(s, encoding='utf-8')", "p.write_text(s, 'utf-8')", "p.open('rb')",
    "p.open('w', encoding='utf-8')", "Image.open(p)", "os.open(p, os.O_RDONLY)",
    "turns.open()", "p.read_bytes()", "webbrowser.open(url)",
    "webbrowser.open('http://127.0.0.1/')"])
def test_the_scan_passes_binary_files_explicit_encodings_and_other_opens(call):
    assert without_encoding(call) == [], call


def test_every_text_file_is_opened_with_an_explicit_encoding():
    found = []
    for folder in SOURCES:
        for path in sorted((ROOT / folder).rglob("*.py")):
            name = str(path.relative_to(ROOT))
            found += without_encoding(path.read_text(encoding="utf-8"), name)
    assert found == [], "text opened with the locale's encoding:\n" + "\n".join(found)
