"""Page-layout checks on a rendered explanatory note (DSTU 3008 layout).

Reads a PDF the way a supervisor leafs through it: the pages as low-resolution images
(``pdftoppm``) for how full each one is, and the pages' text (``pdftotext -layout``) for what
starts and ends them. The report's own HTML says which headings start a chapter and what each
table's header and rows hold, so the checks need no guesses about the content.
"""

from __future__ import annotations

import functools
import html as html_lib
import re
import subprocess
from collections.abc import Callable
from pathlib import Path

import numpy as np
from PIL import Image

#: Page size and margins of templates/report.css (``@page`` and ``@page landscape``), in mm:
#: width, height, top, right, bottom, left.
PORTRAIT = (210.0, 297.0, 20.0, 15.0, 20.0, 30.0)
LANDSCAPE = (297.0, 210.0, 20.0, 20.0, 15.0, 20.0)
#: The same with ``[report] frame = "eskd"`` (templates/frame-eskd.css): the text column inside the
#: frame, above form 2а (the first sheet's form 2 is taller: text ends 55 mm from the bottom).
FRAMED_PORTRAIT = (210.0, 297.0, 20.0, 15.0, 30.0, 30.0)
FRAMED_LANDSCAPE = (297.0, 210.0, 30.0, 15.0, 15.0, 25.0)
FIRST_SHEET_BOTTOM = 55.0
#: The frame (left, top, right, bottom from the page's top-left corner, mm) and the top of the
#: title block: form 2а 277 mm, form 2 252 mm from the top; a landscape page's turned block ends
#: 20 mm from the left edge.
FRAME_PORTRAIT = (20.0, 5.0, 205.0, 292.0)
FRAME_LANDSCAPE = (5.0, 20.0, 292.0, 205.0)
BLOCK_TOP, FIRST_BLOCK_TOP, TURNED_BLOCK_RIGHT = 277.0, 252.0, 20.0
#: A page less full than this (lowest ink in the text area, as a share of its height) is short.
MIN_FILL = 1 / 3
#: Grey level (0 black … 255 white) below which a pixel counts as ink.
INK = 200


def page_images(pdf: Path, folder: Path, resolution: int = 20) -> list[Path]:
    """Every page of ``pdf`` as a grey PNG at ``resolution`` dpi, in page order."""
    folder.mkdir(parents=True, exist_ok=True)
    for old in folder.glob("page-*.png"):
        old.unlink()
    subprocess.run(
        ["pdftoppm", "-r", str(resolution), "-gray", "-png", str(pdf), str(folder / "page")],
        check=True,
    )
    return sorted(folder.glob("page-*.png"), key=lambda p: int(p.stem.rsplit("-", 1)[1]))


def _ink(png: Path, framed: bool = False, first_sheet: bool = False):
    ink = np.asarray(Image.open(png).convert("L")) < INK
    height, width = ink.shape
    if framed:
        page_w, page_h, top, right, bottom, left = (
            FRAMED_LANDSCAPE if width > height else FRAMED_PORTRAIT
        )
        bottom = FIRST_SHEET_BOTTOM if first_sheet and width < height else bottom
    else:
        page_w, page_h, top, right, bottom, left = LANDSCAPE if width > height else PORTRAIT
    px = height / page_h
    return (
        ink,
        px,
        (int(top * px), height - int(bottom * px), int(left * px), width - int(right * px)),
    )


def overflows_right(
    png: Path, tolerance_mm: float = 2.0, framed: bool = False, first_sheet: bool = False
) -> bool:
    """Whether anything between the top and bottom margins reaches into the right margin (a
    table too wide for its page); in a framed note, up to 2 mm before the frame line."""
    ink, px, (top, bottom, left, right) = _ink(png, framed, first_sheet)
    end = ink.shape[1]
    if framed:
        frame_right = (FRAME_LANDSCAPE if ink.shape[1] > ink.shape[0] else FRAME_PORTRAIT)[2]
        end = int((frame_right - 2.0) * px)
    return bool(ink[top:bottom, right + int(tolerance_mm * px) : end].any())


def under_the_block(png: Path, first_sheet: bool = False) -> bool:
    """In a framed note: whether anything is drawn between the text column and the title block
    (the 10 mm above it, below a landscape page's text and the 5 mm right of its turned block,
    each but 1,5 mm next to the text and 2 mm next to a line: a pixel of the 20 dpi images is
    1,3 mm), i.e. text running on towards the block."""
    ink, px, _ = _ink(png, True)
    if ink.shape[1] > ink.shape[0]:
        _, top, right, bottom = FRAME_LANDSCAPE
        page_h = FRAMED_LANDSCAPE[1]
        band = ink[
            int((top + 2) * px) : int((bottom - 2) * px),
            int((TURNED_BLOCK_RIGHT + 2) * px) : int(24.5 * px),
        ]
        below = ink[
            int((page_h - FRAMED_LANDSCAPE[4] + 1.5) * px) : int((bottom - 2) * px),
            int((TURNED_BLOCK_RIGHT + 2) * px) : int((right - 2) * px),
        ]
        return bool(band.any() or below.any())
    left, top, right, bottom = FRAME_PORTRAIT
    block = FIRST_BLOCK_TOP if first_sheet else BLOCK_TOP
    band = ink[
        int((block - 8.5) * px) : int((block - 2) * px),
        int((left + 2) * px) : int((right - 2) * px),
    ]
    return bool(band.any())


def _landscape(png: Path) -> bool:
    """Whether the page image is wider than it is tall."""
    with Image.open(png) as image:
        return image.width > image.height


def page_fill(png: Path, framed: bool = False) -> float:
    """How far down the text area the lowest ink reaches: 0 empty … 1 full. The running page
    number sits in the bottom margin and is not counted."""
    ink, px, (top, bottom, left, right) = _ink(png, framed)
    area = ink[top:bottom, left:right]
    rows = np.flatnonzero(area.any(axis=1))
    return 0.0 if rows.size == 0 else (rows[-1] + 1) / area.shape[0]


def framed(html: str) -> bool:
    """Whether the note is printed in the ESKD frame (``[report] frame = "eskd"``)."""
    return 'class="eskd-block' in html


def _pdftotext(pdf: Path, *args: str) -> list[str]:
    text = subprocess.run(
        ["pdftotext", "-layout", *args, str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout
    return text.split("\f")[:-1] if text.endswith("\f") else text.split("\f")


def crop_texts(pdf: Path, left: float, top: float, right: float, bottom: float) -> list[str]:
    """Each page's text inside the rectangle (mm from the page's top-left corner)."""
    pt = 72 / 25.4
    box = (
        round(left * pt),
        round(top * pt),
        round((right - left) * pt),
        round((bottom - top) * pt),
    )
    return list(_crop_texts(str(pdf), Path(pdf).stat().st_mtime_ns, box))


@functools.lru_cache(maxsize=32)
def _crop_texts(pdf: str, mtime_ns: int, box: tuple[int, int, int, int]) -> tuple[str, ...]:
    """(one run of pdftotext per file version and rectangle: the checks ask for some twice)"""
    return tuple(
        _pdftotext(
            Path(pdf),
            *(
                a
                for name, v in zip(("-x", "-y", "-W", "-H"), box, strict=True)
                for a in (name, str(v))
            ),
        )
    )


def landscape_pages(pdf: Path) -> list[bool]:
    """Per page: whether it is wider than high."""
    info = subprocess.run(
        ["pdfinfo", "-f", "1", "-l", "100000", str(pdf)], capture_output=True, text=True, check=True
    ).stdout
    sizes = re.findall(r"^Page\s+\d+ size:\s+([\d.]+) x ([\d.]+)", info, flags=re.M)
    return [float(w) > float(h) for w, h in sizes]


def first_sheets(pdf: Path) -> list[bool]:
    """Per page of a framed note: whether it carries form 2 (the first sheet), told by the texts of
    its rows "Т. контр." and "Н. контр." (17 mm × 10 mm above "Затв."), where form 2а has its two
    empty rows for changes."""
    rows = crop_texts(pdf, 21.0, 278.0, 36.0, 286.0)
    return [
        bool(text.strip()) and not wide
        for text, wide in zip(rows, landscape_pages(pdf), strict=True)
    ]


def page_texts(pdf: Path, html: str) -> list[str]:
    """The text of each page (``pdftotext -layout``); in a framed note only what is inside the
    frame and above (right of) its title block: the block's texts are read by themselves."""
    if not framed(html):
        return _pdftotext(pdf)
    left, top, right, _ = FRAME_PORTRAIT
    portrait = crop_texts(pdf, left + 1, top + 1, right - 1, BLOCK_TOP - 1)
    first = crop_texts(pdf, left + 1, top + 1, right - 1, FIRST_BLOCK_TOP - 1)
    left, top, right, bottom = FRAME_LANDSCAPE
    landscape = crop_texts(pdf, TURNED_BLOCK_RIGHT + 1, top + 1, right - 1, bottom - 1)
    return [
        w if wide else f if is_first else p
        for p, f, w, wide, is_first in zip(
            portrait, first, landscape, landscape_pages(pdf), first_sheets(pdf), strict=True
        )
    ]


#: characters that shape a line break and print nothing: pdftotext never gives them back
_INVISIBLE = dict.fromkeys(map(ord, "\u2060\u00ad\u200b"))


def _plain(markup: str) -> str:
    text = html_lib.unescape(re.sub(r"<[^>]+>", "", re.sub(r"<br\s*/?>", " ", markup)))
    return " ".join(text.translate(_INVISIBLE).split())


def headings(html: str) -> list[str]:
    """The first line of every chapter-level heading, upper case as printed."""
    out = []
    for h in re.findall(r"<h2[^>]*>(.*?)</h2>", html, flags=re.S):
        out.append(_plain(re.split(r"<br\s*/?>", h)[0]).upper())
    return out


def tables(html: str) -> dict[str, tuple[list[str], list[list[str]]]]:
    """Per table number: its header cells and its body rows (cells), continuation parts included."""
    out: dict[str, tuple[list[str], list[list[str]]]] = {}
    number = None
    for attrs, body in re.findall(r"<table([^>]*)>(.*?)</table>", html, flags=re.S):
        m = re.search(r'data-number="([^"]+)"', attrs)
        if m:
            number = m.group(1)
        elif "continuation" not in attrs or number is None:
            continue
        head = [_plain(c) for c in re.findall(r"<th[^>]*>(.*?)</th>", body, flags=re.S)]
        body_rows = re.findall(r"<tbody>(.*?)</tbody>", body, flags=re.S)
        rows = [
            [_plain(c) for c in re.findall(r"<td[^>]*>(.*?)</td>", r, flags=re.S)]
            for r in re.findall(
                r"<tr(?:\s[^>]*)?>(.*?)</tr>", body_rows[0] if body_rows else "", flags=re.S
            )
        ]
        old = out.setdefault(number, (head, []))
        old[1].extend(rows)
    return out


def _lines(page: str) -> list[str]:
    """The page's non-empty lines, whitespace normalised, the running page number (top right,
    alone or at the far end of the first line, after the continuation label) left out."""
    raw = [line for line in page.splitlines() if line.strip()]
    if raw:
        raw[0] = re.sub(r"(^|\s{3,})\d+\s*$", "", raw[0])
    lines = [" ".join(line.split()) for line in raw]
    return [line for k, line in enumerate(lines) if line or k > 0]


def _starts_table_row(line: str, table_set) -> str | None:
    """The number of the table whose header or body row ``line`` is, else None."""
    tokens = line.split()
    for number, (head, rows) in table_set.items():
        if any(tokens == " ".join(row).split() for row in rows if len(row) >= 2):
            return number
        head_tokens = " ".join(head).split()
        if (
            head
            and len(tokens) >= 3
            and tokens[0] == head_tokens[0]
            and set(tokens) <= set(head_tokens)
        ):
            return number
    return None


def layout_problems(
    pdf: Path,
    pages: list[str],
    html: str,
    folder: Path,
    *,
    table_word: str,
    figure_word: str,
    continued: Callable[[str], str],
) -> list[str]:
    """What a supervisor would return: short pages, a table wider than its page, table
    continuations without the label and the repeated header, captions left at a page's edge
    without their table or figure.

    ``pages`` is the text of each page (``pdftotext -layout``, split at form feeds);
    ``continued(number)`` the continuation label of table ``number`` in the report's language."""
    problems = []
    starts = headings(html)
    table_set = tables(html)
    lines = [_lines(p) for p in pages]

    def starts_chapter(i: int) -> bool:
        return bool(lines[i]) and any(
            h.startswith(lines[i][0].upper()) or lines[i][0].upper().startswith(h) for h in starts
        )

    # 1. No page less than a third full but the title page, a chapter's last page and a wide
    #    table's last landscape page (a portrait page follows it: the landscape pages hold the
    #    table alone); in a framed note nothing on its way into the title block.
    in_frame = framed(html)
    first = first_sheets(pdf) if in_frame else []
    framed_from = (
        first.index(True) if True in first else len(pages)
    )  # the title page and the assignment: no frame
    images = page_images(pdf, folder)
    turned = [_landscape(png) for png in images]
    for i, png in enumerate(images):
        last_of_chapter = i + 1 == len(pages) or starts_chapter(i + 1)
        last_turned = turned[i] and i + 1 < len(pages) and not turned[i + 1]
        fill = page_fill(png, in_frame)
        if i > 0 and not last_of_chapter and not last_turned and fill < MIN_FILL:
            problems.append(f"page {i + 1} is {fill:.0%} full: {(lines[i] or [''])[0][:60]!r}")
        if overflows_right(png, framed=in_frame, first_sheet=in_frame and first[i]):
            problems.append(f"page {i + 1}: something reaches into the right margin")
        if in_frame and i >= framed_from and under_the_block(png, first[i]):
            problems.append(f"page {i + 1}: something runs into the title block")

    labels = {" ".join(continued(n).split()): n for n in table_set}
    for i, page in enumerate(lines):
        if not page:
            continue
        # 2. A page that goes on with a table starts with "Table N.M continued" and its header.
        if page[0] in labels:
            head = table_set[labels[page[0]]][0]
            # a header of two lines (a long column title wraps) sets its one-line cells in the middle,
            # on its second line: the next two lines start with the first word of a header cell
            firsts = {cell.split()[0].rstrip(",") for cell in head if cell.split()}
            if (
                len(page) < 2
                or not head
                or not any(line.split()[0].rstrip(",") in firsts for line in page[1:3])
            ):
                problems.append(f"page {i + 1}: {page[0]!r} is not followed by the table's header")
            # 5. ... and carries at least two of its rows ("Продовження таблиці 7.1" over the one
            #    row 720, a copy of row 0, read as a table of its own)
            rows = [
                line
                for line in page[2:]
                if _starts_table_row(line, {labels[page[0]]: table_set[labels[page[0]]]})
            ]
            if len(rows) < 2:
                problems.append(f"page {i + 1}: {page[0]!r} goes on with {len(rows)} row(s) only")
        elif (number := _starts_table_row(page[0], table_set)) is not None:
            problems.append(
                f"page {i + 1} goes on with table {number} without {continued(number)!r}: {page[0][:60]!r}"
            )
        # 3. A table caption (above its table) never ends a page; a figure caption (below its
        #    figure) never starts one.
        for k, line in enumerate(page):
            m = re.match(rf"{re.escape(table_word)} (\S+) [–—]", line)
            if m and m.group(1) in table_set:
                first = table_set[m.group(1)][0][0].split()[0] if table_set[m.group(1)][0] else ""
                if not any(later.split()[0] == first for later in page[k + 1 :]):
                    problems.append(f"page {i + 1}: the caption {line[:50]!r} without its table")
        if re.match(rf"{re.escape(figure_word)} \S+ [–—]", page[0]):
            problems.append(
                f"page {i + 1} starts with the caption {page[0][:50]!r} away from its figure"
            )
        # 4. A table's note ("Примітка. …", under the table) never starts a page apart from its table.
        if re.match(r"(Примітка|Примечание|Note)\. ", page[0]):
            problems.append(
                f"page {i + 1} starts with a table note {page[0][:50]!r} away from its table"
            )
    return problems
