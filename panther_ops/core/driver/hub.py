"""Docker Hub's released tags of the driver images: an HTTPS GET from this machine (the one
operator-side effect of `driver versions`); the page parsing is `images.py`'s (pure)."""

from __future__ import annotations

from panther_ops.core.driver.images import HUB_TIMEOUT_S, HUB_URL, HubTag, RegistryError, parse_hub_page, tag_key


def fetch_hub_tags(repo: str, *, url_template: str = HUB_URL, timeout: float = HUB_TIMEOUT_S,
                   max_pages: int = 3) -> list[HubTag]:
    """Released Humble tags of ``husarion/<repo>`` from Docker Hub (newest version first).

    Raises:
        RegistryError: ``registry unreachable: <why>`` (no network, timeout, HTTP error, not JSON).
    """
    from urllib.parse import urlsplit

    from panther_ops import __version__
    from panther_ops.transport.http_json import HttpJsonError, get_json

    name = repo.rsplit("/", maxsplit=1)[-1]
    url = url_template.format(repo=name)
    origin = urlsplit(url)[:2]
    if origin[0] not in ("http", "https"):
        raise RegistryError(f"registry URL {url!r} is not http(s)")
    tags: list[HubTag] = []
    for _ in range(max_pages):
        try:
            doc = get_json(url, timeout=timeout, user_agent=f"panther-ops/{__version__}")
        except HttpJsonError as exc:
            raise RegistryError(f"registry unreachable: {exc}") from None
        page, nxt = parse_hub_page(doc, f"husarion/{name}")
        tags.extend(page)
        if nxt is None or urlsplit(nxt)[:2] != origin:
            break
        url = nxt
    return sorted(set(tags), key=lambda t: tag_key(t.name), reverse=True)
