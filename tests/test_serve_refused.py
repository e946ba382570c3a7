"""What a refused request is answered (app/serve/routes.py, token_check): on the page's
own paths, and a browser's navigation to any but the API's, a small page sized for a phone
saying why (the installed app opened at its old address showed a line of text in a
desktop's tiny type); the API's refusals stay one line of text. The oracle: the HTML read
back with Python's own parser."""

from __future__ import annotations

from html.parser import HTMLParser

from support.page_model import serve

NAVIGATE = {"Sec-Fetch-Mode": "navigate", "Sec-Fetch-Dest": "document"}
API = ("/meta", "/ws", "/app.json", "/sw.js", "/manifest.webmanifest")


class Read(HTMLParser):
    """A page's <meta name=... content=...> pairs and its visible text."""

    def __init__(self, page: str):
        super().__init__()
        self.metas: dict[str, str] = {}
        self.text: list[str] = []
        self.skip = 0  # inside <style>, <title>
        self.feed(page)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "meta" and "name" in a:
            self.metas[a["name"]] = a.get("content") or ""
        self.skip += tag in ("style", "title", "script")

    def handle_endtag(self, tag):
        self.skip -= tag in ("style", "title", "script")

    def handle_data(self, data):
        if not self.skip and data.strip():
            self.text.append(data.strip())


async def refusal_page(client, path: str, headers=None) -> Read:
    """`path`'s 403, which must be the page for a phone: read back."""
    resp = await client.get(path, headers=headers or {})
    assert resp.status == 403, path
    assert resp.content_type == "text/html", (path, resp.content_type)
    assert resp.headers["Cache-Control"] == "no-store"
    page = Read(await resp.text())
    assert page.metas["viewport"].startswith("width=device-width"), path
    return page


async def refusal_line(client, path: str, headers=None) -> str:
    resp = await client.get(path, headers=headers or {})
    assert resp.status == 403, path
    assert resp.content_type == "text/plain", (path, resp.content_type)
    body = await resp.text()
    assert body.count("\n") == 1 and body.startswith("frost: "), body
    return body


def test_a_replaced_token_on_the_pages_own_paths_is_a_page_that_says_so():
    async def test(client, feed):
        for path in ("/?token=old", "/index.html?token=old"):
            said = " ".join((await refusal_page(client, path)).text)
            assert "token" in said and "replaced" in said and "QR code" in said, said
        # The installed app opened at some other address of the site: a navigation.
        said = " ".join((await refusal_page(client, "/app?token=old", NAVIGATE)).text)
        assert "replaced" in said
        # Without any token: what it needs, not that it was replaced.
        said = " ".join((await refusal_page(client, "/")).text)
        assert "needs its token" in said and "replaced" not in said, said
        # The right token: the page itself.
        resp = await client.get("/?token=s3cret")
        assert resp.status == 200 and "<canvas" in await resp.text()
    serve(test, token="s3cret")


def test_the_apis_refusals_stay_a_line_of_text():
    async def test(client, feed):
        for path in API:
            for headers in ({}, NAVIGATE):  # (a person may open /meta in a browser)
                line = await refusal_line(client, f"{path}?token=old", headers)
                assert "token" in line
        await refusal_line(client, "/shaders/ice.frag?token=old")  # the page's files: fetched
    serve(test, token="s3cret")


def test_a_name_not_this_machines_gets_the_page_on_loopback_too():
    async def test(client, feed):
        host = {"Host": "evil.example:8025"}
        said = " ".join((await refusal_page(client, "/", host)).text)
        assert "127.0.0.1" in said and "token" not in said, said
        assert "names" in await refusal_line(client, "/meta", host)
    serve(test)
