"""A figure a little smaller rather than a page left more than half empty before it.

WeasyPrint moves a figure that does not fit at the foot of a page, with the sentence announcing
it, to the next page, whatever room that leaves. Laid out once, the printed note shows where:
a page less than half full followed by a page that begins with a figure which, :data:`AT_MOST`
lower, would have fitted. Those figures get a smaller greatest height and the note is laid out
again. A drawing to scale (the kinematic scheme) or set to a share of the text width (the
mechanism's positions) keeps its size.
"""

from __future__ import annotations

from collections.abc import Iterator

#: The most a figure's image is made lower (a share of its height as laid out).
AT_MOST = 0.2
#: A page filled less than this (a share of its text height) is worth a smaller figure after it.
SHORT_PAGE = 0.5
#: Room kept beyond the measured need (CSS px, 96 a inch: 4 mm): the figure's own top margin,
#: truncated at the head of a page, counts again at the foot of the one before.
SPARE_PX = 15.0
#: The images whose size is their meaning: a drawing to scale, panels half the text width.
FIXED_SIZE = ("_scheme.svg", "_positions")


def _walk(box) -> Iterator:
    yield box
    for child in getattr(box, "children", ()):
        yield from _walk(child)


def _classes(box) -> list[str]:
    element = getattr(box, "element", None)
    return (element.get("class") or "").split() if element is not None else []


def _used_bottom(page_box, content_types) -> float:
    """How far down the page its lines, images and table rows reach (CSS px)."""
    bottoms = [
        b.position_y + b.margin_height()
        for b in _walk(page_box.children[0])
        if isinstance(b, content_types)
    ]
    return max(bottoms, default=page_box.content_box_y())


def _leading_figure(page_box):
    """The figure block (``div.figure-block``) a page begins with, or None."""
    top = page_box.content_box_y()
    for box in _walk(page_box.children[0]):
        if "figure-block" in _classes(box):
            return box if box.position_y <= top + 1.0 else None
        if box.element_tag in ("p", "table", "h2", "h3", "img") and box.position_y > top + 1.0:
            return None
    return None


def smaller_figures(document) -> dict[str, float]:
    """{image URL: greatest height, CSS px} of the figures that, that much lower, fit at the foot
    of the page before them, in the laid-out ``document`` (``weasyprint.Document``)."""
    from weasyprint.formatting_structure import boxes  # lazy: heavy optional import

    content = (boxes.LineBox, boxes.ReplacedBox, boxes.TableRowBox)
    pages = [page._page_box for page in document.pages]
    heights: dict[str, float] = {}
    for before, page in zip(pages, pages[1:], strict=False):
        if before.height != page.height:  # a landscape page: a change of page, not of room
            continue
        free = before.content_box_y() + before.height - _used_bottom(before, content)
        block = _leading_figure(page)
        if block is None or free < SHORT_PAGE * before.height:
            continue
        image = next((b for b in _walk(block) if isinstance(b, boxes.ReplacedBox)), None)
        if image is None:
            continue
        source = image.element.get("src")
        if source is None or any(mark in source for mark in FIXED_SIZE):
            continue
        need = block.margin_height() - free + SPARE_PX
        if 0 < need <= AT_MOST * image.height:
            heights[source] = image.height - need
    return heights


def fitting_style(heights: dict[str, float]) -> str:
    """The print style that gives each image of ``heights`` its greatest height."""
    rules = "".join(
        f'figure img[src="{source}"] {{ max-height: {height:.1f}px; width: auto; }}'
        for source, height in sorted(heights.items())
        if '"' not in source and "\\" not in source
    )
    return f"<style>@media print {{ {rules} }}</style>" if rules else ""
