"""HTML to print-ready PDF through WeasyPrint, with no network and no arbitrary files.

The URL fetcher is the security boundary: scene text ends up in the HTML, so the
PDF step must not become a way to read files or reach hosts. Only ``data:`` URIs
(the embedded figures) and files inside the package's own templates folder load.
"""

from __future__ import annotations

import logging
from importlib import resources
from pathlib import Path
from urllib.parse import unquote, urlparse


class BlockedResource(ValueError):
    pass


def _asset_root() -> Path:
    return Path(str(resources.files("crankdyn.templates"))).resolve()


def is_allowed(url: str) -> bool:
    """True for data: URIs and file: URLs inside the package's templates folder."""
    parsed = urlparse(url)
    if parsed.scheme == "data":
        return True
    if parsed.scheme == "file":
        path = Path(unquote(parsed.path)).resolve()
        root = _asset_root()
        return path == root or root in path.parents
    return False


def _fetcher():
    import weasyprint  # lazy: heavy optional import

    if hasattr(weasyprint, "URLFetcher"):  # WeasyPrint >= 66: fetchers are objects
        class SafeURLFetcher(weasyprint.URLFetcher):
            def fetch(self, url, headers=None):
                if not is_allowed(url):
                    raise BlockedResource(f"crankdyn does not load {url!r} into a report")
                return super().fetch(url, headers)

        return SafeURLFetcher(allowed_protocols=("data", "file"), allow_redirects=False)

    def safe_url_fetcher(url, *args, **kwargs):  # older WeasyPrint: a plain function
        if not is_allowed(url):
            raise BlockedResource(f"crankdyn does not load {url!r} into a report")
        return weasyprint.default_url_fetcher(url, *args, **kwargs)

    return safe_url_fetcher


def html_to_pdf(html: str) -> bytes:
    from weasyprint import HTML  # lazy: heavy optional import

    # A blocked resource is logged by WeasyPrint as a warning and left out; keep the
    # console quiet (the tests check the blocking itself).
    logging.getLogger("weasyprint").setLevel(logging.ERROR)
    base = _asset_root().as_uri() + "/"
    return HTML(string=html, base_url=base, url_fetcher=_fetcher()).write_pdf()
