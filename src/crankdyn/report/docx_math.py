"""A report formula's markup as a native Word equation (OMML), written directly.

The formulas of the report are text with ``<i>``, ``<b>``, ``<sub>`` and ``<sup>``; brackets,
bars and braces are plain characters in that text. Word and LibreOffice draw a bracket pair
properly (the closing one matching the opening one, grown with its content) only when it is a
delimiter element (``m:d``) around its content, so matched pairs become ``m:d`` here; an
unmatched bracket (one line of a formula broken across lines) stays a plain character.

The delimiter's properties are written in the schema's order (``begChr``, ``sepChr``,
``endChr``): LibreOffice reads them in that order and takes a closing character written before
the separator for a round bracket. Every run carries the body text's size, since an equation's
size is that of its runs (LibreOffice's default for a formula is 12 pt).
"""

from __future__ import annotations

import html as htmlmod
import re
from dataclasses import dataclass

OPENING = {"(": ")", "[": "]", "{": "}"}
CLOSING = {v: k for k, v in OPENING.items()}
BAR = "|"
#: The square root sign: with a bracket after it, the radical over the bracket's content.
RADICAL = "√"
#: Characters the HTML carries for line breaking only (word joiner, soft hyphen, zero-width space).
INVISIBLE = dict.fromkeys(map(ord, "\u2060\u00ad\u200b"), None)
_FROM_SUPERSCRIPT = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789−")
_TOKEN = re.compile(
    r"(?P<space>[\s\u00a0]+)|(?P<num>\d+(?:[.,]\d+)?)|(?P<sup>[⁰¹²³⁴⁵⁶⁷⁸⁹⁻]+)"
    r"|(?P<word>[^\W\d_]+)|(?P<op>.)",
    re.S,
)
_LATIN_OR_GREEK = re.compile(r"^[A-Za-z\u0370-\u03ff]+$")

#: Widths in ems used to estimate a formula's length (Cambria Math: about half an em a letter).
CHAR_EM, SCRIPT_EM, OPERATOR_EM = 0.5, 0.35, 0.8
#: Relations and binary operators: the equation sets the space around them.
OPERATORS = set("=+−±×≈≠<>≤≥→")
#: Characters set as ordinary text (LibreOffice Math draws "*" alone as "¿"), and punctuation,
#: never the base of a script.
ORDINARY, PUNCTUATION = set("*#%&"), set("/,;:·…")
_TO_SUPERSCRIPT = str.maketrans("0123456789−+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")
_TO_SUBSCRIPT = str.maketrans("0123456789−+", "₀₁₂₃₄₅₆₇₈₉₋₊")


@dataclass
class Item:
    """One piece of a formula: its OMML and its estimated width in ems."""

    xml: str
    width: float
    # "run", "sub" (an m:sSub, which a following superscript joins), "d", "operator", "space",
    # "gap", "radical" (a root sign, waiting for its bracket)
    kind: str = "run"
    base: str = ""
    script: str = ""


def _text_properties(font: str, size: int) -> str:
    return (
        f'<w:rPr><w:rFonts w:ascii="{font}" w:hAnsi="{font}" w:cs="{font}"/>'
        f'<w:sz w:val="{size}"/><w:szCs w:val="{size}"/></w:rPr>'
    )


def _run(text: str, style: str, size: int) -> str:
    """An m:r: ``style`` is "" (math italic), "p" (upright), "b", "bi" or "nor" (ordinary text)."""
    if style == "nor":
        rpr = '<m:rPr><m:nor/><m:sty m:val="p"/></m:rPr>'
    else:
        rpr = f'<m:rPr><m:sty m:val="{style}"/></m:rPr>' if style else ""
    wrpr = _text_properties("Times New Roman" if style == "nor" else "Cambria Math", size)
    return (
        f'<m:r>{rpr}{wrpr}<m:t xml:space="preserve">{htmlmod.escape(text, quote=False)}</m:t></m:r>'
    )


def delimiter(opening: str, closing: str, content: str, size: int) -> str:
    """An m:d around ``content`` (its properties in the schema's order); the brackets Word draws
    itself take their size from the control properties (m:ctrlPr), the runs' size."""
    return (
        f'<m:d><m:dPr><m:begChr m:val="{htmlmod.escape(opening)}"/><m:sepChr m:val=""/>'
        f'<m:endChr m:val="{htmlmod.escape(closing)}"/><m:grow/>'
        f"<m:ctrlPr>{_text_properties('Cambria Math', size)}</m:ctrlPr></m:dPr>"
        f"<m:e>{content}</m:e></m:d>"
    )


def radical(content: str, size: int) -> str:
    """An m:rad (a square root, its degree hidden) over ``content``: the root sign Word draws
    itself, its bar over the whole radicand."""
    return (
        f'<m:rad><m:radPr><m:degHide m:val="1"/>'
        f"<m:ctrlPr>{_text_properties('Cambria Math', size)}</m:ctrlPr></m:radPr>"
        f"<m:deg/><m:e>{content}</m:e></m:rad>"
    )


class _Builder:
    """Collects items; brackets open and close frames, a closed frame becomes one m:d item."""

    def __init__(self, size: int):
        self.size = size
        self.frames: list[tuple[str, list[Item]]] = [("", [])]

    @property
    def items(self) -> list[Item]:
        return self.frames[-1][1]

    def add(self, item: Item) -> None:
        """Add ``item``; an operator takes the spaces around it into its run of ordinary text,
        so that it is spaced as in the PDF (Word and LibreOffice space a math operator each
        their own way, and LibreOffice not at all next to ordinary text)."""
        last = self.items[-1] if self.items else None
        if item.kind == "space" and (last is None or last.kind == "space"):
            return
        if (
            item.kind == "space"
            and last is not None
            and last.kind == "operator"
            and not last.script.endswith(" ")
        ):
            self.items[-1] = self.operator(last.script + " ")
            return
        if item.kind == "operator" and last is not None and last.kind == "space":
            self.items.pop()
            item = self.operator(" " + item.script)
        self.items.append(item)

    def operator(self, text: str) -> Item:
        return Item(
            _run(text, "nor", self.size),
            OPERATOR_EM * (0.6 + 0.2 * len(text)),
            "operator",
            script=text,
        )

    def text(self, text: str, style: str) -> None:
        self.add(Item(_run(text, style, self.size), CHAR_EM * len(text)))

    def delimiter_char(self, char: str) -> None:
        top = self.frames[-1][0]
        if char == BAR and top == BAR or char in CLOSING and top == CLOSING[char]:
            opening, items = self.frames.pop()
            closing = BAR if char == BAR else char
            if opening == "(" and self.items and self.items[-1].kind == "radical":
                self.items.pop()  # "√(…)": a radical over the bracket's content, as typeset
                self.add(
                    Item(
                        radical("".join(i.xml for i in items), self.size),
                        sum(i.width for i in items) + 1.5 * CHAR_EM,
                    )
                )
                return
            self.add(
                Item(
                    delimiter(opening, closing, "".join(i.xml for i in items), self.size),
                    sum(i.width for i in items) + 2 * CHAR_EM,
                    "d",
                )
            )
        elif char == BAR or char in OPENING:
            self.frames.append((char, []))
        else:  # a closing bracket whose opening one is on another line: ordinary text (LibreOffice
            # draws a lone math bracket as "¿")
            self.text(char, "nor")

    def script(self, tag: str, content: list[Item]) -> None:
        script_xml = "".join(i.xml for i in content)
        width = SCRIPT_EM / CHAR_EM * sum(i.width for i in content)
        if not self.items or self.items[-1].kind in ("operator", "space", "gap", "punct"):
            # a script with no base (the "¹/₁₆" of a fraction in text): the digits raised or lowered
            # as characters, else on an empty base (an empty m:e is drawn as a box by LibreOffice)
            text = "".join(re.findall(r"<m:t[^>]*>([^<]*)</m:t>", script_xml))
            table = _TO_SUPERSCRIPT if tag == "sup" else _TO_SUBSCRIPT
            if text and text.translate(table) != text and not re.search(r"[^0-9−+]", text):
                self.text(text.translate(table), "nor")
                return
            self.add(Item(_run("\u200a", "nor", self.size), 0.1))
        base = self.items.pop()
        if tag == "sup" and base.kind == "sub":
            self.add(
                Item(
                    f"<m:sSubSup><m:e>{base.base}</m:e><m:sub>{base.script}</m:sub>"
                    f"<m:sup>{script_xml}</m:sup></m:sSubSup>",
                    base.width + width,
                    "run",
                )
            )
        elif tag == "sub":
            self.add(
                Item(
                    f"<m:sSub><m:e>{base.xml}</m:e><m:sub>{script_xml}</m:sub></m:sSub>",
                    base.width + width,
                    "sub",
                    base.xml,
                    script_xml,
                )
            )
        else:
            self.add(
                Item(
                    f"<m:sSup><m:e>{base.xml}</m:e><m:sup>{script_xml}</m:sup></m:sSup>",
                    base.width + width,
                )
            )

    def finish(self) -> list[Item]:
        """The items, unclosed brackets as plain characters before their content."""
        while len(self.frames) > 1:
            opening, items = self.frames.pop()
            self.text(opening, "nor")
            self.items.extend(items)
        return self.items


def _tokens(builder: _Builder, text: str, italic: bool, bold: bool) -> None:
    for m in _TOKEN.finditer(text.translate(INVISIBLE)):
        kind, value = m.lastgroup, m.group()
        if kind == "space":
            # ordinary text: a math run's spaces are dropped (LibreOffice) or replaced by its
            # own spacing
            if (
                "\u00a0" in value and len(value) > 1
            ):  # the gap between the parts of a formula (", &nbsp; ")
                builder.add(Item(_run("\u2002\u2002", "nor", builder.size), 1.0, "gap"))
            elif value == "\u202f":  # a narrow space (a number and its unit)
                builder.add(Item(_run("\u202f", "nor", builder.size), 0.15, "space"))
            else:
                builder.add(Item(_run(" ", "nor", builder.size), 0.25, "space"))
        elif kind == "num":
            builder.text(value, "p")
        elif kind == "sup":  # a power of ten typeset with superscript digits (10⁻¹⁶)
            inner = _Builder(builder.size)
            inner.text(value.translate(_FROM_SUPERSCRIPT), "p")
            builder.script("sup", inner.finish())
        elif kind == "word":
            if not _LATIN_OR_GREEK.match(value):
                builder.text(value, "nor")  # e.g. a unit in Cyrillic
            elif italic:
                for char in value:
                    builder.text(char, "bi" if bold else "")
            else:
                builder.text(value, "b" if bold else "p")
        elif value in OPENING or value in CLOSING or value == BAR:
            builder.delimiter_char(value)
        elif value == RADICAL:  # its bracket, when it closes on this line, makes an m:rad
            builder.add(Item(_run(value, "p", builder.size), CHAR_EM, "radical"))
        elif value in OPERATORS:
            builder.add(builder.operator(value))
        elif value in ORDINARY:  # a character LibreOffice Math reads as an operator of its own
            builder.text(value, "nor")
        else:
            builder.add(
                Item(
                    _run(value, "p", builder.size),
                    CHAR_EM,
                    "punct" if value in PUNCTUATION else "run",
                )
            )


def _walk(builder: _Builder, node, italic: bool = False, bold: bool = False) -> None:
    for child in node.children:
        classes = child.classes()
        if "eq-carry" in classes:  # a sign repeated where the PDF's line breaks
            continue
        if not child.tag:
            _tokens(builder, child.text, italic, bold)
        elif child.tag in ("sub", "sup"):
            inner = _Builder(builder.size)
            _walk(inner, child, italic, bold)
            builder.script(child.tag, inner.finish())
        elif child.tag == "br":
            continue
        else:
            _walk(
                builder,
                child,
                italic or child.tag in ("i", "em", "var"),
                bold or child.tag in ("b", "strong"),
            )


def formula_items(node, size: int) -> list[Item]:
    """The formula markup of ``node`` as OMML items at ``size`` half-points."""
    builder = _Builder(size)
    _walk(builder, node)
    return builder.finish()


def formula_width(node, size: int) -> float:
    """The estimated width of the formula of ``node`` in points."""
    return sum(i.width for i in formula_items(node, size)) * size / 2


def omml(node, size: int) -> str:
    """The formula markup of ``node`` (text, ``<i>``, ``<b>``, ``<sub>``, ``<sup>``) as m:oMath."""
    return "<m:oMath>" + "".join(i.xml for i in formula_items(node, size)) + "</m:oMath>"
