"""HTTPS on the LAN that a phone trusts (app/serve/trust.py, docs/phone.md "HTTPS on your
network"): the local authority made once and kept in the config folder, the server's
certificate it issues, `frost serve --host 0.0.0.0` on two ports. The oracles are
independent of the code under test: Python's own TLS client trusting the kept authority's
file alone (ssl.create_default_context(cafile=...)), the certificates read back with
`cryptography`, the file modes from the file system, a system Chromium told to trust the
authority through its NSS database (certutil)."""

from __future__ import annotations

import asyncio
import contextlib
import datetime as dt
import io
import json
import os
import re
import socket
import ssl
import stat
import subprocess
import sys
from pathlib import Path

import aiohttp
import numpy as np
import pytest
from cryptography import x509
from cryptography.hazmat.primitives import serialization
from cryptography.x509.oid import ExtendedKeyUsageOID
from PIL import Image
from support.https import browser_problem, trusting_chromium, trusting_home
from support.phone import PHONE, synced
from support.serve import lan_serve

from app.serve import trust
from bench.serve_process import ServeProcess

ROOT = Path(__file__).resolve().parent.parent


def cert_of(path: Path) -> x509.Certificate:
    return x509.load_pem_x509_certificate(path.read_bytes())


# ---- the authority and the certificate, in process ------------------------------------------

def test_the_config_folder_is_the_platforms_own():
    home = Path("/home/ann")
    assert trust.config_dir({"XDG_CONFIG_HOME": "/x/cfg"}, "linux", home) == Path("/x/cfg/frost")
    assert trust.config_dir({}, "linux", home) == Path("/home/ann/.config/frost")
    assert trust.config_dir({"XDG_CONFIG_HOME": "rel"}, "linux", home) == Path("/home/ann/.config/frost")
    assert trust.config_dir({}, "darwin", home) == Path("/home/ann/Library/Application Support/frost")
    assert trust.config_dir({"APPDATA": "C:/Users/ann/AppData/Roaming"}, "win32", home) == \
        Path("C:/Users/ann/AppData/Roaming/frost")


@pytest.mark.usefixtures("subprocesses")
def test_frost_info_names_the_config_folder_and_what_it_holds(tmp_path):
    """A user has a way to find the authority, the token and the QR images: `frost info`
    names the folder they are in (here the one XDG_CONFIG_HOME says)."""
    run = subprocess.run([sys.executable, "-m", "app", "info"], cwd=ROOT, capture_output=True,
                         text=True, timeout=120,
                         env={**os.environ, "XDG_CONFIG_HOME": str(tmp_path)})
    assert run.returncode == 0, run.stderr
    [line] = [line for line in run.stdout.splitlines() if line.startswith("config folder: ")]
    assert line.startswith(f"config folder: {tmp_path / 'frost'} ("), line
    assert all(word in line for word in ("authority", "token", "QR images", "weather")), line


NAMES = sorted(["127.0.0.1", "::1", "localhost", "192.168.1.20", "pane", "pane.local"])


def test_the_authority_is_made_once_and_issues_a_certificate_apple_accepts(tmp_path):
    folder = tmp_path / "frost"
    now = dt.datetime(2026, 11, 26, 12, tzinfo=dt.timezone.utc)
    issued = trust.local_certificate(folder, NAMES, now)
    ca, leaf = cert_of(folder / "ca.crt"), cert_of(folder / "server.pem")
    assert issued.ca_der == ca.public_bytes(serialization.Encoding.DER)
    # the authority: a CA that may sign servers only (path length 0), for ten years
    bc = ca.extensions.get_extension_for_class(x509.BasicConstraints)
    assert bc.critical and bc.value.ca and bc.value.path_length == 0
    assert ca.extensions.get_extension_for_class(x509.KeyUsage).value.key_cert_sign
    assert ca.subject == ca.issuer
    # the server's: signed by it, its names in the SANs, serverAuth, at most 825 days
    leaf.verify_directly_issued_by(ca)
    assert not leaf.extensions.get_extension_for_class(x509.BasicConstraints).value.ca
    san = leaf.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert sorted(san.get_values_for_type(x509.DNSName)) == ["localhost", "pane", "pane.local"]
    assert sorted(map(str, san.get_values_for_type(x509.IPAddress))) == ["127.0.0.1", "192.168.1.20", "::1"]
    assert list(leaf.extensions.get_extension_for_class(x509.ExtendedKeyUsage).value) == \
        [ExtendedKeyUsageOID.SERVER_AUTH]
    life = leaf.not_valid_after_utc - leaf.not_valid_before_utc
    assert dt.timedelta(days=700) < life <= dt.timedelta(days=825)
    assert leaf.not_valid_before_utc <= now < leaf.not_valid_after_utc
    # the private keys readable by the user alone, in a folder of the user alone
    for name in ("ca.key", "server.pem"):
        assert stat.S_IMODE((folder / name).stat().st_mode) == 0o600, name
    assert stat.S_IMODE(folder.stat().st_mode) == 0o700
    assert b"PRIVATE KEY" not in (folder / "ca.crt").read_bytes()


def test_the_certificate_is_kept_and_issued_again_when_names_change_or_it_nears_its_end(tmp_path):
    folder = tmp_path / "frost"
    now = dt.datetime(2026, 11, 26, 12, tzinfo=dt.timezone.utc)
    trust.local_certificate(folder, NAMES, now)
    ca_bytes, first = (folder / "ca.crt").read_bytes(), (folder / "server.pem").read_bytes()
    trust.local_certificate(folder, NAMES, now + dt.timedelta(days=100))  # nothing changed
    assert (folder / "server.pem").read_bytes() == first
    moved = sorted(NAMES + ["10.0.0.7"])  # the laptop on another network
    trust.local_certificate(folder, moved, now + dt.timedelta(days=100))
    second = (folder / "server.pem").read_bytes()
    assert second != first and trust.san_names(cert_of(folder / "server.pem")) == moved
    # 20 days before its end (fewer than 30 left): issued anew, valid from then
    late = cert_of(folder / "server.pem").not_valid_after_utc - dt.timedelta(days=20)
    trust.local_certificate(folder, moved, late)
    assert (folder / "server.pem").read_bytes() != second
    assert cert_of(folder / "server.pem").not_valid_after_utc > late + dt.timedelta(days=700)
    # the same authority throughout, which signed each
    assert (folder / "ca.crt").read_bytes() == ca_bytes
    cert_of(folder / "server.pem").verify_directly_issued_by(cert_of(folder / "ca.crt"))


def test_a_certificate_of_another_authority_is_replaced_by_one_of_the_kept_one(tmp_path):
    trust.local_certificate(tmp_path / "a", NAMES)
    trust.local_certificate(tmp_path / "b", NAMES)
    (tmp_path / "b" / "server.pem").write_bytes((tmp_path / "a" / "server.pem").read_bytes())
    trust.local_certificate(tmp_path / "b", NAMES)
    cert_of(tmp_path / "b" / "server.pem").verify_directly_issued_by(cert_of(tmp_path / "b" / "ca.crt"))


def test_a_damaged_authority_is_one_clear_error_not_a_silent_new_one(tmp_path):
    trust.local_certificate(tmp_path, NAMES)
    (tmp_path / "ca.key").write_bytes(b"not a key")
    with pytest.raises(trust.TrustError, match="move that folder away"):
        trust.local_certificate(tmp_path, NAMES)


def test_the_token_is_kept_and_replaced_when_asked(tmp_path):
    token = trust.kept_token(tmp_path)
    assert re.fullmatch(r"[\w-]{22}", token)
    assert trust.kept_token(tmp_path) == token
    assert stat.S_IMODE((tmp_path / "token").stat().st_mode) == 0o600
    new = trust.kept_token(tmp_path, new=True)
    assert new != token and trust.kept_token(tmp_path) == new


@pytest.mark.parametrize("mode", [0o640, 0o604, 0o660, 0o644], ids=oct)
def test_a_kept_private_file_readable_by_anyone_else_is_made_the_users_alone(tmp_path, mode):
    """The token, the authority's key and the server's key, kept with a wider mode (a copy,
    a restore from a backup), are read and left readable by the user alone: no bit for the
    group nor for others (the mode from the file system is the oracle)."""
    now = dt.datetime(2026, 11, 26, 12, tzinfo=dt.timezone.utc)
    token = trust.kept_token(tmp_path)
    trust.local_certificate(tmp_path, NAMES, now)
    private = ("token", "ca.key", "server.pem")
    for name in private:
        os.chmod(tmp_path / name, mode)
    assert trust.kept_token(tmp_path) == token
    trust.local_certificate(tmp_path, NAMES, now)
    for name in private:
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o600, name


@pytest.mark.parametrize("kept", [b"", b"short\n", b"a token with spaces in it\n", b"x" * 65,
                                  b"\xff\xfe" * 12, b"abcdefghijklmnop;rm -rf\n"])
def test_a_kept_token_file_not_holding_a_token_is_replaced_by_a_new_one(tmp_path, kept):
    """A token must be 16 to 64 of the URL-safe characters (a page carries it in its
    address): any other content of the file is replaced by a new token, kept."""
    (tmp_path / "token").write_bytes(kept)
    token = trust.kept_token(tmp_path)
    assert re.fullmatch(r"[A-Za-z0-9_-]{16,64}", token) and token.encode() != kept.strip()
    assert (tmp_path / "token").read_text(encoding="utf-8").strip() == token
    assert trust.kept_token(tmp_path) == token


def test_the_machines_names_hold_its_host_name_lan_address_and_loopback():
    names = trust.machine_names("0.0.0.0", lan="192.168.1.20", hostname="Pane")
    assert {"localhost", "127.0.0.1", "::1", "pane", "pane.local", "192.168.1.20"} <= set(names)
    assert "0.0.0.0" not in names
    for every in ("0.0.0.0", "::", ""):  # a wildcard names no address: no certificate holds it
        held = trust.machine_names(every, lan=None, hostname="pane")
        assert every not in held and {"localhost", "127.0.0.1", "::1"} <= set(held), every
    assert "10.1.2.3" in trust.machine_names("10.1.2.3", lan=None, hostname="pane")
    assert "bad_name" not in trust.machine_names("0.0.0.0", lan=None, hostname="bad_name")


@pytest.mark.parametrize(("written", "canonical"), [
    ("0:0:0:0:0:0:0:1", "::1"), ("0000::0001", "::1"), ("FE80:0:0::1", "fe80::1"),
    ("10.1.2.3", "10.1.2.3")])
def test_an_address_however_written_is_named_once_in_its_canonical_form(written, canonical):
    # the oracle: the names for the address written canonically (RFC 5952, by hand)
    names = trust.machine_names(written, lan="192.168.1.20", hostname="pane")
    assert names == trust.machine_names(canonical, lan="192.168.1.20", hostname="pane")
    assert names.count("::1") == 1 and canonical in names


@pytest.mark.parametrize("anywhere", ["0:0:0:0:0:0:0:0", "::0", "0.0.0.0", "::"])
def test_every_address_however_written_names_no_address_of_its_own(anywhere):
    assert trust.machine_names(anywhere, lan=None, hostname="pane") == \
        ["127.0.0.1", "::1", "localhost", "pane", "pane.local"]


def test_a_certificate_for_a_host_written_longhand_is_kept_from_one_start_to_the_next(tmp_path):
    now = dt.datetime(2026, 11, 26, 12, tzinfo=dt.timezone.utc)
    names = trust.machine_names("0:0:0:0:0:0:0:1", lan="192.168.1.20", hostname="pane")
    trust.local_certificate(tmp_path, names, now)
    first = (tmp_path / "server.pem").read_bytes()
    trust.local_certificate(tmp_path, names, now + dt.timedelta(hours=1))  # the next start
    assert (tmp_path / "server.pem").read_bytes() == first
    # read back by cryptography: ::1 once among the addresses
    ips = cert_of(tmp_path / "server.pem").extensions.get_extension_for_class(
        x509.SubjectAlternativeName).value.get_values_for_type(x509.IPAddress)
    assert sorted(map(str, ips)) == ["127.0.0.1", "192.168.1.20", "::1"]


@pytest.mark.parametrize("host", ["0:0:0:0:0:0:0:1", "0000::1", "LOCALHOST"])
def test_loopback_however_written_is_served_as_loopback_is(host):
    """No token and HTTP alone, as for ::1 and localhost (the oracle: the plan for those)."""
    from app.cli.parser import build_parser
    from app.serve.command import plan

    def planned(h):
        return plan(build_parser().parse_args(["serve", "--host", h]))

    assert planned(host) == planned("::1") == (None, None, b"")


# ---- frost serve --host 0.0.0.0, end to end ---------------------------------------------------

@pytest.fixture
def serve(tmp_path):
    """`frost serve --host 0.0.0.0` (support.serve.lan_serve), its config folder under
    tmp_path unless `config` says; each stopped after the test."""
    started: list[ServeProcess] = []

    def start(*args: str, config: Path = tmp_path / "config", env: dict | None = None) -> ServeProcess:
        started.append(lan_serve(config, *args, env=env))
        return started[-1]

    yield start
    for s in started:
        s.stop()


def trusting(cafile: Path) -> ssl.SSLContext:
    """A client that trusts this authority alone (no system roots)."""
    return ssl.create_default_context(cafile=str(cafile))


def presented(port: int, ctx: ssl.SSLContext, name: str = "127.0.0.1") -> x509.Certificate:
    """The certificate the server presents on `port`, the handshake verified by `ctx`."""
    with socket.create_connection(("127.0.0.1", port), timeout=30) as raw, \
            ctx.wrap_socket(raw, server_hostname=name) as tls:
        return x509.load_der_x509_certificate(tls.getpeercert(binary_form=True))


async def hello_over(url: str, ctx: ssl.SSLContext | None, origin: str | None = None) -> dict:
    """The first message of the socket at `url` (ws:// or wss://)."""
    headers = {"Origin": origin} if origin else {}
    async with aiohttp.ClientSession() as http, \
            http.ws_connect(url, ssl=ctx if ctx else False, headers=headers) as ws:
        msg = await ws.receive(timeout=30)
        return json.loads(msg.data)


async def status_of(url: str, ctx: ssl.SSLContext | None = None) -> tuple[int, str, bytes]:
    async with aiohttp.ClientSession() as http, \
            http.get(url, ssl=ctx if ctx else False) as r:
        return r.status, r.headers.get("Content-Type", ""), await r.read()


def qr_modules(path: Path, scale: int = 8, border: int = 4) -> list[list[bool]]:
    """The dark modules of a QR code's PNG (`scale` px a module, `border` modules round),
    read at each module's centre."""
    image = np.asarray(Image.open(path).convert("L"))
    size = image.shape[0] // scale - 2 * border
    centre = [(border + i) * scale + scale // 2 for i in range(size)]
    return [[bool(image[y, x] < 128) for x in centre] for y in centre]


SAID_IMAGE = re.compile(r"frost serve: the console \(cp1252\) cannot show the QR code: open "
                        r"the image (.+)\n")


def images_said(out: str) -> list[Path]:
    """The QR images a cp1252 console's lines name, in order (the page's, the app's)."""
    return [Path(found) for found in SAID_IMAGE.findall(out)]


def assert_qr_of(path: Path, url: str) -> None:
    """The PNG at `path` is the QR code of `url`, module for module."""
    import segno

    code = segno.make(url, error="m")
    assert qr_modules(path) == [[bool(m) for m in row] for row in code.matrix], (path, url)


@pytest.mark.parametrize("encoding", ["utf-8", "cp1252"])
@pytest.mark.usefixtures("subprocesses")
def test_the_qr_codes_are_drawn_where_the_console_can_show_them_else_written_as_images(
        serve, tmp_path, encoding):
    """A console that is not UTF-8 (a redirected Windows console, cp1252) cannot show the
    codes' block characters: the URLs print, a line names each code's PNG (in the config
    folder, beside the token), and the server serves on until Ctrl-C."""
    import segno

    s = serve(env={"PYTHONIOENCODING": encoding})
    assert asyncio.run(status_of(f"http://127.0.0.1:{s.port}/?token={s.token}"))[0] == 200
    out = s.stop()
    assert s.proc.returncode == 130, out
    folder = tmp_path / "config" / "frost"
    if encoding == "utf-8":
        for url in (s.url, s.https):
            drawn = io.StringIO()
            segno.make(url, error="m").terminal(out=drawn, compact=True)
            assert drawn.getvalue() in out
        assert not list(folder.glob("*.png"))
    else:
        page, app = images_said(out)
        assert page.parent == app.parent == folder, out
        assert_qr_of(page, s.url)
        assert_qr_of(app, s.https)
    assert "Traceback" not in out and "UnicodeEncodeError" not in out


@pytest.mark.parametrize("name", ["zima", "\u0437\u0438\u043c\u0430"], ids=["ascii", "cyrillic"])
@pytest.mark.usefixtures("subprocesses")
def test_two_servers_on_one_config_folder_each_name_their_own_qr_images(serve, tmp_path, name):
    """Two LAN servers on one config folder, on a cp1252 console, both serving: each line
    names an image of that server's own address (the second wrote qr-page.png over the
    first's, whose line then named the second's address). A folder whose name holds
    letters cp1252 has no byte for (a user name in Cyrillic, "зима") is said with their
    escapes: the lines survive it (the server died of a UnicodeEncodeError)."""
    config = tmp_path / name
    servers = [serve(config=config, env={"PYTHONIOENCODING": "cp1252"}) for _ in range(2)]
    said = []
    for s in servers:  # (the app's line follows its address, read so far)
        s.lines.append(s.proc.stdout.readline())  # type: ignore[union-attr]
        said.append(images_said("".join(s.lines)))
    first, second = said
    assert len(set(first + second)) == 4, said
    said = [[Path(str(p).encode("ascii").decode("unicode_escape")) for p in paths]
            for paths in said]  # (the escapes a cp1252 console got read back)
    for s, (page, app) in zip(servers, said, strict=True):
        assert_qr_of(page, s.url)
        assert_qr_of(app, s.https)
        assert page.parent == config / "frost"
    for s in servers:
        out = s.stop()
        assert s.proc.returncode == 130 and "Traceback" not in out, out


@pytest.mark.usefixtures("subprocesses")
def test_the_lan_server_answers_over_https_with_the_kept_authoritys_certificate_in_two_runs(
        serve, tmp_path):
    config = tmp_path / "config"
    folder = config / "frost"
    first = serve()
    assert first.https_port not in (None, first.port)  # --port 0: two free ports, stated
    cafile = folder / "ca.crt"
    ca = cert_of(cafile)
    ctx = trusting(cafile)  # Python's own TLS client, trusting that file alone
    leaf = presented(first.https_port, ctx)
    leaf.verify_directly_issued_by(ca)
    hostname = socket.gethostname().lower()
    assert {"127.0.0.1", "localhost", hostname} <= set(trust.san_names(leaf))
    # the address the terminal printed for a phone (the LAN's) verifies too
    printed = re.search(r"https://([^/:]+):", first.https).group(1)
    assert printed in trust.san_names(leaf)
    presented(first.https_port, ctx, name=printed)
    local = f"127.0.0.1:{first.https_port}"

    async def first_run():
        q = f"?token={first.token}"
        status, kind, body = await status_of(f"https://{local}/{q}", ctx)
        assert (status, kind) == (200, "text/html") and b"<canvas" in body
        hello = await hello_over(f"wss://{local}/ws{q}", ctx, origin=f"https://{local}")
        assert hello["type"] == "hello"
        # the plain HTTP page and its socket still work, as before
        status, _, body = await status_of(f"http://127.0.0.1:{first.port}/{q}")
        assert status == 200 and b"<canvas" in body
        assert (await hello_over(f"ws://127.0.0.1:{first.port}/ws{q}", None))["type"] == "hello"
        # the page learns the ports
        status, _, body = await status_of(f"http://127.0.0.1:{first.port}/app.json{q}")
        assert json.loads(body) == {"http": first.port, "https": first.https_port,
                                    "ca": "frost-ca.crt"}
    asyncio.run(first_run())
    token = first.token
    first.stop()

    second = serve()
    assert second.token == token  # kept across runs: an installed page keeps working
    assert cafile.read_bytes() == ca.public_bytes(serialization.Encoding.PEM)  # the same authority
    presented(second.https_port, trusting(cafile)).verify_directly_issued_by(ca)
    assert asyncio.run(hello_over(f"wss://127.0.0.1:{second.https_port}/ws?token={token}",
                                  trusting(cafile)))["type"] == "hello"
    second.stop()

    third = serve("--new-token")
    assert third.token != token

    async def old_token_refused():
        for port, ctx_ in ((third.port, None), (third.https_port, trusting(cafile))):
            scheme = "https" if ctx_ else "http"
            assert (await status_of(f"{scheme}://127.0.0.1:{port}/?token={token}", ctx_))[0] == 403
            assert (await status_of(f"{scheme}://127.0.0.1:{port}/?token={third.token}", ctx_))[0] == 200
    asyncio.run(old_token_refused())
    assert (folder / "token").read_text(encoding="utf-8").strip() == third.token


@pytest.mark.usefixtures("subprocesses")
def test_without_the_token_only_the_authoritys_public_certificate_is_served_on_both_ports(
        serve, tmp_path):
    s = serve()
    folder = tmp_path / "config" / "frost"
    ctx = trusting(folder / "ca.crt")
    ca_der = cert_of(folder / "ca.crt").public_bytes(serialization.Encoding.DER)
    secret = serialization.load_pem_private_key((folder / "ca.key").read_bytes(), None) \
        .private_numbers().private_value.to_bytes(32, "big")  # the key's secret scalar

    async def main():
        for scheme, port, c in (("http", s.port, None), ("https", s.https_port, ctx)):
            base = f"{scheme}://127.0.0.1:{port}"
            for path in ("/", "/web/main.js", "/web/makeapp.js", "/shaders/ice.frag", "/meta",
                         "/app.json", "/backdrops/dusk.png", "/ws", "/ca.key", "/frost-ca.key"):
                assert (await status_of(base + path, c))[0] == 403, (scheme, path)
            status, kind, body = await status_of(base + "/frost-ca.crt", c)
            assert (status, kind) == (200, "application/x-x509-ca-cert"), scheme
            assert body == ca_der  # the public certificate, as the file holds it
            assert secret not in body and b"PRIVATE" not in body
    asyncio.run(main())


@pytest.mark.usefixtures("subprocesses")
def test_the_socket_on_the_https_port_takes_https_origins_of_that_port_only(serve, tmp_path):
    s = serve()
    ctx = trusting(tmp_path / "config" / "frost" / "ca.crt")
    url = f"wss://127.0.0.1:{s.https_port}/ws?token={s.token}"

    async def refused(origin: str) -> bool:
        try:
            await hello_over(url, ctx, origin=origin)
        except aiohttp.WSServerHandshakeError as err:
            return err.status == 403
        return False
    assert asyncio.run(hello_over(url, ctx, origin=f"https://127.0.0.1:{s.https_port}"))["type"] == "hello"
    assert asyncio.run(refused(f"http://127.0.0.1:{s.https_port}"))  # not this scheme
    assert asyncio.run(refused(f"https://127.0.0.1:{s.port}"))  # not this port
    assert asyncio.run(refused("https://evil.example"))


@pytest.mark.usefixtures("subprocesses")
def test_no_https_serves_http_alone_and_no_authority(serve, tmp_path):
    s = serve("--no-https")
    out = s.stop()
    assert s.https is None and "https://" not in out
    assert not (tmp_path / "config" / "frost" / "ca.key").exists()


@pytest.mark.usefixtures("subprocesses")
def test_a_certificate_of_the_users_own_is_served_on_loopback_when_asked(tmp_path):
    mine = tmp_path / "mine"
    trust.local_certificate(mine, ["127.0.0.1", "localhost"])
    s = ServeProcess("--port", "0", "--https-port", "0", "--cert", str(mine / "server.pem"),
                     "--key", str(mine / "server.pem"), cwd=ROOT,
                     env={"XDG_CONFIG_HOME": str(tmp_path / "config")})
    try:
        line = s.proc.stdout.readline()  # (the line after the page's address)
        port = int(re.search(r"over HTTPS: https://127\.0\.0\.1:(\d+)/", line).group(1))
        ctx = trusting(mine / "ca.crt")
        presented(port, ctx).verify_directly_issued_by(cert_of(mine / "ca.crt"))
        assert asyncio.run(status_of(f"https://127.0.0.1:{port}/", ctx))[0] == 200
        assert asyncio.run(status_of(f"https://127.0.0.1:{port}/frost-ca.crt", ctx))[0] == 404
    finally:
        s.stop()
    assert not (tmp_path / "config").exists()  # loopback: no token, no authority made


@pytest.mark.parametrize("args, says", [
    (["--cert", "c.pem"], "--cert and --key go together"),
    (["--no-https", "--https-port", "9"], "--no-https serves HTTP alone"),
    (["--port", "9000", "--https-port", "9000"], "--https-port 9000 is --port too"),
    (["--port", "65535"], "--port 65535 leaves no next port"),
    (["--cert", "/no/such.pem", "--key", "/no/such.pem"], "cannot use the certificate /no/such.pem"),
])
@pytest.mark.usefixtures("subprocesses")
def test_bad_https_command_lines_are_one_clear_error(tmp_path, args, says):
    run = subprocess.run([sys.executable, "-m", "app", "serve", "--host", "0.0.0.0",
                          "--max-seconds", "5", *args], cwd=ROOT, capture_output=True, text=True,
                         timeout=60, env={**os.environ, "XDG_CONFIG_HOME": str(tmp_path)})
    assert (run.returncode, run.stderr.count("\n")) == (2, 1), run.stderr
    assert run.stderr.startswith("frost: error: ") and says in run.stderr
    assert run.stderr.endswith(" (see frost serve --help)\n"), run.stderr  # (command-line.md)


def test_a_tls_handshake_never_finished_is_closed(tmp_path, monkeypatch):
    """A connection that opens and sends nothing holds no file descriptor for asyncio's
    default minute: the HTTPS port ends its handshake after HANDSHAKE_S."""
    from app.serve import listen as listening
    from app.serve.feed import Feed
    from app.serve.server import make_app
    from sim import Params

    monkeypatch.setattr(listening, "HANDSHAKE_S", 0.5)
    issued = trust.local_certificate(tmp_path, ["127.0.0.1"])

    async def main():
        feed = Feed(Params.preset("c-2"), seed=1)
        runner = await listening.listen(make_app(feed, "t" * 22), "127.0.0.1", 0, "t" * 22,
                                        listening.Https(0, issued.context()))
        assert runner is not None
        try:
            port = runner.addresses[1][1]
            reader, writer = await asyncio.open_connection("127.0.0.1", port)
            with contextlib.suppress(ConnectionResetError):  # closed: EOF or reset
                assert await asyncio.wait_for(reader.read(), 10) == b""
            writer.close()
        finally:
            await runner.cleanup()
    asyncio.run(main())


# ---- a browser told to trust the authority ----------------------------------------------------


browser = pytest.mark.skipif(browser_problem() is not None, reason=str(browser_problem()))


@pytest.mark.browser
@browser
@pytest.mark.usefixtures("subprocesses")
def test_a_chromium_trusting_the_authority_opens_the_https_page_as_a_secure_context(serve, tmp_path):
    from playwright.sync_api import Error, sync_playwright

    s = serve()
    cafile = tmp_path / "config" / "frost" / "ca.crt"
    name = socket.gethostname().lower()  # in the certificate's names (the machine's own)
    assert not trust.ip_or_loopback(name), name
    https = f"https://{name}:{s.https_port}/?token={s.token}"
    with sync_playwright() as pw:
        # Not trusting it: the certificate is refused (the oracle that trust is what counts).
        b = trusting_chromium(pw, trusting_home(tmp_path / "stranger", None), name)
        with pytest.raises(Error, match="ERR_CERT_AUTHORITY_INVALID"):
            b.new_context(**PHONE).new_page().goto(https)
        b.close()
        b = trusting_chromium(pw, trusting_home(tmp_path / "home", cafile), name)
        page = b.new_context(**PHONE).new_page()
        failed: list[str] = []
        page.on("response", lambda r: r.status >= 400 and failed.append(f"{r.status} {r.url}"))
        page.goto(https)
        synced(page, "frost.frames > 0")
        assert page.evaluate("window.isSecureContext") is True
        assert page.evaluate("window.frost.socket.url").startswith(f"wss://{name}:{s.https_port}/ws?")
        assert page.evaluate("window.frost.connected") is True
        # over HTTPS the menu offers no steps: this is the app's address already
        page.click("#open")
        assert page.locator("#makeapp-open").count() == 0
        assert page.evaluate("window.frost.makeApp.shown") is None
        page.screenshot(path=str(tmp_path / "https-page.png"))
        # the plain page: no secure context, its menu offers the steps and the HTTPS address
        page.goto(f"http://{name}:{s.port}/?token={s.token}")
        synced(page, "frost.frames > 0")
        assert page.evaluate("window.isSecureContext") is False
        assert page.evaluate("window.frost.socket.url").startswith("ws://")
        page.click("#open")
        page.click("#makeapp-open")
        assert page.locator("#makeapp").is_visible()
        cert = page.get_attribute("#makeapp-cert", "href")
        assert cert == "frost-ca.crt"
        assert page.get_attribute("#makeapp-https", "href") == https
        text = page.inner_text("#makeapp")
        for words in ("Install a certificate", "CA certificate", "Android 11",
                      "Profile Downloaded", "Certificate Trust Settings"):
            assert words in text, words
        page.screenshot(path=str(tmp_path / "makeapp.png"))
        got = page.request.get(f"http://{name}:{s.port}/frost-ca.crt")  # no token
        assert got.status == 200 and got.body() == cert_of(cafile).public_bytes(serialization.Encoding.DER)
        assert failed == []
        b.close()
    if os.environ.get("FROST_KEEP_SHOTS"):
        import shutil
        for shot in ("https-page.png", "makeapp.png"):
            shutil.copy(tmp_path / shot, Path(os.environ["FROST_KEEP_SHOTS"]) / shot)


@pytest.mark.browser
@browser
@pytest.mark.usefixtures("subprocesses")
def test_an_https_page_whose_socket_never_opens_shows_the_steps(serve, tmp_path):
    """A page cannot learn that the certificate failed its socket (iOS refuses the WSS of
    an untrusted authority after the page loaded): after a while with no hello it shows the
    steps by itself, and hides them once the socket opens after all."""
    from playwright.sync_api import sync_playwright

    s = serve()
    cafile = tmp_path / "config" / "frost" / "ca.crt"
    name = socket.gethostname().lower()
    with sync_playwright() as pw:
        b = trusting_chromium(pw, trusting_home(tmp_path / "home", cafile), name)
        page = b.new_context(**PHONE).new_page()
        # Every socket fails at once, as an untrusted certificate makes it fail; until the
        # test lets it through.
        page.add_init_script("""
            const Real = window.WebSocket;
            window.WebSocket = function (url) {
              if (window.letThrough) return new Real(url);
              const fake = { readyState: 3, close() {}, send() {} };
              setTimeout(() => fake.onclose && fake.onclose({ code: 1006, reason: "" }), 10);
              return fake;
            };
            window.WebSocket.OPEN = 1;
        """)
        # The page's timers on a clock the test moves on: its wait for a hello (8 s) and
        # its sockets' retries (up to 8 s) jumped over, not waited out.
        page.clock.install()
        page.goto(f"https://{name}:{s.https_port}/?token={s.token}")
        page.wait_for_function("window.frost && window.frost.makeApp", timeout=30_000)
        assert page.evaluate("window.frost.makeApp.shown") is None  # not at once
        page.clock.fast_forward(7_000)
        assert page.evaluate("window.frost.makeApp.shown") is None  # not before its time
        page.clock.fast_forward(1_500)
        page.wait_for_function("window.frost.makeApp.shown === 'never-opened'", timeout=30_000)
        assert page.locator("#makeapp").is_visible()
        text = page.inner_text("#makeapp")
        assert "never opened" in text and "Install a certificate" in text
        assert "Certificate Trust Settings" in text
        assert page.get_attribute("#makeapp-next a", "href") == \
            f"http://{name}:{s.port}/?token={s.token}"
        page.screenshot(path=str(tmp_path / "never-opened.png"))
        page.evaluate("window.letThrough = true")
        page.clock.fast_forward(8_500)  # (the next retry, at most 8 s away)
        page.wait_for_function("window.frost.hellos > 0 && window.frost.makeApp.shown === null",
                               timeout=60_000)
        assert not page.locator("#makeapp").is_visible()
        b.close()
    if os.environ.get("FROST_KEEP_SHOTS"):
        import shutil
        shutil.copy(tmp_path / "never-opened.png", Path(os.environ["FROST_KEEP_SHOTS"]) / "never-opened.png")
