"""HTTPS on the LAN that a phone trusts (docs/phone.md, "HTTPS on your network";
docs/phone-design.md, "HTTPS: the authority and the certificate").

A self-signed certificate is not enough for a phone: with a certificate error Chromium
registers no service worker and installs no page, and iOS Safari refuses the WSS socket
even after the warning is passed. So, as mkcert does, frost creates once, and keeps, a
certificate authority of its own in the user's config folder (`config_dir`), which the
phone is told to trust, and issues from it the server's certificate for this machine's
names and LAN addresses, again whenever they change or it nears its end. The token of
`--host 0.0.0.0` is kept beside it, so a page installed on a phone still works after a
restart.

Files in the folder (private ones readable by the user alone, 0600):

| file | what |
| --- | --- |
| `ca.crt` | the authority's certificate (public: served as /frost-ca.crt) |
| `ca.key` | the authority's private key (private; never read but to sign) |
| `server.pem` | the server's key and certificate in one file (private), replaced whole |
| `token` | the token the URL carries (private) |
| `qr-page-HOST-PORT.png`, `qr-app-...` | the URLs' QR codes where the console cannot draw them (listen.py) |
"""

from __future__ import annotations

import datetime as dt
import getpass
import ipaddress
import os
import re
import secrets
import socket
import ssl
import time
from dataclasses import dataclass
from pathlib import Path

from app.config import config_dir as config_dir  # (the folder of this module's files)

CA_DAYS = 3650  # the authority: ten years (a phone trusts it once)
LEAF_DAYS = 820  # the server's: Apple accepts at most 825 days for a TLS server certificate
RENEW_DAYS = 30  # re-issued when fewer days than this are left
CA_FILE, CA_KEY_FILE, SERVER_FILE, TOKEN_FILE = "ca.crt", "ca.key", "server.pem", "token"
TOKEN_RE = re.compile(r"[A-Za-z0-9_-]{16,64}")
DNS_RE = re.compile(r"[a-z0-9]([a-z0-9-]*[a-z0-9])?(\.[a-z0-9]([a-z0-9-]*[a-z0-9])?)*")


class TrustError(Exception):
    """Why HTTPS cannot be set up, in one line for the user."""


def _folder(folder: Path) -> Path:
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    except OSError as err:
        raise TrustError(f"cannot make the folder {folder}: {err.strerror or err}") from None
    return folder


def _write(path: Path, data: bytes, private: bool, exclusive: bool = False) -> bool:
    """Write `path` whole (never half-written for a reader), mode 0600 if private; with
    `exclusive`, only if it does not exist yet (False: another process made it first)."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600 if private else 0o644)
        with os.fdopen(fd, "wb") as out:
            out.write(data)
        if private:
            os.chmod(tmp, 0o600)  # whatever the umask
        if not exclusive:
            os.replace(tmp, path)
            return True
        try:
            os.link(tmp, path)  # fails where the file exists: two servers starting at once
            return True
        except FileExistsError:
            return False
    except OSError as err:
        raise TrustError(f"cannot write {path}: {err.strerror or err}") from None
    finally:
        tmp.unlink(missing_ok=True)


def _read(path: Path, private: bool) -> bytes | None:
    """The file's bytes, None if it is missing; a private file's mode made 0600 if it
    was wider."""
    try:
        if private and os.name == "posix" and path.stat().st_mode & 0o077:
            os.chmod(path, 0o600)
        return path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError as err:
        raise TrustError(f"cannot read {path}: {err.strerror or err}") from None


# ---- the token ------------------------------------------------------------------------

def kept_token(folder: Path, new: bool = False) -> str:
    """The token kept in `folder` (made, and kept, if there is none or `new`)."""
    path = _folder(folder) / TOKEN_FILE
    if not new:
        kept = (_read(path, private=True) or b"").decode("ascii", "replace").strip()
        if TOKEN_RE.fullmatch(kept):
            return kept
    token = secrets.token_urlsafe(16)
    _write(path, token.encode() + b"\n", private=True)
    return token


# ---- the names of this machine -----------------------------------------------------------

def machine_names(host: str, lan: str | None = None, hostname: str | None = None) -> list[str]:
    """The names the server's certificate holds: localhost and the loopback addresses, the
    machine's host name (and its .local name, which phones resolve by mDNS), its LAN
    address (`lan`, the one a phone reaches), every address its host name resolves to,
    and `host` where it names one address or name (not 0.0.0.0 or ::). Sorted, lower case,
    each address in its canonical form (the certificate read back writes `::1` however the
    command line wrote it), names a certificate cannot hold left out."""
    hostname = socket.gethostname() if hostname is None else hostname
    found = {"localhost", "127.0.0.1", "::1", hostname.lower()}
    if hostname and "." not in hostname:
        found.add(f"{hostname.lower()}.local")
    if lan:
        found.add(lan.lower())
    if not unspecified(host):
        found.add(host.lower())
    try:
        for info in socket.getaddrinfo(hostname, None, proto=socket.IPPROTO_TCP):
            found.add(str(info[4][0]).split("%")[0])
    except (OSError, UnicodeError):
        pass
    return sorted(n for n in {canonical(n) for n in found}
                  if _ip(n) is not None or (len(n) < 254 and DNS_RE.fullmatch(n)))


def canonical(name: str) -> str:
    """A name as it is compared: an address in its one written form (`0:0:0:0:0:0:0:1` is
    `::1`), any other name in lower case."""
    ip = _ip(name)
    return str(ip) if ip is not None else name.lower()


def unspecified(host: str) -> bool:
    """Whether a --host listens on every address (0.0.0.0, ::, however written) rather
    than naming one."""
    ip = _ip(host)
    return host == "" or (ip is not None and ip.is_unspecified)


def ip_or_loopback(name: str) -> bool:
    """Whether `name` is an address, or a name a browser takes for this machine itself."""
    return _ip(name) is not None or name == "localhost" or name.endswith(".localhost")


def _ip(name: str):
    try:
        return ipaddress.ip_address(name)
    except ValueError:
        return None


# ---- the authority and the server's certificate ---------------------------------------------

@dataclass
class Issued:
    """What serving HTTPS takes: the certificate chain file, and the authority's public
    certificate (DER) to serve a phone, None for a certificate of the user's own."""
    cert_file: Path
    key_file: Path
    ca_der: bytes | None

    def context(self) -> ssl.SSLContext:
        """A server's TLS context (TLS 1.2 at least) with this certificate."""
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
        ctx.minimum_version = ssl.TLSVersion.TLSv1_2
        try:
            ctx.load_cert_chain(self.cert_file, self.key_file)
        except (OSError, ssl.SSLError, ValueError) as err:
            what = getattr(err, "strerror", None) or getattr(err, "reason", None) or err
            raise TrustError(f"cannot use the certificate {self.cert_file} with the key "
                             f"{self.key_file}: {what}") from None
        return ctx


def users_own(cert: str, key: str) -> Issued:
    """--cert FILE --key FILE: a certificate the user has (mkcert's, a real domain's)."""
    issued = Issued(Path(cert), Path(key), None)
    issued.context()  # refused now, in one line, rather than at the first page
    return issued


def local_certificate(folder: Path, names: list[str], now: dt.datetime | None = None) -> Issued:
    """The authority kept in `folder` (made the first time) and the server's certificate it
    issued for `names`, issued anew where the names differ, fewer than RENEW_DAYS days are
    left, or the authority is not its issuer."""
    from cryptography.hazmat.primitives import serialization

    now = now or dt.datetime.now(dt.timezone.utc)
    ca_cert, ca_key = _authority(_folder(folder), now)
    path = folder / SERVER_FILE
    held = _read(path, private=True)
    if held is None or _needs_issuing(held, ca_cert, names, now):
        key, cert = _issue(ca_cert, ca_key, names, now)
        pem = key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                serialization.NoEncryption()) + \
            cert.public_bytes(serialization.Encoding.PEM)
        _write(path, pem, private=True)
    return Issued(path, path, ca_cert.public_bytes(serialization.Encoding.DER))


def _authority(folder: Path, now: dt.datetime):
    """The kept authority (certificate, private key), made first if there is none."""
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric import ec

    key_path, cert_path = folder / CA_KEY_FILE, folder / CA_FILE
    key_pem = _read(key_path, private=True)
    if key_pem is None:
        key = ec.generate_private_key(ec.SECP256R1())
        cert = _authority_cert(key, now)
        pem = key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                                serialization.NoEncryption())
        if _write(key_path, pem, private=True, exclusive=True):
            _write(cert_path, cert.public_bytes(serialization.Encoding.PEM), private=False)
            return cert, key
        key_pem = _read(key_path, private=True)  # another server made it first: its own
    for _ in range(20):  # (written just after its key by a server starting beside this one)
        cert_pem = _read(cert_path, private=False)
        if cert_pem is not None:
            break
        time.sleep(0.1)
    broken = (f"the authority in {folder} cannot be read; move that folder away to make "
              "a new one (each phone must then trust the new one)")
    if cert_pem is None or key_pem is None:
        raise TrustError(broken)
    try:
        kept = serialization.load_pem_private_key(key_pem, None)
        cert = x509.load_pem_x509_certificate(cert_pem)
    except (ValueError, TypeError):
        raise TrustError(broken) from None
    spki = (serialization.Encoding.DER, serialization.PublicFormat.SubjectPublicKeyInfo)
    if cert.public_key().public_bytes(*spki) != kept.public_key().public_bytes(*spki):
        raise TrustError(broken)  # a key and a certificate that are not one pair
    return cert, kept


def _authority_cert(key, now: dt.datetime):
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes
    from cryptography.x509.oid import NameOID

    try:
        user = getpass.getuser()
    except (KeyError, OSError, ImportError):
        user = "user"
    name = x509.Name([
        x509.NameAttribute(NameOID.ORGANIZATION_NAME, "frost local authority"),
        x509.NameAttribute(NameOID.ORGANIZATIONAL_UNIT_NAME, f"{user}@{socket.gethostname()}"[:64]),
        x509.NameAttribute(NameOID.COMMON_NAME, f"frost {user}@{socket.gethostname()}"[:64]),
    ])
    public = key.public_key()
    return (x509.CertificateBuilder()
            .subject_name(name).issuer_name(name).public_key(public)
            .serial_number(x509.random_serial_number())
            .not_valid_before(now - dt.timedelta(hours=1))
            .not_valid_after(now + dt.timedelta(days=CA_DAYS))
            .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, key_cert_sign=True, crl_sign=True,
                                         content_commitment=False, key_encipherment=False,
                                         data_encipherment=False, key_agreement=False,
                                         encipher_only=False, decipher_only=False), critical=True)
            .add_extension(x509.SubjectKeyIdentifier.from_public_key(public), critical=False)
            .sign(key, hashes.SHA256()))


def _issue(ca_cert, ca_key, names: list[str], now: dt.datetime):
    """A new key and the certificate the authority issues for it: `names` in its subject
    alternative names, serverAuth, LEAF_DAYS days."""
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

    key = ec.generate_private_key(ec.SECP256R1())
    sans: list[x509.GeneralName] = [
        x509.IPAddress(ip) if (ip := _ip(n)) is not None else x509.DNSName(n) for n in names]
    start = now - dt.timedelta(hours=1)  # a phone's clock a little behind
    cert = (x509.CertificateBuilder()
            .subject_name(x509.Name([x509.NameAttribute(NameOID.ORGANIZATION_NAME, "frost serve"),
                                     x509.NameAttribute(NameOID.COMMON_NAME, names[0][:64])]))
            .issuer_name(ca_cert.subject).public_key(key.public_key())
            .serial_number(x509.random_serial_number())
            .not_valid_before(start).not_valid_after(start + dt.timedelta(days=LEAF_DAYS))
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, key_cert_sign=False, crl_sign=False,
                                         content_commitment=False, key_encipherment=False,
                                         data_encipherment=False, key_agreement=False,
                                         encipher_only=False, decipher_only=False), critical=True)
            .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
            .add_extension(x509.SubjectAlternativeName(sans), critical=False)
            .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
            .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(ca_cert.public_key()),
                           critical=False)
            .sign(ca_key, hashes.SHA256()))
    return key, cert


def san_names(cert) -> list[str]:
    """A certificate's subject alternative names as `machine_names` writes them, sorted."""
    from cryptography import x509

    try:
        san = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    except x509.ExtensionNotFound:
        return []
    return sorted([str(ip) for ip in san.get_values_for_type(x509.IPAddress)]
                  + san.get_values_for_type(x509.DNSName))


def _needs_issuing(pem: bytes, ca_cert, names: list[str], now: dt.datetime) -> bool:
    from cryptography import x509
    from cryptography.exceptions import InvalidSignature
    from cryptography.hazmat.primitives import serialization

    try:
        cert = x509.load_pem_x509_certificate(pem)
        serialization.load_pem_private_key(pem, None)
        cert.verify_directly_issued_by(ca_cert)
    except (ValueError, TypeError, InvalidSignature):  # not whole, or not this authority's
        return True
    left = cert.not_valid_after_utc - now
    return san_names(cert) != sorted(names) or left < dt.timedelta(days=RENEW_DAYS)
