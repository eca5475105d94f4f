"""Blocks of the Word document written as WordprocessingML directly, not through pandoc.

pandoc turns HTML into Word well in general, but some blocks of the report need what its HTML
reader cannot express: an equation's number at the right margin and a long equation set on
several lines; the worked substitutions and the "where" lines as left-aligned paragraphs, one a
line (a justified paragraph with line breaks stretches its lines across the page); tables with
columns as wide as their content, numbers right-aligned as in the PDF, header rows repeated
and rows never split; the title page's signature block as lines, not a grid. Each such block is
written here from the report's HTML tree (:class:`~crankdyn.report.docx.Node`).
"""

from __future__ import annotations

import html as htmlmod
import re

from . import docx_math

#: Sizes in half-points: the body text, a table's text, a wide (landscape) table's text.
BODY_SIZE, TABLE_SIZE, WIDE_TABLE_SIZE, SMALLEST_EQUATION_SIZE = 28, 22, 18, 20
#: Twips (twentieths of a point).
PARAGRAPH_INDENT = 709  # 1.25 cm
CELL_MARGIN = 57  # each side (1 mm)
#: A character's width in ems for estimating column widths (Times New Roman: about half an em;
#: Cyrillic capitals and bold digits wider).
TEXT_EM = 0.58


def escape(text: str) -> str:
    return htmlmod.escape(text, quote=False)


def _run(text: str, italic: bool, bold: bool, script: str, size: int | None) -> str:
    props = ("<w:b/><w:bCs/>" if bold else "") + ("<w:i/><w:iCs/>" if italic else "")
    if size:
        props += f'<w:sz w:val="{size}"/><w:szCs w:val="{size}"/>'
    if script:
        props += f'<w:vertAlign w:val="{script}"/>'
    rpr = f"<w:rPr>{props}</w:rPr>" if props else ""
    return f'<w:r>{rpr}<w:t xml:space="preserve">{escape(text)}</w:t></w:r>'


def runs(
    node,
    size: int | None = None,
    italic: bool = False,
    bold: bool = False,
    script: str = "",
    skip: frozenset = frozenset(),
) -> str:
    """The inline markup of ``node`` (text, ``<i>``, ``<b>``, ``<sub>``, ``<sup>``, ``<br>``) as
    w:r runs;
    elements with a class in ``skip`` are left out."""
    out = []
    for child in node.children:
        if child.classes() & skip:
            continue
        if not child.tag:
            if child.text:
                out.append(_run(child.text, italic, bold, script, size))
        elif child.tag == "br":
            out.append("<w:r><w:br/></w:r>")
        elif child.tag in ("sub", "sup"):
            out.append(
                runs(
                    child,
                    size,
                    italic,
                    bold,
                    "subscript" if child.tag == "sub" else "superscript",
                    skip,
                )
            )
        else:
            out.append(
                runs(
                    child,
                    size,
                    italic or child.tag in ("i", "em", "var"),
                    bold or child.tag in ("b", "strong"),
                    script,
                    skip,
                )
            )
    return "".join(out)


def paragraph(style: str, content: str, ppr: str = "") -> str:
    return f'<w:p><w:pPr><w:pStyle w:val="{style}"/>{ppr}</w:pPr>{content}</w:p>'


# --------------------------------------------------------------------------- equations


def _split_parts(formula) -> list[list]:
    """The formula's children grouped by its parts (``.eq-part``), each with the separator
    before it."""
    groups: list[list] = [[]]
    for child in formula.children:
        if "eq-part" in child.classes() and any(
            "eq-part" in c.classes() for g in groups for c in g
        ):
            groups.append([])
        groups[-1].append(child)
    return [g for g in groups if g]


def _strip_separator(children: list) -> list:
    """A line of parts without the comma and spaces it starts with (they end the line before)."""
    out = list(children)
    while out and not out[0].tag and not out[0].text.strip(" ,\u00a0\u2060"):
        out.pop(0)
    if out and not out[0].tag:
        text = out[0].text.lstrip(" \u00a0\u2060")
        out[0] = type(out[0])("", text=text)
    return out


def equation(formula, number: str, text_width: int) -> str:
    """An equation as one or more paragraphs of style "Equation": the formula centred (a tab to
    the centre), the number at the right margin. A formula wider than the line is set on several
    lines at its parts' boundaries; a part wider than a line alone is set smaller."""
    node_type = type(formula)
    number_width = 20 * (len(number) * TEXT_EM * BODY_SIZE / 2 + 10)  # the number and a gap
    available = text_width - number_width  # twips
    centred = 2 * (text_width / 2 - number_width)

    def width(children: list, size: int) -> float:
        return 20 * docx_math.formula_width(node_type("span", children=children), size)

    parts = _split_parts(formula)
    lines: list[list] = []
    for part in parts:
        if lines and width(lines[-1] + part, BODY_SIZE) <= available:
            lines[-1] += part
        else:
            lines.append(_strip_separator(part) if lines else part)
    out = []
    for k, children in enumerate(lines):
        size = BODY_SIZE
        while size > SMALLEST_EQUATION_SIZE and width(children, size) > available:
            size -= 2
        last = k == len(lines) - 1
        math = docx_math.omml(node_type("span", children=children), size)
        centre = width(children, size) <= centred
        tail = (
            f'<w:r><w:tab/></w:r><w:r><w:t xml:space="preserve">{escape(number)}</w:t></w:r>'
            if last and number
            else ""
        )
        ppr = "" if last else "<w:keepNext/>"
        if not centre:  # too wide to centre: it starts at the left margin
            ppr += f'<w:tabs><w:tab w:val="clear" w:pos="{text_width // 2}"/></w:tabs>'
        out.append(
            paragraph("Equation", ("<w:r><w:tab/></w:r>" if centre else "") + math + tail, ppr)
        )
    return "".join(out)


# ----------------------------------------------------------------- worked lines and "where"


def worked_line(node) -> str:
    """A worked substitution: one left-aligned paragraph per line of the PDF (``br.eq-break``)."""
    lines: list[list] = [[]]
    for child in node.children:
        if child.tag == "br" and "eq-break" in child.classes():
            lines.append([])
        else:
            lines[-1].append(child)
    node_type = type(node)
    out = []
    for k, children in enumerate(lines):
        ppr = "<w:keepNext/>" if k < len(lines) - 1 else ""
        out.append(paragraph("WorkedLine", runs(node_type("span", children=children)), ppr))
    return "".join(out)


def where(node) -> str:
    """The "where" lines under an equation: "where" at the paragraph indent, each explained
    symbol on a line of its own, aligned after the word."""
    word = next((c for c in node.walk() if "where-word" in c.classes()), None)
    lines = [c for c in node.walk() if "where-line" in c.classes()]
    if not lines:
        return paragraph("Where", runs(node))
    word_text = word.plain().strip() if word is not None else ""
    hang = round(20 * (len(word_text) * 0.55 * BODY_SIZE / 2 + 6))
    left = PARAGRAPH_INDENT + hang
    out = []
    for k, line in enumerate(lines):
        keep = "<w:keepNext/>" if k < len(lines) - 1 else ""
        if k == 0:
            ppr = (
                f'{keep}<w:tabs><w:tab w:val="left" w:pos="{left}"/></w:tabs>'
                f'<w:ind w:left="{left}" w:hanging="{hang}"/>'
            )
            content = _run(word_text, False, False, "", None) + "<w:r><w:tab/></w:r>" + runs(line)
        else:
            ppr = f'{keep}<w:ind w:left="{left}" w:firstLine="0"/>'
            content = runs(line)
        out.append(paragraph("Where", content, ppr))
    return "".join(out)


# --------------------------------------------------------------------------- the signature block


def signatures(table) -> str:
    """The title page's signature block as lines without borders: blanks as underlined tabs."""
    out = []
    for row in (n for n in table.walk() if n.tag == "tr"):
        content = []
        for child in row.walk():
            if child is row or child.tag != "td":
                continue
            content.append(_cell_line(child))
        text = "".join(content)
        out.append(paragraph("Signature", text or "<w:r><w:t></w:t></w:r>"))
    return "".join(out)


def _cell_line(cell) -> str:
    out = []
    for child in cell.children:
        classes = child.classes()
        if "blank" in classes:
            length = 14 if "wide" in classes else 9
            out.append(
                f'<w:r><w:rPr><w:u w:val="single"/></w:rPr><w:t xml:space="preserve">'
                f"{chr(0xA0) * length}</w:t></w:r>"
            )
        elif "hint" in classes:
            out.append(
                '<w:r><w:rPr><w:sz w:val="20"/><w:szCs w:val="20"/></w:rPr>'
                f'<w:t xml:space="preserve">'
                f"{escape(child.plain())}</w:t></w:r>"
            )
        elif not child.tag:
            out.append(_run(child.text.replace("\n", " "), False, False, "", None))
        else:
            out.append(runs(type(cell)("span", children=[child])))
    return "".join(out)


# --------------------------------------------------------------------------- tables

_NUMBER = re.compile(r"^[−\-+]?[\d\s\u00a0\u202f]*[\d][\d,.\s\u00a0\u202f]*(?:[eE·×][\d⁰-⁹⁻−-]+)?$")


def _cell_text(cell) -> str:
    return " ".join(cell.plain().replace("\u2060", "").split())


def text_ems(text: str) -> float:
    """The estimated width of ``text`` in ems (Times New Roman): capitals wider than the average
    character (:data:`TEXT_EM`), spaces narrower."""
    return sum(0.25 if c.isspace() else 0.72 if c.isupper() else TEXT_EM for c in text)


#: Where a line may break: white space but the no-break spaces (a number's group separator
#: "19 891", "8,675 МПа"), and after a range's dash or a slash.
_BREAK = re.compile(r"[^\S\u00a0\u2007\u202f]+|(?<=[–/])")


def _longest_word(text: str) -> float:
    """The width in ems of the longest piece of ``text`` a line cannot break: words (a number
    with its no-break group separators is one), and ranges after their dash ("60–")."""
    return max((text_ems(w) for w in _BREAK.split(text)), default=0.0)


def _candidate_widths(rows: list[list], header_rows: int, size: int) -> list[list[float]]:
    """Column widths in twips with the header on one line, with it wrapped at its words, and with
    every cell wrapped at its words."""
    columns = max((len(r) for r in rows), default=0)
    em = size * 10  # twips per em at ``size`` half-points
    full, natural, least = ([0.0] * columns for _ in range(3))
    for k, row in enumerate(rows):
        position = 0
        for cell in row:
            span = int(cell.attrs.get("colspan", "1") or 1)
            c, position = position, position + span
            if span > 1 or c >= columns:
                continue
            text = _cell_text(cell)
            whole, words = text_ems(text) * em, _longest_word(text) * em
            full[c] = max(full[c], whole)
            natural[c] = max(natural[c], words if k < header_rows else whole)
            least[c] = max(least[c], words)
    pad = 2 * CELL_MARGIN + 80
    return [[max(w, 1.5 * em) + pad for w in ws] for ws in (full, natural, least)]


def fits(rows: list[list], header_rows: int, size: int, text_width: int) -> bool:
    """Whether the table fits the text width at ``size``, its header wrapped at its words at
    most."""
    return sum(_candidate_widths(rows, header_rows, size)[1]) <= text_width


def column_widths(rows: list[list], header_rows: int, size: int, text_width: int) -> list[int]:
    """Column widths in twips from the content: each column as wide as its longest cell, the
    header on one line if the table then fits the text width, else wrapped at its words; body
    cells wrapped at their words if still too wide. A word or number is never broken: a table
    whose words alone are too wide is scaled to the text width."""
    widths = _candidate_widths(rows, header_rows, size)
    for candidate in widths[:2]:
        if sum(candidate) <= text_width:
            return [round(w) for w in candidate]
    natural, least = widths[1], widths[2]
    spare, excess = (
        sum(n - m for n, m in zip(natural, least, strict=False)),
        sum(natural) - text_width,
    )
    if spare >= excess:  # wrap the longer cells' text
        return [round(n - (n - m) * excess / spare) for n, m in zip(natural, least, strict=False)]
    return [round(m * text_width / sum(least)) for m in least]


def _wraps(cells: list, widths: list[int], size: int) -> bool:
    """Whether a cell of the row takes more than one line (its estimated text wider than its
    column)."""
    column = 0
    for cell in cells:
        span = int(cell.attrs.get("colspan", "1") or 1)
        room = sum(widths[column : column + span]) - 2 * CELL_MARGIN
        column += span
        if text_ems(_cell_text(cell)) * size * 10 > room:
            return True
    return False


def _alignment(cell, header: bool, first: bool, table_classes: set[str]) -> str:
    if header or "text" in cell.classes():
        return "center"
    if first and "values" in table_classes:
        return "left"
    text = _cell_text(cell)
    return "right" if _NUMBER.match(text) or not text else "center"


def _identity(node, continued: str) -> str:
    number = node.attrs.get("data-number", "")
    if not number:
        return ""
    return (
        f'<w:tblCaption w:val="{htmlmod.escape(number)}"/>'
        f'<w:tblDescription w:val="{htmlmod.escape(continued)}"/>'
    )


#: A table of at most this many body rows is kept on one page in Word (a third of a page of
#: table rows at the body's line spacing): split, it would leave a few rows and their header
#: under a "continued" label on the next page.
SHORT_TABLE_ROWS = 12


def table(
    node, text_width: int, wide: bool, continued: str = "", note: bool = False
) -> tuple[str, int]:
    """The table (w:tbl) and its font size: header rows repeated on every page.
    A numbered table carries its number and its continuation label ("Table N continued") as its
    caption and description (``w:tblCaption``, ``w:tblDescription``), for the page pass.
    As in the PDF, the header and the first two rows keep together (under the caption before
    them), and so do the last rows and the table's ``note`` after them; a table of at most
    :data:`SHORT_TABLE_ROWS` rows keeps whole, moving to the next page rather than leaving a few
    rows under a "continued" label there."""
    classes = node.classes()
    head = [
        r for part in node.children if part.tag == "thead" for r in part.children if r.tag == "tr"
    ]
    body = [
        r
        for part in node.children
        if part.tag in ("tbody", "tfoot")
        for r in part.children
        if r.tag == "tr"
    ]
    body += [r for r in node.children if r.tag == "tr"]
    rows = [[c for c in r.children if c.tag in ("th", "td")] for r in head + body]
    size = TABLE_SIZE
    widths = column_widths(rows, len(head), size, text_width)
    if wide and not fits(rows, len(head), size, text_width):  # a wide table: smaller, as in the PDF
        size = WIDE_TABLE_SIZE
        widths = column_widths(rows, len(head), size, text_width)
    grid = "".join(f'<w:gridCol w:w="{w}"/>' for w in widths)
    out = [
        f'<w:tbl><w:tblPr><w:tblStyle w:val="Table"/><w:tblW w:w="{sum(widths)}" w:type="dxa"/>'
        f'<w:jc w:val="center"/><w:tblLayout w:type="fixed"/>{_identity(node, continued)}</w:tblPr>'
        f"<w:tblGrid>{grid}</w:tblGrid>"
    ]
    keep = set(range(len(head) + min(2, len(body))))  # the first three rows under the header
    keep |= set(
        range(len(head) + max(0, len(body) - 3), len(head) + len(body) - 1)
    )  # the last three
    if len(body) <= SHORT_TABLE_ROWS:
        keep |= set(range(len(head) + len(body) - 1))
    if note:
        keep.add(len(head) + len(body) - 1)
    for k, (row_node, cells) in enumerate(zip(head + body, rows, strict=False)):
        header = k < len(head)
        bold = "extremum" in row_node.classes()
        # a row of several lines never splits; w:cantSplit on every row would make LibreOffice 7.4
        # drop the rows of a table that starts near a page's end (a row of one line cannot split)
        if header:
            out.append("<w:tr><w:trPr><w:tblHeader/></w:trPr>")
        elif _wraps(cells, widths, size):
            out.append("<w:tr><w:trPr><w:cantSplit/></w:trPr>")
        else:
            out.append("<w:tr>")
        column = 0
        for c, cell in enumerate(cells):
            span = int(cell.attrs.get("colspan", "1") or 1)
            cell_width = sum(widths[column : column + span])
            column += span
            tcpr = f'<w:tcW w:w="{cell_width}" w:type="dxa"/>' + (
                f'<w:gridSpan w:val="{span}"/>' if span > 1 else ""
            )
            tcpr += '<w:vAlign w:val="center"/>'
            align = _alignment(cell, header or cell.tag == "th", c == 0, classes)
            content = (
                runs(cell, size, bold=bold or (cell.tag == "th" and False))
                or "<w:r><w:t></w:t></w:r>"
            )
            out.append(
                f"<w:tc><w:tcPr>{tcpr}</w:tcPr>"
                + paragraph(
                    "TableCell",
                    content,
                    ("<w:keepNext/>" if k in keep else "") + f'<w:jc w:val="{align}"/>',
                )
                + "</w:tc>"
            )
        out.append("</w:tr>")
    out.append("</w:tbl>")
    return "".join(out), size
