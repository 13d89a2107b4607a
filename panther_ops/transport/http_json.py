"""JSON over HTTP(S) from this machine (Docker Hub's tag list): the one web client of the operator side."""

from __future__ import annotations

import json
from typing import Any


class HttpJsonError(Exception):
    """The URL could not be fetched as JSON; the message says why (no network, HTTP status, not JSON)."""


def get_json(url: str, *, timeout: float, user_agent: str, max_bytes: int = 8_000_000) -> Any:
    """GET ``url`` (http or https only) and parse the answer as JSON."""
    import urllib.error
    import urllib.request
    from urllib.parse import urlsplit

    if urlsplit(url).scheme not in ("http", "https"):
        raise HttpJsonError(f"URL {url!r} is not http(s)")
    req = urllib.request.Request(url, headers={"Accept": "application/json",  # noqa: S310 - scheme checked
                                               "User-Agent": user_agent})
    try:
        with urllib.request.urlopen(req, timeout=timeout) as resp:  # noqa: S310 - scheme checked
            return json.loads(resp.read(max_bytes))
    except urllib.error.HTTPError as exc:
        raise HttpJsonError(f"{url} answered HTTP {exc.code}") from None
    except urllib.error.URLError as exc:
        raise HttpJsonError(str(exc.reason)) from None
    except (OSError, TimeoutError) as exc:
        raise HttpJsonError(str(exc)) from None
    except ValueError:
        raise HttpJsonError(f"{url} did not answer JSON") from None
