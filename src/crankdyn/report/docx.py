"""The report as an editable Word document (``--format docx``), converted by pandoc from the report HTML.

Why pandoc: it is the well-kept converter that turns HTML headings, paragraphs, lists and
``<figure>`` (a picture with its caption) into Word, with the styles of a reference document.
The blocks it cannot set from HTML as the PDF sets them are written as WordprocessingML here
(:mod:`.docx_blocks`, :mod:`.docx_math`) and stand in pandoc's input as placeholder paragraphs
replaced in its output; the page set-up (A4, DSTU 3008 margins as the PDF has them, page numbers
where the language's standard puts them as the PDF does, none on the title page, landscape
sections), the contents as a TOC field and the
abstract's page count as a NUMPAGES field are small XML edits of its output. Where LibreOffice is
installed, :mod:`.docx_pages` lays the document out once to add the "Table N.M continued" labels
and fill in the fields' results.

The conversion follows the HTML generically rather than the sections of today:

* ``h2``/``h3``/``h4`` become Heading 1/2/3 (``h1``, the title on the title page, the Title style);
  each top-level part after the title page starts a new page, an unnumbered heading is centred;
* every ``.equation`` becomes one or more paragraphs of style "Equation": its ``.formula``
  markup (``<i>``, ``<b>``, ``<sub>``, ``<sup>`` and text) as OMML, then its number;
* worked substitutions and "where" lines become left-aligned paragraphs, one a line;
* tables become Word tables with columns from their content, numbers right-aligned;
* every ``<img>`` showing one of the report's figures becomes a PNG at :data:`PNG_DPI` drawn
  from the same matplotlib figure (the HTML has it as SVG);
* ``nav`` (the contents) becomes the TOC field, its entries the field's text until Word updates it;
* the title blocks of ``[report] frame = "eskd"`` are left out: the Word document has no sheet frame
  (the PDF's page furniture; a student draws it with the university's Word template).

The styles (Times New Roman 14 pt, 1.5 line spacing, first-line indent, black headings,
grid tables, captions) are in a reference.docx made from pandoc's own default at first use.
"""

from __future__ import annotations

import base64
import html as htmlmod
import io
import re
import shutil
import subprocess
import tempfile
import zipfile
from dataclasses import dataclass, field
from functools import lru_cache
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

from ..errors import CrankdynError
from . import docx_blocks, docx_pages
from .figures import STYLE, tight_layout

PNG_DPI = 220
VOID = {
    "area",
    "base",
    "br",
    "col",
    "embed",
    "hr",
    "img",
    "input",
    "link",
    "meta",
    "source",
    "track",
    "wbr",
    "mspace",
}

# Page set-up in twentieths of a point (DSTU 3008: left 30 mm, right 15 mm, top and bottom 20 mm; A4).
MM = 1440 / 25.4
PAGE = {
    "w": 11906,
    "h": 16838,
    "top": round(20 * MM),
    "bottom": round(20 * MM),
    "left": round(30 * MM),
    "right": round(15 * MM),
}
TEXT_WIDTH = PAGE["w"] - PAGE["left"] - PAGE["right"]
# A landscape page (a wide table): left and right 20 mm, top 20 mm, bottom 15 mm, as in the PDF.
LANDSCAPE = {
    "w": PAGE["h"],
    "h": PAGE["w"],
    "top": round(20 * MM),
    "bottom": round(15 * MM),
    "left": round(20 * MM),
    "right": round(20 * MM),
}
LANDSCAPE_TEXT_WIDTH = LANDSCAPE["w"] - LANDSCAPE["left"] - LANDSCAPE["right"]


class DocxError(CrankdynError):
    """The Word export cannot run here (no pandoc) or pandoc failed."""


# --------------------------------------------------------------------------- a small HTML tree


@dataclass
class Node:
    tag: str  # "" for a text node, "raw" for markup passed through as it is
    attrs: dict[str, str] = field(default_factory=dict)
    children: list[Node] = field(default_factory=list)
    text: str = ""

    def classes(self) -> set[str]:
        return set(self.attrs.get("class", "").split())

    def walk(self):
        yield self
        for child in self.children:
            yield from child.walk()

    def plain(self) -> str:
        return self.text if not self.tag else "".join(c.plain() for c in self.children)


class _TreeBuilder(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.root = Node("root")
        self.stack = [self.root]

    def handle_starttag(self, tag, attrs):
        node = Node(tag, {k: v or "" for k, v in attrs})
        self.stack[-1].children.append(node)
        if tag not in VOID:
            self.stack.append(node)

    def handle_startendtag(self, tag, attrs):
        self.stack[-1].children.append(Node(tag, {k: v or "" for k, v in attrs}))

    def handle_endtag(self, tag):
        for i in range(len(self.stack) - 1, 0, -1):
            if self.stack[i].tag == tag:
                del self.stack[i:]
                return

    def handle_data(self, data):
        self.stack[-1].children.append(Node("", text=data))


def parse_html(text: str) -> Node:
    builder = _TreeBuilder()
    builder.feed(text)
    builder.close()
    return builder.root


# --------------------------------------------------------------------------- HTML for pandoc


def _custom(style: str, *children: Node) -> Node:
    return Node("div", {"data-custom-style": style}, list(children))


@dataclass
class _Blocks:
    """What the HTML given to pandoc only points at: the blocks written as WordprocessingML here
    (a paragraph ``RAW<n>X`` stands for ``raw[n]``) and marks for the paragraph after a mark."""

    raw: list[str] = field(default_factory=list)
    text_width: int = 0
    language: str = "en"
    folder: Path | None = None  # where the figures' PNG files are

    def continued(self, table: Node) -> str:
        """The label of a page a numbered table continues on: the one its rows carry (a long
        table's), else the catalog's ``doc.continued``."""
        number = table.attrs.get("data-number", "")
        if not number:
            return ""
        carried = next(
            (n.attrs["data-continued"] for n in table.walk() if "data-continued" in n.attrs), ""
        )
        return carried or _continued_label(self.language).format(number=number)

    def block(self, xml: str) -> Node:
        self.raw.append(xml)
        return Node("p", children=[Node("", text=f"{_RAW}{len(self.raw) - 1}X")])

    @staticmethod
    def mark(what: str) -> Node:
        return Node("p", children=[Node("", text=f"{_MARK}{what}")])


_RAW, _MARK, _NUMPAGES = "CRANKDYNRAW", "CRANKDYNMARK", "CRANKDYNNUMPAGES"
_SECTION_PORTRAIT, _SECTION_LANDSCAPE = "CRANKDYNSECTIONPORTRAIT", "CRANKDYNSECTIONLANDSCAPE"


@lru_cache(maxsize=8)
def _continued_label(language: str) -> str:
    from .i18n import (  # lazy: heavy optional import (only a continued table)
        core_catalog_dir,
        load_catalog_file,
    )

    for name in (language, "en"):
        path = core_catalog_dir() / f"{name}.toml"
        if path.is_file():
            label = load_catalog_file(path).get("doc.continued")
            if label:
                return label
    return "{number}"


#: A figure at most this high (mm): lower than the PDF's 175 mm, which shrinks a figure
#: to the rest of its page where Word moves it to the next; never wider than the text.
FIGURE_MAX_HEIGHT_MM = 150


def _figure_size(png: Path) -> dict[str, str]:
    """The width and height of a figure's picture for pandoc, in mm: its size at :data:`PNG_DPI`,
    scaled down to the PDF's greatest height and the text width."""
    import struct  # lazy: heavy optional import (only when a figure is sized)

    try:
        width_px, height_px = struct.unpack(">II", png.read_bytes()[16:24])  # the PNG's IHDR
    except (OSError, struct.error):
        return {}
    width, height = width_px / PNG_DPI * 25.4, height_px / PNG_DPI * 25.4
    scale = min(1.0, FIGURE_MAX_HEIGHT_MM / height, TEXT_WIDTH / MM / width)
    return {"width": f"{width * scale:.1f}mm", "height": f"{height * scale:.1f}mm"}


def _section_end(placeholder: str) -> str:
    """An empty paragraph of no height that ends a section (its sectPr, filled in later)."""
    return (
        '<w:p><w:pPr><w:spacing w:before="0" w:after="0" w:line="20" w:lineRule="exact"/>'
        f'<w:ind w:firstLine="0"/><w:rPr><w:sz w:val="2"/></w:rPr>{placeholder}</w:pPr></w:p>'
    )


def _equation(node: Node, blocks: _Blocks) -> Node:
    formula = next((n for n in node.walk() if "formula" in n.classes()), None)
    number = next((n for n in node.walk() if "eqno" in n.classes()), None)
    number_text = number.plain().strip() if number is not None else ""
    return blocks.block(
        docx_blocks.equation(
            formula if formula is not None else node, number_text, blocks.text_width
        )
    )


def _contents(node: Node) -> list[Node]:
    heading = next((n for n in node.walk() if n.tag in ("h1", "h2", "h3", "h4")), None)
    out = (
        [_custom("TOC Heading", Node("p", children=[Node("", text=heading.plain().strip())]))]
        if heading
        else []
    )

    def entries(list_node: Node, level: int) -> None:
        for item in (c for c in list_node.children if c.tag == "li"):
            own = "".join(c.plain() for c in item.children if c.tag not in ("ul", "ol"))
            if own.strip():
                entry = Node("p", children=[Node("", text=" ".join(own.split()))])
                out.append(_custom(f"toc {level}", entry))
            for sub in (c for c in item.children if c.tag in ("ul", "ol")):
                entries(sub, min(level + 1, 2))

    for list_node in (n for n in node.children if n.tag in ("ul", "ol")):
        entries(list_node, 1)
    return out


def _table_block(node: Node, blocks: _Blocks, images: dict[str, str]) -> list[Node]:
    """A table block (the sentence referring to it, the caption, the table, its note); a wide one
    (``.landscape``) in a landscape section of its own."""
    landscape = "landscape" in node.classes()
    width = LANDSCAPE_TEXT_WIDTH if landscape else blocks.text_width
    out: list[Node] = [blocks.block(_section_end(_SECTION_PORTRAIT))] if landscape else []
    for child in node.children:
        if child.tag == "table":
            caption = next((c for c in child.children if c.tag == "caption"), None)
            if caption is not None:
                paragraph = docx_blocks.paragraph("TableCaption", docx_blocks.runs(caption))
                out.append(blocks.block(paragraph))
            note = any("table-note" in c.classes() for c in node.children)
            xml, _ = docx_blocks.table(
                child, width, "wide" in child.classes(), blocks.continued(child), note
            )
            out.append(blocks.block(xml))
        elif child.tag:
            holder = Node("div", children=[child])
            _transform(holder, images, blocks)
            out += holder.children
    if landscape:
        out.append(blocks.block(_section_end(_SECTION_LANDSCAPE)))
    return out


#: Blocks of the title page and the assignment in a style of their own (as the PDF's CSS sets them).
_CLASS_STYLES = {
    "university": "Title Page University",
    "doc-kind": "Title Page Kind",
    "doc-title": "Title Page Subject",
    "city-year": "Title Page Year",
    "ministry": "Centred",
    "department": "Centred",
    "centered": "Centred",
    "keywords": "Keywords",
}
_BLOCKS = {"p", "div", "table", "ul", "ol", "section", "figure", "h2", "h3", "h4"}


def _transform(node: Node, images: dict[str, str], blocks: _Blocks, top: bool = False) -> None:
    new_children: list[Node] = []
    sections = 0
    for position, child in enumerate(node.children):
        first_block = not any(c.tag for c in node.children[:position])
        if child.tag in ("style", "script", "head"):
            continue
        classes = child.classes()
        if "mech-animation" in classes:  # interactive, screen only (hidden in print as well)
            continue
        if "colophon" in classes:  # the program's stamp: on screen only, as in the PDF
            continue
        if (
            "eskd-block" in classes
        ):  # the sheet frame's title blocks: the PDF's page furniture, not text
            continue
        if top and child.tag in ("section", "nav"):
            if sections:  # every part after the title page starts on a new page, as in the PDF
                new_children.append(blocks.mark("break"))
            sections += 1
        if "equation" in classes:
            new_children.append(_equation(child, blocks))
            continue
        if child.tag == "p" and "worked-line" in classes:
            new_children.append(blocks.block(docx_blocks.worked_line(child)))
            continue
        if child.tag == "p" and "where" in classes:
            new_children.append(blocks.block(docx_blocks.where(child)))
            continue
        if child.tag == "table" and "signatures" in classes:
            new_children.append(blocks.block(docx_blocks.signatures(child)))
            continue
        if "table-block" in classes:
            new_children += _table_block(child, blocks, images)
            continue
        if child.tag == "table":
            xml, _ = docx_blocks.table(
                child, blocks.text_width, "wide" in classes, blocks.continued(child)
            )
            new_children.append(blocks.block(xml))
            continue
        if child.tag == "span" and "blank" in classes:  # a line to sign on: underlined spaces
            spaces = "\u00a0" * (14 if "wide" in classes else 9)
            new_children.append(Node("u", children=[Node("", text=spaces)]))
            continue
        if child.tag == "a" and "pagecount" in classes:
            new_children.append(Node("", text=_NUMPAGES))
            continue
        if child.tag == "nav":
            new_children += _contents(child)
            continue
        if child.tag == "h1":
            new_children.append(_custom("Title", Node("p", children=child.children)))
            continue
        if child.tag == "h2" and "unnumbered" in classes:
            new_children.append(blocks.mark("centre"))
        if child.tag == "h2" and not first_block:  # under a line: the line starts the page
            new_children.append(blocks.mark("samepage"))
        style = next((s for c, s in _CLASS_STYLES.items() if c in classes), None)
        if (
            child.tag in ("div", "p")
            and style
            and not any(c.tag in _BLOCKS for c in child.children)
        ):
            new_children.append(_custom(style, Node("p", children=child.children)))
            continue
        if child.tag == "img" and child.attrs.get("src", "") in images:
            child.attrs["src"] = images[child.attrs["src"]]
            if blocks.folder:
                child.attrs.update(_figure_size(blocks.folder / child.attrs["src"]))
        if "title-page" in classes:
            _transform(child, images, blocks)
            new_children.append(_custom("Title Page", child))
            continue
        _transform(child, images, blocks)
        new_children.append(child)
    node.children = new_children


def _serialise(node: Node) -> str:
    if node.tag == "raw":
        return node.text
    if not node.tag:
        return htmlmod.escape(node.text, quote=False)
    attrs = "".join(f' {k}="{htmlmod.escape(v)}"' for k, v in node.attrs.items())
    if node.tag in VOID:
        return f"<{node.tag}{attrs}/>"
    inner = "".join(_serialise(c) for c in node.children)
    return inner if node.tag == "root" else f"<{node.tag}{attrs}>{inner}</{node.tag}>"


def pandoc_html(report_html: str, images: dict[str, str], blocks: _Blocks | None = None) -> str:
    """The report HTML rewritten for pandoc: PNG figures, custom styles, no contents list, and
    the blocks written here (equations, tables ...) as placeholders collected in ``blocks``."""
    blocks = blocks if blocks is not None else _Blocks()
    blocks.text_width = blocks.text_width or TEXT_WIDTH
    root = parse_html(report_html)
    body = next((n for n in root.walk() if n.tag == "body"), root)
    lang = next((n.attrs.get("lang", "") for n in root.walk() if n.tag == "html"), "")
    blocks.language = lang or blocks.language
    _transform(body, images, blocks, top=True)
    return (
        f'<!DOCTYPE html><html lang="{htmlmod.escape(lang)}"><head><meta charset="utf-8"><title></title></head>'
        f"<body>{''.join(_serialise(c) for c in body.children)}</body></html>"
    )


# --------------------------------------------------------------------------- pandoc and the reference document


def pandoc_path() -> str:
    """The pandoc program: on PATH (Debian's ``pandoc``) or the one the ``pypandoc-binary`` wheel carries."""
    found = shutil.which("pandoc")
    if found:
        return found
    try:
        import pypandoc  # lazy: heavy optional import (pandoc: only for a Word file)

        return pypandoc.get_pandoc_path()
    except Exception:  # noqa: BLE001 - not installed, or installed without its binary
        raise DocxError(
            "--format docx needs pandoc: install the Debian package 'pandoc' "
            "(apt-get install pandoc) or the wheel 'pypandoc-binary' (pip install pypandoc-binary)"
        ) from None


def _pandoc(args: list[str], stdin: bytes | None = None) -> bytes:
    try:
        done = subprocess.run(
            [pandoc_path(), *args], input=stdin, capture_output=True, timeout=600, check=False
        )
    except OSError as exc:
        raise DocxError(f"cannot run pandoc: {exc}") from None
    if done.returncode != 0:
        raise DocxError("pandoc failed: " + done.stderr.decode("utf-8", "replace").strip()[:2000])
    return done.stdout


TNR = '<w:rFonts w:ascii="Times New Roman" w:hAnsi="Times New Roman" w:eastAsia="Times New Roman" w:cs="Times New Roman"/>'

# Our styles: (styleId, name, basedOn, pPr, rPr). Paragraph properties in twips, sizes in half-points.
_STYLES = (
    (
        "Normal",
        "Normal",
        None,
        '<w:spacing w:before="0" w:after="0" w:line="360" w:lineRule="auto"/><w:jc w:val="both"/>',
        TNR + '<w:sz w:val="28"/><w:szCs w:val="28"/>',
    ),
    (
        "BodyText",
        "Body Text",
        "Normal",
        '<w:spacing w:before="0" w:after="0"/><w:ind w:firstLine="709"/>',
        "",
    ),
    ("FirstParagraph", "First Paragraph", "BodyText", "", ""),
    (
        "Compact",
        "Compact",
        "Normal",
        '<w:spacing w:before="0" w:after="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "TableCell",
        "Table Cell",
        "Normal",
        '<w:spacing w:before="0" w:after="0" w:line="240" w:lineRule="auto"/>'
        '<w:ind w:firstLine="0"/><w:jc w:val="center"/>',
        '<w:sz w:val="22"/><w:szCs w:val="22"/>',
    ),
    ("TitlePageUniversity", "Title Page University", "TitlePage", "", "<w:b/><w:bCs/><w:caps/>"),
    (
        "TitlePageKind",
        "Title Page Kind",
        "TitlePage",
        '<w:spacing w:before="1440" w:after="0"/>',
        '<w:b/><w:bCs/><w:caps/><w:spacing w:val="20"/><w:sz w:val="36"/><w:szCs w:val="36"/>',
    ),
    (
        "TitlePageSubject",
        "Title Page Subject",
        "TitlePage",
        '<w:spacing w:before="60" w:after="720"/><w:ind w:left="567" w:right="567" w:firstLine="0"/>',
        '<w:b/><w:bCs/><w:sz w:val="32"/><w:szCs w:val="32"/>',
    ),
    (
        "TitlePageYear",
        "Title Page Year",
        "TitlePage",
        '<w:spacing w:before="720" w:after="0"/>',
        "",
    ),
    ("Keywords", "Keywords", "BodyText", '<w:jc w:val="left"/>', "<w:caps/>"),
    ("Centred", "Centred", "Normal", '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    (
        "Title",
        "Title",
        "Normal",
        '<w:keepNext/><w:spacing w:before="480" w:after="240"/><w:jc w:val="center"/>',
        '<w:b/><w:bCs/><w:caps/><w:sz w:val="32"/><w:szCs w:val="32"/>',
    ),
    ("TitlePage", "Title Page", "Normal", '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    (
        "Heading1",
        "heading 1",
        "Normal",
        '<w:keepNext/><w:keepLines/><w:pageBreakBefore/><w:spacing w:before="0" '
        'w:after="240"/><w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="0"/>',
        '<w:b/><w:bCs/><w:caps/><w:sz w:val="28"/><w:szCs w:val="28"/>',
    ),
    (
        "Heading2",
        "heading 2",
        "Normal",
        '<w:keepNext/><w:keepLines/><w:spacing w:before="240" w:after="120"/>'
        '<w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="1"/>',
        "<w:b/><w:bCs/>",
    ),
    (
        "Heading3",
        "heading 3",
        "Normal",
        '<w:keepNext/><w:keepLines/><w:spacing w:before="120" w:after="60"/>'
        '<w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="2"/>',
        "<w:b/><w:bCs/><w:i/>",
    ),
    (
        "Caption",
        "caption",
        "Normal",
        '<w:spacing w:before="60" w:after="120"/><w:ind w:firstLine="0"/>',
        "",
    ),
    ("TableCaption", "Table Caption", "Caption", '<w:keepNext/><w:jc w:val="left"/>', ""),
    ("ImageCaption", "Image Caption", "Caption", '<w:jc w:val="center"/>', ""),
    (
        "CaptionedFigure",
        "Captioned Figure",
        "Normal",
        '<w:keepNext/><w:ind w:firstLine="0"/><w:jc w:val="center"/>',
        "",
    ),
    ("Figure", "Figure", "Normal", '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    (
        "Equation",
        "Equation",
        "Normal",
        f'<w:tabs><w:tab w:val="center" w:pos="{TEXT_WIDTH // 2}"/>'
        f'<w:tab w:val="right" w:pos="{TEXT_WIDTH}"/></w:tabs><w:spacing w:before="120" w:after="120"/>'
        '<w:ind w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "WorkedLine",
        "Worked Line",
        "Normal",
        '<w:spacing w:before="60" w:after="60"/>'
        f'<w:ind w:left="{2 * 280}" w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "Where",
        "Where",
        "Normal",
        f'<w:ind w:left="{docx_blocks.PARAGRAPH_INDENT}" w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "Signature",
        "Signature",
        "Normal",
        '<w:spacing w:before="0" w:after="0"/>'
        '<w:ind w:left="4536" w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "TableContinued",
        "Table Continued",
        "Normal",
        '<w:keepNext/><w:spacing w:before="0" w:after="60"/>'
        '<w:ind w:firstLine="0"/><w:jc w:val="left"/>',
        '<w:sz w:val="24"/><w:szCs w:val="24"/>',
    ),
    (
        "TOCHeading",
        "TOC Heading",
        "Normal",
        '<w:pageBreakBefore/><w:spacing w:after="240"/><w:ind w:firstLine="0"/>'
        '<w:jc w:val="center"/>',
        "<w:b/><w:bCs/><w:caps/>",
    ),
    (
        "TOC1",
        "toc 1",
        "Normal",
        f'<w:tabs><w:tab w:val="right" w:leader="dot" w:pos="{TEXT_WIDTH}"/></w:tabs>'
        '<w:ind w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
    (
        "TOC2",
        "toc 2",
        "Normal",
        f'<w:tabs><w:tab w:val="right" w:leader="dot" w:pos="{TEXT_WIDTH}"/></w:tabs>'
        '<w:ind w:left="280" w:firstLine="0"/><w:jc w:val="left"/>',
        "",
    ),
)

_TABLE_STYLE = (
    '<w:style w:type="table" w:default="1" w:styleId="Table"><w:name w:val="Table"/>'
    '<w:basedOn w:val="TableNormal"/><w:qFormat/><w:pPr><w:ind w:firstLine="0"/></w:pPr><w:tblPr>'
    '<w:jc w:val="center"/><w:tblBorders>'
    + "".join(
        f'<w:{side} w:val="single" w:sz="4" w:space="0" w:color="000000"/>'
        for side in ("top", "left", "bottom", "right", "insideH", "insideV")
    )
    + '</w:tblBorders><w:tblCellMar><w:left w:w="57" w:type="dxa"/><w:right w:w="57" w:type="dxa"/>'
    "</w:tblCellMar></w:tblPr></w:style>"
)


def _style_xml(style_id: str, name: str, based_on: str | None, ppr: str, rpr: str) -> str:
    custom = (
        ""
        if style_id
        in (
            "Normal",
            "BodyText",
            "Title",
            "Heading1",
            "Heading2",
            "Heading3",
            "Caption",
            "TOCHeading",
            "TOC1",
            "TOC2",
        )
        else ' w:customStyle="1"'
    )
    default = ' w:default="1"' if style_id == "Normal" else ""
    parts = [
        f'<w:style w:type="paragraph"{default}{custom} w:styleId="{style_id}"><w:name w:val="{name}"/>'
    ]
    if based_on:
        parts.append(f'<w:basedOn w:val="{based_on}"/>')
    parts.append(f"<w:qFormat/><w:pPr>{ppr}</w:pPr><w:rPr>{rpr}</w:rPr></w:style>")
    return "".join(parts)


def _restyle(styles: str) -> str:
    """pandoc's default styles.xml with ours in place of its paragraph and table styles of the same id."""
    ours = {s[0]: _style_xml(*s) for s in _STYLES}
    ours["Table"] = _TABLE_STYLE

    def replace(match: re.Match) -> str:
        style_id = re.search(r'w:styleId="([^"]+)"', match.group(0)).group(1)
        return ours.pop(style_id, match.group(0))

    styles = re.sub(r"<w:style [^>]*>.*?</w:style>", replace, styles, flags=re.S)
    # Theme fonts and accent colours (pandoc's blue headings) give way to Times New Roman in black.
    styles = re.sub(r"<w:rFonts [^>]*Theme[^>]*/>", TNR, styles)
    styles = re.sub(r"<w:color [^>]*/>", "", styles)
    styles = re.sub(
        r"<w:sz w:val=\"24\" />\s*<w:szCs w:val=\"24\" />",
        '<w:sz w:val="28"/><w:szCs w:val="28"/>',
        styles,
    )
    return styles.replace("</w:styles>", "".join(ours.values()) + "</w:styles>")


@lru_cache(maxsize=1)
def reference_docx() -> bytes:
    """The reference document carrying the styles: pandoc's default reference.docx, restyled."""
    default = _pandoc(["--print-default-data-file", "reference.docx"])
    out = io.BytesIO()
    with (
        zipfile.ZipFile(io.BytesIO(default)) as source,
        zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as target,
    ):
        for item in source.infolist():
            data = source.read(item.filename)
            if item.filename == "word/styles.xml":
                data = _restyle(data.decode("utf-8")).encode("utf-8")
            target.writestr(item, data)
    return out.getvalue()


# --------------------------------------------------------------------------- after pandoc


@dataclass(frozen=True)
class PageNumber:
    """Where a language's standard puts the page number, as the PDF's stylesheet does: DSTU
    3008:2015 in the top right corner (report.css), GOST 7.32-2017 at the bottom centre
    (report.ru.css). ``part``: the Word part that holds it, a header or a footer."""

    part: str  # "header" or "footer"
    alignment: str  # w:jc: "right" or "center"

    @property
    def element(self) -> str:
        return "w:hdr" if self.part == "header" else "w:ftr"

    @property
    def relationship_id(self) -> str:
        return f"rIdCrankdyn{self.part.capitalize()}"

    @property
    def file_name(self) -> str:
        return f"{self.part}_crankdyn.xml"

    def xml(self) -> str:
        # 12 pt on a single line, as the PDF sets it: the body text's 14 pt at 1.5 lines does not
        # fit a footer into a landscape page's 15 mm bottom margin and shortens the text area
        run = '<w:r><w:rPr><w:sz w:val="24"/><w:szCs w:val="24"/></w:rPr>'
        return (
            '<?xml version="1.0" encoding="UTF-8" standalone="yes"?>'
            f'<{self.element} xmlns:w="http://schemas.openxmlformats.org/wordprocessingml/2006/main">'
            '<w:p><w:pPr><w:spacing w:before="0" w:after="0" w:line="240" w:lineRule="auto"/>'
            f'<w:jc w:val="{self.alignment}"/><w:ind w:firstLine="0"/></w:pPr>'
            f'{run}<w:fldChar w:fldCharType="begin"/></w:r>'
            f'{run}<w:instrText xml:space="preserve"> PAGE </w:instrText></w:r>'
            f'{run}<w:fldChar w:fldCharType="separate"/></w:r>{run}<w:t>1</w:t></w:r>'
            f'{run}<w:fldChar w:fldCharType="end"/></w:r></w:p></{self.element}>'
        )


TOP_RIGHT = PageNumber("header", "right")
BOTTOM_CENTRE = PageNumber("footer", "center")
#: The page number's place by the note's language (report.ru.css moves it for GOST 7.32); the
#: others follow DSTU 3008.
PAGE_NUMBERS = {"ru": BOTTOM_CENTRE}


def page_number(language: str) -> PageNumber:
    """Where the page number of a note in ``language`` stands."""
    return PAGE_NUMBERS.get(language, TOP_RIGHT)


def _section(page: dict, first: bool, number: PageNumber = TOP_RIGHT) -> str:
    """A section's properties: its page, the header or footer with the page number (none on the
    document's first page: the title page)."""
    orient = ' w:orient="landscape"' if page["w"] > page["h"] else ""
    return (
        f'<w:sectPr><w:{number.part}Reference w:type="default" r:id="{number.relationship_id}"/>'
        f'<w:pgSz w:w="{page["w"]}" w:h="{page["h"]}"{orient}/>'
        f'<w:pgMar w:top="{page["top"]}" w:right="{page["right"]}" w:bottom="{page["bottom"]}" '
        f'w:left="{page["left"]}" w:header="709" w:footer="567" w:gutter="0"/>'
        + ("<w:titlePg/>" if first else "")
        + "</w:sectPr>"
    )


_TOC_BEGIN = (
    '<w:r><w:fldChar w:fldCharType="begin" w:dirty="true"/></w:r>'
    '<w:r><w:instrText xml:space="preserve"> TOC \\o "1-3" \\h \\z \\u </w:instrText></w:r>'
    '<w:r><w:fldChar w:fldCharType="separate"/></w:r>'
)
_TOC_END = '<w:r><w:fldChar w:fldCharType="end"/></w:r>'
_PARAGRAPH = re.compile(r"<w:p>(?:(?!</w:p>).)*?</w:p>|<w:p [^>]*>(?:(?!</w:p>).)*?</w:p>", re.S)


def _styled(paragraph: str, style_id: str) -> bool:
    return (
        f'<w:pStyle w:val="{style_id}" />' in paragraph
        or f'<w:pStyle w:val="{style_id}"/>' in paragraph
    )


def _numpages(count: str) -> str:
    """The NUMPAGES field (the abstract's page count), its result ``count`` until it is updated."""
    return (
        '<w:r><w:fldChar w:fldCharType="begin"/></w:r>'
        '<w:r><w:instrText xml:space="preserve"> NUMPAGES </w:instrText></w:r>'
        '<w:r><w:fldChar w:fldCharType="separate"/></w:r>'
        f'<w:r><w:t>{count}</w:t></w:r><w:r><w:fldChar w:fldCharType="end"/></w:r>'
    )


def _with_property(paragraph: str, prop: str) -> str:
    """``paragraph`` with the paragraph property ``prop`` (after its style, in schema order)."""
    if "<w:pPr>" in paragraph or "<w:pPr " in paragraph:
        m = re.search(r"<w:pPr\s*>(\s*<w:pStyle [^>]*/>)?", paragraph)
        return paragraph[: m.end()] + prop + paragraph[m.end() :]
    return re.sub(
        r"^<w:p(\s[^>]*)?>", lambda m: m.group(0) + f"<w:pPr>{prop}</w:pPr>", paragraph, count=1
    )


def _page_count_field(m: re.Match) -> str:
    """A run holding the page count's placeholder: the text before it, the field, the text after."""
    run = m.group(1)
    return (
        f'{run}<w:t xml:space="preserve">{m.group(2)}</w:t></w:r>'
        + _numpages("")
        + f'{run}<w:t xml:space="preserve">{m.group(3)}</w:t></w:r>'
    )


_MARK_PROPERTIES = {
    "break": "<w:pageBreakBefore/>",
    "samepage": '<w:pageBreakBefore w:val="0"/>',
    "centre": '<w:ind w:firstLine="0"/><w:jc w:val="center"/>',
}


def _document(xml: str, raw: list[str] | None = None, number: PageNumber = TOP_RIGHT) -> str:
    raw = raw or []
    paragraphs = list(_PARAGRAPH.finditer(xml))
    toc = [m for m in paragraphs if _styled(m.group(0), "TOC1") or _styled(m.group(0), "TOC2")]
    edits: dict[int, str] = {}
    pending: list[str] = []
    for m in paragraphs:
        text = m.group(0)
        found = re.search(rf"{_RAW}(\d+)X|{_MARK}(\w+)", text)
        if found and found.group(2):  # a mark: no paragraph of its own, a property of the next one
            pending.append(_MARK_PROPERTIES[found.group(2)])
            edits[m.start()] = ""
            continue
        if found:
            text = raw[int(found.group(1))]
        if pending:
            first = _PARAGRAPH.search(text)
            if first:
                changed = first.group(0)
                for prop in pending:
                    changed = _with_property(changed, prop)
                text = text[: first.start()] + changed + text[first.end() :]
            pending = []
        if text != m.group(0):
            edits[m.start()] = text
    if toc:
        first, last = toc[0], toc[-1]
        text = edits.get(first.start(), first.group(0))
        edits[first.start()] = text.replace("</w:pPr>", "</w:pPr>" + _TOC_BEGIN, 1)
        text = edits.get(last.start(), last.group(0))
        edits[last.start()] = text[: -len("</w:p>")] + _TOC_END + "</w:p>"
    out, position = [], 0
    for m in paragraphs:
        if m.start() in edits:
            out += [xml[position : m.start()], edits[m.start()]]
            position = m.end()
    xml = "".join(out) + xml[position:]
    xml = re.sub(
        rf'(<w:r>(?:<w:rPr>(?:(?!</w:r>).)*?</w:rPr>)?)<w:t(?: xml:space="preserve")?>'
        rf"([^<]*?){_NUMPAGES}([^<]*)</w:t></w:r>",
        _page_count_field,
        xml,
        flags=re.S,
    )
    xml = re.sub(
        r"<w:sectPr\s*/>|<w:sectPr>.*?</w:sectPr>(?=\s*</w:body>)",
        _SECTION_PORTRAIT,
        xml,
        count=1,
        flags=re.S,
    )
    sections = iter(range(10**6))
    xml = re.sub(
        f"{_SECTION_PORTRAIT}|{_SECTION_LANDSCAPE}",
        lambda m: _section(
            PAGE if m.group(0) == _SECTION_PORTRAIT else LANDSCAPE, next(sections) == 0, number
        ),
        xml,
    )
    if 'xmlns:r="' not in xml[:2000]:
        xml = xml.replace(
            "<w:document ",
            '<w:document xmlns:r="http://schemas.openxmlformats.org/officeDocument/'
            '2006/relationships" ',
            1,
        )
    return xml


def _finish(docx: bytes, raw: list[str] | None = None, number: PageNumber = TOP_RIGHT) -> bytes:
    """pandoc's output with the page set-up, the header or footer with page numbers, the TOC field
    and equation tabs."""
    out = io.BytesIO()
    with (
        zipfile.ZipFile(io.BytesIO(docx)) as source,
        zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as target,
    ):
        for item in source.infolist():
            data = source.read(item.filename)
            name = item.filename
            if name == "word/document.xml":
                data = _document(data.decode("utf-8"), raw, number).encode("utf-8")
            elif name == "word/_rels/document.xml.rels":
                data = data.replace(
                    b"</Relationships>",
                    (
                        f'<Relationship Id="{number.relationship_id}" Type="http://schemas.openxmlformats.org/officeDocument/2006/'
                        f'relationships/{number.part}" Target="{number.file_name}"/></Relationships>'
                    ).encode(),
                )
            elif name == "[Content_Types].xml":
                data = data.replace(
                    b"</Types>",
                    (
                        f'<Override PartName="/word/{number.file_name}" ContentType='
                        f'"application/vnd.openxmlformats-officedocument.wordprocessingml.{number.part}+xml"/></Types>'
                    ).encode(),
                )
            elif name == "word/settings.xml" and b"updateFields" not in data:
                data = re.sub(
                    rb"(<w:settings[^>]*>)", rb'\1<w:updateFields w:val="true"/>', data, count=1
                )
            target.writestr(item, data)
        target.writestr(f"word/{number.file_name}", number.xml())
    return out.getvalue()


# --------------------------------------------------------------------------- the whole conversion


def _figure_png(figure: Any) -> bytes:
    import matplotlib.pyplot as plt  # lazy: heavy optional import (matplotlib: only for a Word file's PNG figures)

    buffer = io.BytesIO()
    with plt.rc_context(STYLE):
        tight_layout(figure)  # laid out here: the SVG may have been drawn by another process
        figure.set_layout_engine(None)
        figure.savefig(buffer, format="png", dpi=PNG_DPI, metadata={"Software": None})
    return buffer.getvalue()


def report_docx(html: str, figures: list, language: str, layout: bool = True) -> bytes:
    """report.docx from the report HTML and its figures (each with the matplotlib figure it was
    drawn from); ``layout``: its pages laid out by LibreOffice where it is installed
    (:mod:`.docx_pages`)."""
    with tempfile.TemporaryDirectory(prefix="crankdyn-docx-") as tmp:
        folder = Path(tmp)
        images: dict[str, str] = {}
        for i, figure in enumerate(figures, start=1):
            source = (
                figure.typeset() if hasattr(figure, "typeset") else getattr(figure, "figure", None)
            )
            if source is None:
                continue
            name = f"figure_{i:03d}.png"
            (folder / name).write_bytes(_figure_png(source))
            images["data:image/svg+xml;base64," + base64.b64encode(figure.svg).decode("ascii")] = (
                name
            )
        blocks = _Blocks(text_width=TEXT_WIDTH, folder=folder)
        (folder / "report.html").write_text(pandoc_html(html, images, blocks), encoding="utf-8")
        (folder / "reference.docx").write_bytes(reference_docx())
        _pandoc(
            [
                "--from",
                "html",
                "--to",
                "docx",
                "--shift-heading-level-by=-1",
                "--metadata",
                f"lang={language}",
                "--reference-doc",
                str(folder / "reference.docx"),
                "--resource-path",
                str(folder),
                "--output",
                str(folder / "report.docx"),
                str(folder / "report.html"),
            ]
        )
        document = _finish((folder / "report.docx").read_bytes(), blocks.raw, page_number(language))
    return docx_pages.lay_out(document) if layout else document
