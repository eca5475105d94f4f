"""The report as an editable Word document (``--format docx``), converted by pandoc from the report HTML.

Why pandoc: it is the well-kept converter that turns HTML tables into native Word tables
(header rows repeated on every page), ``<figure>`` into a picture with its caption, and MathML
into native Word equations (OMML, ``m:oMath``), with the styles of a reference document. What
it cannot express from HTML is done on its output afterwards, in a few small XML edits: the
page set-up (A4, DSTU 3008 margins as the PDF has them, page numbers top right, none on
the title page), the contents as a Word TOC field that Word updates on opening, and the tab
stops that put an equation's number at the right margin.

The conversion follows the HTML generically rather than the sections of today:

* ``h2``/``h3``/``h4`` become Heading 1/2/3 (``h1``, the title on the title page, the Title style);
* every ``.equation`` becomes a paragraph of style "Equation": its ``.formula`` markup
  (``<i>``, ``<b>``, ``<sub>``, ``<sup>`` and text) as MathML, then its number;
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
from .figures import STYLE, tight_layout

PNG_DPI = 220
VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr",
        "mspace"}

# Page set-up in twentieths of a point (DSTU 3008: left 30 mm, right 15 mm, top and bottom 20 mm; A4).
MM = 1440 / 25.4
PAGE = {"w": 11906, "h": 16838, "top": round(20 * MM), "bottom": round(20 * MM), "left": round(30 * MM),
        "right": round(15 * MM)}
TEXT_WIDTH = PAGE["w"] - PAGE["left"] - PAGE["right"]


class DocxError(CrankdynError):
    """The Word export cannot run here (no pandoc) or pandoc failed."""


# --------------------------------------------------------------------------- a small HTML tree

@dataclass
class Node:
    tag: str  # "" for a text node, "raw" for markup passed through as it is (MathML)
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


# --------------------------------------------------------------------------- formulas as MathML

_TOKEN = re.compile(r"(?P<space>[\s\u00a0]+)|(?P<num>\d+(?:[.,]\d+)?)|(?P<sup>[⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+)"
                    r"|(?P<word>[^\W\d_]+)|(?P<op>.)", re.S)
_FROM_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789−")
_LATIN_OR_GREEK = re.compile(r"^[A-Za-z\u0370-\u03ff]+$")


def _text_items(text: str, italic: bool, bold: bool) -> list[str]:
    items: list[str] = []
    for m in _TOKEN.finditer(text):
        kind, value = m.lastgroup, m.group()
        if kind == "space":
            if "\u00a0" in value:
                items.append('<mspace width="1em"/>')
        elif kind == "num":  # a decimal comma as text: pandoc would split the number at it
            tag = "mtext" if "," in value else "mn"
            items.append(f"<{tag}>{htmlmod.escape(value)}</{tag}>")
        elif kind == "sup":  # a power of ten typeset with superscript digits (10⁻¹⁶)
            exponent = f"<mn>{htmlmod.escape(value.translate(_FROM_SUPERSCRIPT))}</mn>"
            base = items.pop() if items else "<mrow/>"
            items.append(f"<msup>{base}{exponent}</msup>")
        elif kind == "word":
            if not _LATIN_OR_GREEK.match(value):
                items.append(f"<mtext>{htmlmod.escape(value)}</mtext>")  # e.g. a unit in Cyrillic
            elif italic:
                variant = ' mathvariant="bold-italic"' if bold else ""
                items += [f"<mi{variant}>{htmlmod.escape(c)}</mi>" for c in value]
            else:
                variant = "bold" if bold else "normal"
                items.append(f'<mi mathvariant="{variant}">{htmlmod.escape(value)}</mi>')
        else:
            items.append(f"<mo>{htmlmod.escape(value)}</mo>")
    return items


def _math_items(node: Node, italic: bool = False, bold: bool = False) -> list[str]:
    items: list[str] = []
    for child in node.children:
        if "eq-carry" in child.classes():  # a sign repeated where the PDF's line breaks: Word wraps itself
            continue
        if not child.tag:
            items += _text_items(child.text, italic, bold)
        elif child.tag in ("sub", "sup"):
            script = "<mrow>" + "".join(_math_items(child, italic, bold)) + "</mrow>"
            base = items.pop() if items else "<mrow/>"
            if child.tag == "sup" and base.startswith("<msub>") and base.endswith("</msub>"):
                items.append("<msubsup>" + base[len("<msub>"):-len("</msub>")] + script + "</msubsup>")
            else:
                items.append(f"<m{child.tag}>{base}{script}</m{child.tag}>")
        else:
            items += _math_items(child, italic or child.tag in ("i", "em", "var"),
                                 bold or child.tag in ("b", "strong"))
    return items


def formula_mathml(node: Node) -> str:
    """The markup of a report formula (text, ``<i>``, ``<b>``, ``<sub>``, ``<sup>``) as inline MathML."""
    return '<math display="inline"><mrow>' + "".join(_math_items(node)) + "</mrow></math>"


# --------------------------------------------------------------------------- HTML for pandoc

def _custom(style: str, *children: Node) -> Node:
    return Node("div", {"data-custom-style": style}, list(children))


def _equation(node: Node) -> Node:
    formula = next((n for n in node.walk() if "formula" in n.classes()), None)
    number = next((n for n in node.walk() if "eqno" in n.classes()), None)
    math = formula_mathml(formula if formula is not None else node)
    paragraph = Node("p", children=[Node("raw", text=math)])
    if number is not None:
        paragraph.children.append(Node("", text=number.plain().strip()))
    return _custom("Equation", paragraph)


def _contents(node: Node) -> list[Node]:
    heading = next((n for n in node.walk() if n.tag in ("h1", "h2", "h3", "h4")), None)
    out = [_custom("TOC Heading", Node("p", children=[Node("", text=heading.plain().strip())]))] if heading else []
    entries = [n.plain().strip() for n in node.walk() if n.tag == "li"]
    out += [_custom("toc 1", Node("p", children=[Node("", text=e)])) for e in entries if e]
    return out


def _transform(node: Node, images: dict[str, str]) -> None:
    new_children: list[Node] = []
    for child in node.children:
        if child.tag in ("style", "script", "head"):
            continue
        classes = child.classes()
        if "mech-animation" in classes:  # interactive, screen only (hidden in print as well)
            continue
        if "eskd-block" in classes:  # the sheet frame's title blocks: the PDF's page furniture, not text
            continue
        if "equation" in classes:
            new_children.append(_equation(child))
            continue
        if child.tag == "nav":
            new_children += _contents(child)
            continue
        if child.tag == "h1":
            new_children.append(_custom("Title", Node("p", children=child.children)))
            continue
        if child.tag == "img" and child.attrs.get("src", "") in images:
            child.attrs["src"] = images[child.attrs["src"]]
        if "title-page" in classes:
            _transform(child, images)
            new_children.append(_custom("Title Page", child))
            continue
        _transform(child, images)
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


def pandoc_html(report_html: str, images: dict[str, str]) -> str:
    """The report HTML rewritten for pandoc: MathML equations, PNG figures, custom styles, no contents list."""
    root = parse_html(report_html)
    body = next((n for n in root.walk() if n.tag == "body"), root)
    lang = next((n.attrs.get("lang", "") for n in root.walk() if n.tag == "html"), "")
    _transform(body, images)
    return f'<!DOCTYPE html><html lang="{htmlmod.escape(lang)}"><head><meta charset="utf-8"><title></title></head>' \
           f"<body>{''.join(_serialise(c) for c in body.children)}</body></html>"


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
        raise DocxError("--format docx needs pandoc: install the Debian package 'pandoc' "
                        "(apt-get install pandoc) or the wheel 'pypandoc-binary' (pip install pypandoc-binary)") from None


def _pandoc(args: list[str], stdin: bytes | None = None) -> bytes:
    try:
        done = subprocess.run([pandoc_path(), *args], input=stdin, capture_output=True, timeout=600, check=False)
    except OSError as exc:
        raise DocxError(f"cannot run pandoc: {exc}") from None
    if done.returncode != 0:
        raise DocxError("pandoc failed: " + done.stderr.decode("utf-8", "replace").strip()[:2000])
    return done.stdout


TNR = '<w:rFonts w:ascii="Times New Roman" w:hAnsi="Times New Roman" w:eastAsia="Times New Roman" w:cs="Times New Roman"/>'

# Our styles: (styleId, name, basedOn, pPr, rPr). Paragraph properties in twips, sizes in half-points.
_STYLES = (
    ("Normal", "Normal", None, '<w:spacing w:before="0" w:after="0" w:line="360" w:lineRule="auto"/><w:jc w:val="both"/>',
     TNR + '<w:sz w:val="28"/><w:szCs w:val="28"/>'),
    ("BodyText", "Body Text", "Normal", '<w:spacing w:before="0" w:after="0"/><w:ind w:firstLine="709"/>', ""),
    ("FirstParagraph", "First Paragraph", "BodyText", "", ""),
    ("Compact", "Compact", "Normal", '<w:spacing w:before="0" w:after="0" w:line="240" w:lineRule="auto"/>'
     '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', '<w:sz w:val="24"/><w:szCs w:val="24"/>'),
    ("Title", "Title", "Normal", '<w:keepNext/><w:spacing w:before="480" w:after="240"/><w:jc w:val="center"/>',
     '<w:b/><w:bCs/><w:caps/><w:sz w:val="32"/><w:szCs w:val="32"/>'),
    ("TitlePage", "Title Page", "Normal", '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    ("Heading1", "heading 1", "Normal", '<w:keepNext/><w:keepLines/><w:pageBreakBefore/><w:spacing w:before="0" '
     'w:after="240"/><w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="0"/>',
     '<w:b/><w:bCs/><w:sz w:val="28"/><w:szCs w:val="28"/>'),
    ("Heading2", "heading 2", "Normal", '<w:keepNext/><w:keepLines/><w:spacing w:before="240" w:after="120"/>'
     '<w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="1"/>', '<w:b/><w:bCs/>'),
    ("Heading3", "heading 3", "Normal", '<w:keepNext/><w:keepLines/><w:spacing w:before="120" w:after="60"/>'
     '<w:ind w:firstLine="709"/><w:jc w:val="left"/><w:outlineLvl w:val="2"/>', '<w:b/><w:bCs/><w:i/>'),
    ("Caption", "caption", "Normal", '<w:spacing w:before="60" w:after="120"/><w:ind w:firstLine="0"/>', ""),
    ("TableCaption", "Table Caption", "Caption", '<w:keepNext/><w:jc w:val="left"/>', ""),
    ("ImageCaption", "Image Caption", "Caption", '<w:jc w:val="center"/>', ""),
    ("CaptionedFigure", "Captioned Figure", "Normal", '<w:keepNext/><w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    ("Figure", "Figure", "Normal", '<w:ind w:firstLine="0"/><w:jc w:val="center"/>', ""),
    ("Equation", "Equation", "Normal", f'<w:tabs><w:tab w:val="center" w:pos="{TEXT_WIDTH // 2}"/>'
     f'<w:tab w:val="right" w:pos="{TEXT_WIDTH}"/></w:tabs><w:spacing w:before="120" w:after="120"/>'
     '<w:ind w:firstLine="0"/><w:jc w:val="left"/>', ""),
    ("TOCHeading", "TOC Heading", "Normal", '<w:pageBreakBefore/><w:spacing w:after="240"/><w:ind w:firstLine="0"/>'
     '<w:jc w:val="center"/>', '<w:b/><w:bCs/><w:caps/>'),
    ("TOC1", "toc 1", "Normal", f'<w:tabs><w:tab w:val="right" w:leader="dot" w:pos="{TEXT_WIDTH}"/></w:tabs>'
     '<w:ind w:firstLine="0"/><w:jc w:val="left"/>', ""),
    ("TOC2", "toc 2", "Normal", f'<w:tabs><w:tab w:val="right" w:leader="dot" w:pos="{TEXT_WIDTH}"/></w:tabs>'
     '<w:ind w:left="280" w:firstLine="0"/><w:jc w:val="left"/>', ""),
)

_TABLE_STYLE = ('<w:style w:type="table" w:default="1" w:styleId="Table"><w:name w:val="Table"/>'
                '<w:basedOn w:val="TableNormal"/><w:qFormat/><w:pPr><w:ind w:firstLine="0"/></w:pPr><w:tblPr>'
                '<w:jc w:val="center"/><w:tblBorders>' + "".join(
                    f'<w:{side} w:val="single" w:sz="4" w:space="0" w:color="000000"/>'
                    for side in ("top", "left", "bottom", "right", "insideH", "insideV")) +
                '</w:tblBorders><w:tblCellMar><w:left w:w="57" w:type="dxa"/><w:right w:w="57" w:type="dxa"/>'
                '</w:tblCellMar></w:tblPr></w:style>')


def _style_xml(style_id: str, name: str, based_on: str | None, ppr: str, rpr: str) -> str:
    custom = "" if style_id in ("Normal", "BodyText", "Title", "Heading1", "Heading2", "Heading3", "Caption",
                                "TOCHeading", "TOC1", "TOC2") else ' w:customStyle="1"'
    default = ' w:default="1"' if style_id == "Normal" else ""
    parts = [f'<w:style w:type="paragraph"{default}{custom} w:styleId="{style_id}"><w:name w:val="{name}"/>']
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
    styles = re.sub(r"<w:sz w:val=\"24\" />\s*<w:szCs w:val=\"24\" />", '<w:sz w:val="28"/><w:szCs w:val="28"/>', styles)
    return styles.replace("</w:styles>", "".join(ours.values()) + "</w:styles>")


@lru_cache(maxsize=1)
def reference_docx() -> bytes:
    """The reference document carrying the styles: pandoc's default reference.docx, restyled."""
    default = _pandoc(["--print-default-data-file", "reference.docx"])
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(default)) as source, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as target:
        for item in source.infolist():
            data = source.read(item.filename)
            if item.filename == "word/styles.xml":
                data = _restyle(data.decode("utf-8")).encode("utf-8")
            target.writestr(item, data)
    return out.getvalue()


# --------------------------------------------------------------------------- after pandoc

_HEADER = ('<?xml version="1.0" encoding="UTF-8" standalone="yes"?>'
           '<w:hdr xmlns:w="http://schemas.openxmlformats.org/wordprocessingml/2006/main">'
           '<w:p><w:pPr><w:jc w:val="right"/><w:ind w:firstLine="0"/></w:pPr>'
           '<w:r><w:fldChar w:fldCharType="begin"/></w:r><w:r><w:instrText xml:space="preserve"> PAGE </w:instrText></w:r>'
           '<w:r><w:fldChar w:fldCharType="separate"/></w:r><w:r><w:t>1</w:t></w:r>'
           '<w:r><w:fldChar w:fldCharType="end"/></w:r></w:p></w:hdr>')
# DSTU 3008:2015: the page number in the top right corner (a header, as the PDF has it)
_HEADER_ID = "rIdCrankdynHeader"
_SECTION = (f'<w:sectPr><w:headerReference w:type="default" r:id="{_HEADER_ID}"/>'
            f'<w:pgSz w:w="{PAGE["w"]}" w:h="{PAGE["h"]}"/>'
            f'<w:pgMar w:top="{PAGE["top"]}" w:right="{PAGE["right"]}" w:bottom="{PAGE["bottom"]}" '
            f'w:left="{PAGE["left"]}" w:header="709" w:footer="567" w:gutter="0"/><w:titlePg/></w:sectPr>')
_TOC_BEGIN = ('<w:r><w:fldChar w:fldCharType="begin" w:dirty="true"/></w:r>'
              '<w:r><w:instrText xml:space="preserve"> TOC \\o "1-3" \\h \\z \\u </w:instrText></w:r>'
              '<w:r><w:fldChar w:fldCharType="separate"/></w:r>')
_TOC_END = '<w:r><w:fldChar w:fldCharType="end"/></w:r>'
_PARAGRAPH = re.compile(r"<w:p>(?:(?!</w:p>).)*?</w:p>|<w:p [^>]*>(?:(?!</w:p>).)*?</w:p>", re.S)


def _styled(paragraph: str, style_id: str) -> bool:
    return f'<w:pStyle w:val="{style_id}" />' in paragraph or f'<w:pStyle w:val="{style_id}"/>' in paragraph


def _equation_tabs(paragraph: str) -> str:
    """Centre the equation and put its number at the right margin (tab stops of the Equation style)."""
    tab = "<w:r><w:tab/></w:r>"
    paragraph = paragraph.replace("</w:pPr>", "</w:pPr>" + tab, 1)
    last = paragraph.rfind("<w:r>")
    if last > paragraph.find("</m:oMath>") > 0:
        paragraph = paragraph[:last] + tab + paragraph[last:]
    return paragraph


def _document(xml: str) -> str:
    paragraphs = list(_PARAGRAPH.finditer(xml))
    toc = [m for m in paragraphs if _styled(m.group(0), "TOC1")]
    edits: dict[int, str] = {}
    for m in paragraphs:
        if _styled(m.group(0), "Equation"):
            edits[m.start()] = _equation_tabs(m.group(0))
    if toc:
        first, last = toc[0], toc[-1]
        text = edits.get(first.start(), first.group(0))
        edits[first.start()] = text.replace("</w:pPr>", "</w:pPr>" + _TOC_BEGIN, 1)
        text = edits.get(last.start(), last.group(0))
        edits[last.start()] = text[:-len("</w:p>")] + _TOC_END + "</w:p>"
    out, position = [], 0
    for m in paragraphs:
        if m.start() in edits:
            out += [xml[position:m.start()], edits[m.start()]]
            position = m.end()
    xml = "".join(out) + xml[position:]
    xml = re.sub(r"<w:sectPr\s*/>|<w:sectPr>.*?</w:sectPr>(?=\s*</w:body>)", _SECTION, xml, count=1, flags=re.S)
    if 'xmlns:r="' not in xml[:2000]:
        xml = xml.replace("<w:document ", '<w:document xmlns:r="http://schemas.openxmlformats.org/officeDocument/'
                          '2006/relationships" ', 1)
    return xml


def _finish(docx: bytes) -> bytes:
    """pandoc's output with the page set-up, the header with page numbers, the TOC field and equation tabs."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(docx)) as source, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as target:
        for item in source.infolist():
            data = source.read(item.filename)
            name = item.filename
            if name == "word/document.xml":
                data = _document(data.decode("utf-8")).encode("utf-8")
            elif name == "word/_rels/document.xml.rels":
                data = data.replace(b"</Relationships>", (
                    f'<Relationship Id="{_HEADER_ID}" Type="http://schemas.openxmlformats.org/officeDocument/2006/'
                    f'relationships/header" Target="header_crankdyn.xml"/></Relationships>').encode())
            elif name == "[Content_Types].xml":
                data = data.replace(b"</Types>", b'<Override PartName="/word/header_crankdyn.xml" ContentType='
                                    b'"application/vnd.openxmlformats-officedocument.wordprocessingml.header+xml"/></Types>')
            elif name == "word/settings.xml" and b"updateFields" not in data:
                data = re.sub(rb"(<w:settings[^>]*>)", rb'\1<w:updateFields w:val="true"/>', data, count=1)
            target.writestr(item, data)
        target.writestr("word/header_crankdyn.xml", _HEADER)
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


def report_docx(html: str, figures: list, language: str) -> bytes:
    """report.docx from the report HTML and its figures (each with the matplotlib figure it was drawn from)."""
    with tempfile.TemporaryDirectory(prefix="crankdyn-docx-") as tmp:
        folder = Path(tmp)
        images: dict[str, str] = {}
        for i, figure in enumerate(figures, start=1):
            source = figure.typeset() if hasattr(figure, "typeset") else getattr(figure, "figure", None)
            if source is None:
                continue
            name = f"figure_{i:03d}.png"
            (folder / name).write_bytes(_figure_png(source))
            images["data:image/svg+xml;base64," + base64.b64encode(figure.svg).decode("ascii")] = name
        (folder / "report.html").write_text(pandoc_html(html, images), encoding="utf-8")
        (folder / "reference.docx").write_bytes(reference_docx())
        _pandoc(["--from", "html", "--to", "docx", "--shift-heading-level-by=-1", "--metadata", f"lang={language}",
                 "--reference-doc", str(folder / "reference.docx"), "--resource-path", str(folder),
                 "--output", str(folder / "report.docx"), str(folder / "report.html")])
        return _finish((folder / "report.docx").read_bytes())
