"""The printed report's figures placed as PDF forms: matplotlib's own PDF page of each figure,
put where WeasyPrint laid out an empty image of its size.

WeasyPrint draws an SVG figure element by element, in Python, a quarter of a report's PDF time.
A figure matplotlib drew as a one-page PDF (:func:`crankdyn.report.figures.to_pdf`) is already
what the page needs: the layout gets a placeholder, an SVG of the figure's size that draws nothing
(:func:`placeholder_svg`); after the layout each placeholder's box is found on its page
(:func:`placements`) and the figure's page is stamped there as a form XObject with pikepdf
(:func:`stamp`). The page's text, numbers and links are WeasyPrint's; the figure is the same
drawing, its text searchable.

Without pikepdf, or for a figure that is only an SVG, WeasyPrint draws the SVG as before.
"""

from __future__ import annotations

import importlib.util
import io
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any
from urllib.parse import unquote, urljoin

#: A page's size in a matplotlib figure PDF: ``/MediaBox [ 0 0 432 288 ]`` (points).
_MEDIA_BOX = re.compile(rb"/MediaBox\s*\[\s*0\s+0\s+([0-9.]+)\s+([0-9.]+)\s*\]")
#: CSS pixels to PDF points (WeasyPrint's page transform at zoom 1).
_POINTS_PER_PX = 0.75


def available() -> bool:
    """Whether figures can be stamped (pikepdf installed)."""
    return importlib.util.find_spec("pikepdf") is not None


def figure_page(figure) -> bytes | None:
    """The figure's PDF page to stamp, or None: a figure given only as its SVG, or one whose page
    could not be drawn (it is then printed from its SVG, which raises the figure's own error)."""
    try:
        return getattr(figure, "pdf", None)
    except Exception:  # noqa: BLE001 - see above
        return None


def page_size_pt(pdf: bytes) -> tuple[float, float]:
    """(width, height) in points of the first page of a figure PDF."""
    found = _MEDIA_BOX.search(pdf)
    if found is not None:
        return float(found.group(1)), float(found.group(2))
    import pikepdf  # lazy: heavy optional import (a PDF that writes its box otherwise)

    with pikepdf.open(io.BytesIO(pdf)) as document:
        box = [float(v) for v in document.pages[0].mediabox]
    return box[2] - box[0], box[3] - box[1]


def placeholder_svg(pdf: bytes) -> bytes:
    """An SVG that draws nothing, of the figure PDF's size: the layout gives it the figure's box."""
    width, height = page_size_pt(pdf)
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}pt" height="{height}pt" '
        f'viewBox="0 0 {width} {height}"></svg>'
    ).encode()


@dataclass(frozen=True)
class Placement:
    """A figure's place on a page, in PDF points from the page's lower left corner."""

    page: int
    url: str
    left: float
    bottom: float
    right: float
    top: float


def placements(document, forms: Mapping[str, bytes], base: str) -> list[Placement]:
    """Where each placeholder of ``forms`` (URL -> figure PDF) was laid out in ``document`` (a
    WeasyPrint document rendered with ``base`` as its base URL): the content box of its image."""
    found: list[Placement] = []

    def walk(box, number: int, height_pt: float) -> None:
        box = getattr(box, "_box", box)  # an absolutely placed box's placeholder
        element = getattr(box, "element", None)
        if getattr(box, "replacement", None) is not None and element is not None:
            url = unquote(urljoin(base, element.get("src") or ""))
            if url in forms:
                x, y = box.content_box_x(), box.content_box_y()
                found.append(
                    Placement(
                        number,
                        url,
                        x * _POINTS_PER_PX,
                        height_pt - (y + box.height) * _POINTS_PER_PX,
                        (x + box.width) * _POINTS_PER_PX,
                        height_pt - y * _POINTS_PER_PX,
                    )
                )
        for child in getattr(box, "children", ()):
            walk(child, number, height_pt)

    for number, page in enumerate(document.pages):
        walk(page._page_box, number, page.height * _POINTS_PER_PX)
    return found


def stamp(pdf: bytes, where: list[Placement], forms: Mapping[str, bytes]) -> bytes:
    """``pdf`` with each figure's page drawn into its placement (scaled to the box, its aspect
    kept), as a form XObject stored once however often it is placed."""
    if not where:
        return pdf
    import pikepdf  # lazy: heavy optional import (only a printed report with figures)

    with pikepdf.open(io.BytesIO(pdf)) as document:
        made: dict[str, Any] = {}
        for placement in where:
            form = made.get(placement.url)
            if form is None:
                with pikepdf.open(io.BytesIO(forms[placement.url])) as figure:
                    form = made[placement.url] = document.copy_foreign(
                        figure.pages[0].as_form_xobject()
                    )
            document.pages[placement.page].add_overlay(
                form,
                pikepdf.Rectangle(placement.left, placement.bottom, placement.right, placement.top),
            )
        out = io.BytesIO()
        document.save(out, deterministic_id=True)
    return out.getvalue()


class NotPlaced(RuntimeError):
    """A figure of the page has no box to be stamped into: the PDF is made again with WeasyPrint
    drawing the figures, rather than without the figure."""


#: An image's source in a page's HTML.
_IMAGE_SOURCE = re.compile(r'<img\b[^>]*?\bsrc="([^"]+)"')


class StampedDocument:
    """A WeasyPrint document (laid out from ``html``) whose :meth:`write_pdf` stamps the
    figures' forms into its PDF; everything else (its pages, bookmarks, links) is the document's
    own. Raises :class:`NotPlaced` when a figure of ``html`` served as a placeholder was not
    found on a page."""

    def __init__(self, document, forms: Mapping[str, bytes], base: str, html: str):
        self._document = document
        self._forms = forms
        self._base = base
        self._html = html

    def __getattr__(self, name: str):
        return getattr(self._document, name)

    def write_pdf(self, *args, **kwargs) -> bytes:
        where = placements(self._document, self._forms, self._base)
        shown = {unquote(urljoin(self._base, src)) for src in _IMAGE_SOURCE.findall(self._html)}
        lost = (shown & set(self._forms)) - {placement.url for placement in where}
        if lost:
            raise NotPlaced(f"no place found for {', '.join(sorted(lost))}")
        return stamp(self._document.write_pdf(*args, **kwargs), where, self._forms)
