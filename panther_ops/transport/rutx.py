"""The Teltonika RUTX11's REST API (HTTPS, bearer token), over a socket the caller opens.

``POST /api/login`` with ``{"username", "password"}`` answers ``data.token``; every other
request carries ``Authorization: Bearer <token>``. The router's certificate is self-signed:
it is not checked against a CA but pinned (its SHA-256 fingerprint, recorded on first use
like an SSH host key, refused when it changes). A request refused for an expired token logs
in again once. The password is a `Secret` and never appears in a message.
"""

from __future__ import annotations

import hashlib
import http.client
import json
import socket
import ssl
from collections.abc import Callable
from typing import Any

from panther_ops.errors import OpsError, TransportError, UsageError
from panther_ops.secret import Secret

Opener = Callable[[], socket.socket]


class RouterAuthError(UsageError):
    """The router refused the credentials (exit 2: bad input, nothing changed)."""


class CertificateChanged(OpsError):
    """The router's certificate is not the pinned one."""


def fingerprint(der: bytes) -> str:
    return "SHA256:" + hashlib.sha256(der).hexdigest()


class RouterClient:
    """One router, reached through ``opener`` (a new connection per request)."""

    def __init__(self, opener: Opener, robot: str, host: str, *, pinned: str | None,
                 pin: Callable[[str], None], timeout: float = 10.0) -> None:
        self.opener, self.robot, self.host, self.timeout = opener, robot, host, timeout
        self.pinned = pinned
        self._pin = pin
        self.fingerprint: str | None = None
        self.pinned_now = False
        self._token: str | None = None
        self._creds: tuple[str, Secret] | None = None

    # -- connection -------------------------------------------------------------
    def _connect(self) -> http.client.HTTPConnection:
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        ctx.check_hostname = False
        ctx.verify_mode = ssl.CERT_NONE  # self-signed: pinned below instead
        raw = self.opener()
        try:
            tls = ctx.wrap_socket(raw, server_hostname=None)
        except (ssl.SSLError, OSError) as exc:
            raw.close()
            raise TransportError(self.robot, f"TLS with the router {self.host} failed: {exc}") from None
        der = tls.getpeercert(binary_form=True) or b""
        seen = fingerprint(der)
        self.fingerprint = seen
        if self.pinned is None:
            self._pin(seen)
            self.pinned, self.pinned_now = seen, True
        elif seen != self.pinned:
            tls.close()
            raise CertificateChanged(
                f"{self.robot}: the router {self.host} shows certificate {seen}, not the pinned {self.pinned}; "
                "refused", hint="if the router was reset or replaced, remove its line from the pin file")
        conn = http.client.HTTPConnection(self.host, timeout=self.timeout)
        conn.sock = tls
        return conn

    def _request(self, method: str, path: str, body: Any | None, token: str | None) -> tuple[int, Any]:
        conn = self._connect()
        try:
            headers = {"Content-Type": "application/json", "Connection": "close"}
            if token:
                headers["Authorization"] = f"Bearer {token}"
            payload = None if body is None else json.dumps(body)
            conn.request(method, path, body=payload, headers=headers)
            resp = conn.getresponse()
            raw = resp.read()
        except (OSError, http.client.HTTPException) as exc:
            raise TransportError(self.robot, f"router {self.host}: {method} {path} failed: {exc}") from None
        finally:
            conn.close()
        try:
            doc = json.loads(raw) if raw else {}
        except ValueError:
            raise TransportError(self.robot, f"router {self.host}: {method} {path}: not JSON "
                                             f"(HTTP {resp.status})") from None
        return resp.status, doc

    # -- API ----------------------------------------------------------------------
    def login(self, username: str, password: Secret) -> None:
        status, doc = self._request("POST", "/api/login", {"username": username, "password": password.reveal()},
                                    None)
        token = (doc.get("data") or {}).get("token") if isinstance(doc, dict) else None
        if status in (401, 403) or (status == 200 and not token):
            raise RouterAuthError(f"the router {self.host} refused the login of {username!r}",
                                  hint="check PANTHER_OPS_ROUTER_PASSWORD or the credentials file")
        if status != 200:
            raise TransportError(self.robot, f"router {self.host}: login answered HTTP {status}: {_errors(doc)}")
        self._token, self._creds = str(token), (username, password)

    def call(self, method: str, path: str, body: Any | None = None) -> Any:
        """``data`` of the answer; logs in again once when the token expired."""
        if self._token is None:
            raise TransportError(self.robot, "router: not logged in")
        status, doc = self._request(method, path, body, self._token)
        if status == 401 and self._creds is not None:
            self.login(*self._creds)
            status, doc = self._request(method, path, body, self._token)
        if status != 200 or not (isinstance(doc, dict) and doc.get("success", True)):
            raise TransportError(self.robot, f"router {self.host}: {method} {path} answered HTTP {status}: "
                                             f"{_errors(doc)}")
        return doc.get("data")


def _errors(doc: Any) -> str:
    if isinstance(doc, dict) and isinstance(doc.get("errors"), list):
        return "; ".join(f"{e.get('source', '')} {e.get('error', '')}".strip() for e in doc["errors"]
                         if isinstance(e, dict)) or "error"
    return str(doc)[:200]
