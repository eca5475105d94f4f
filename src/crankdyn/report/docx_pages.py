"""The Word document's pages as LibreOffice lays them out: continued tables, contents, page count.

Word has no "Table N continued" line on the pages a table continues on, and it fills in the
contents' page numbers and the page count only when its fields are updated. When LibreOffice
(``soffice``) is installed, the document is laid out once by it (converted to PDF, read with
``pdftotext``) and, from those pages:

* a table that goes on over a page break is split there: the rest starts on the next page under
  the label ("Продовження таблиці 2.1") and the repeated header. A forced page break makes the
  pages after it independent of those before, so one split per chapter is made per layout, and
  the layout repeated until no table goes on without its label (at most :data:`MAX_LAYOUTS`);
* the contents get their page numbers and the page count field (the abstract's) its value.

Word may lay out a page a line longer or shorter than LibreOffice; the fields (contents, page
count) are still fields and are right after "update fields" in Word.

The pass is skipped without ``soffice`` or ``pdftotext``, or with ``CRANKDYN_DOCX_LAYOUT=0``.
"""

from __future__ import annotations

import html as htmlmod
import io
import os
import re
import shutil
import subprocess
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

MAX_LAYOUTS = 8
#: LibreOffice sets an imported equation in its own default size (12 pt) unless its profile says
#: otherwise: the conversion's profile gives the body text's size.
EQUATION_POINTS = 14
CONVERSION_TIMEOUT_S = 120
_PROFILE = """<?xml version="1.0" encoding="UTF-8"?>
<oor:items xmlns:oor="http://openoffice.org/2001/registry" \
xmlns:xs="http://www.w3.org/2001/XMLSchema" \
xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
<item oor:path="/org.openoffice.Office.Math/StandardFormat">\
<prop oor:name="BaseSize" oor:op="fuse">\
<value>{points}</value></prop></item>
</oor:items>
"""


def libreoffice() -> str | None:
    """The LibreOffice program, if the layout pass can run here."""
    if (
        os.environ.get("CRANKDYN_DOCX_LAYOUT", "1").strip() == "0"
        or shutil.which("pdftotext") is None
    ):
        return None
    return shutil.which("soffice") or shutil.which("libreoffice")


def profile(folder: Path) -> Path:
    """A LibreOffice user profile for the conversion (equations at the body text's size)."""
    user = folder / "user"
    user.mkdir(parents=True, exist_ok=True)
    (user / "registrymodifications.xcu").write_text(
        _PROFILE.format(points=EQUATION_POINTS), encoding="utf-8"
    )
    return folder


def to_pdf(docx: Path, out_dir: Path, program: str, profile_dir: Path) -> Path | None:
    """``docx`` converted to PDF by LibreOffice, or None when it fails."""
    try:
        subprocess.run(
            [
                program,
                f"-env:UserInstallation={profile_dir.resolve().as_uri()}",
                "--headless",
                "--convert-to",
                "pdf",
                "--outdir",
                str(out_dir),
                str(docx),
            ],
            capture_output=True,
            timeout=CONVERSION_TIMEOUT_S,
            check=False,
        )
    except (OSError, subprocess.TimeoutExpired):
        return None
    pdf = out_dir / (docx.stem + ".pdf")
    return pdf if pdf.is_file() else None


def page_texts(pdf: Path) -> list[list[str]]:
    """Each page's non-empty lines, whitespace normalised, the running page number left out: at
    the end of the first line (top right, DSTU 3008) or as the last line (bottom centre, GOST
    7.32), where it is the page's own number (pages are counted from the title page)."""
    text = subprocess.run(
        ["pdftotext", "-layout", str(pdf), "-"],
        capture_output=True,
        text=True,
        timeout=CONVERSION_TIMEOUT_S,
        check=True,
    ).stdout
    pages = text.split("\f")
    if pages and not pages[-1].strip():
        pages.pop()
    out = []
    for number, page in enumerate(pages, start=1):
        lines = [" ".join(line.split()) for line in page.splitlines() if line.strip()]
        if lines and lines[-1] == str(number):
            lines.pop()
        elif lines:
            lines[0] = re.sub(rf"(^|\s){number}$", "", lines[0]).strip()
            if not lines[0]:
                lines.pop(0)
        out.append(lines)
    return out


# --------------------------------------------------------------------------- the document's tables

_TABLE = re.compile(r"<w:tbl>.*?</w:tbl>", re.S)
_ROW = re.compile(r"<w:tr>.*?</w:tr>", re.S)
_CELL = re.compile(r"<w:tc>.*?</w:tc>", re.S)


def _text(xml: str) -> str:
    return htmlmod.unescape("".join(re.findall(r"<w:t(?:\s[^>]*)?>([^<]*)</w:t>", xml)))


def _row_matcher(row: str):
    """Whether a line of the page's text is the row: its cells' text, or, for a row whose longest
    cell wraps over several lines, a line with the other cells' text and part of the longest."""
    cells = [_text(cell).replace("\u2060", "").split() for cell in _CELL.findall(row)]
    whole = [t for c in cells for t in c]
    longest = max(range(len(cells)), key=lambda k: len(" ".join(cells[k])), default=0)
    others = [t for k, c in enumerate(cells) if k != longest for t in c]
    long_words = set(cells[longest]) if cells else set()

    def matches(tokens: list[str]) -> bool:
        if tokens == whole:
            return True
        if not others or not long_words:
            return False
        # (the short cells are centred: on a line of their own, or with some of the longest's words)
        return [t for t in tokens if t not in long_words] == others

    return matches if whole else (lambda tokens: False)


@dataclass
class TablePart:
    """One w:tbl of a numbered table (a table split at a page break is several)."""

    start: int
    end: int
    number: str
    label: str
    head: list[str]  # the header rows' XML
    body: list[str]  # the body rows' XML
    first_row: int  # the index of its first body row in the whole table


def table_parts(xml: str) -> list[TablePart]:
    parts: list[TablePart] = []
    seen: dict[str, int] = {}
    for m in _TABLE.finditer(xml):
        number = re.search(r'<w:tblCaption w:val="([^"]*)"/>', m.group(0))
        if not number:
            continue
        label = re.search(r'<w:tblDescription w:val="([^"]*)"/>', m.group(0))
        rows = _ROW.findall(m.group(0))
        head = [r for r in rows if "<w:tblHeader/>" in r]
        body = [r for r in rows if "<w:tblHeader/>" not in r]
        key = htmlmod.unescape(number.group(1))
        parts.append(
            TablePart(
                m.start(),
                m.end(),
                key,
                htmlmod.unescape(label.group(1)) if label else "",
                head,
                body,
                seen.get(key, 0),
            )
        )
        seen[key] = seen.get(key, 0) + len(body)
    return parts


def _breaks(xml: str, pages: list[list[str]]) -> list[tuple[TablePart, int]]:
    """The tables that go on over a page break without their label: (part, index of the first
    body row on the next page within the part)."""
    found = []
    parts = table_parts(xml)
    for part in parts:
        rows = [_row_matcher(r) for r in part.body]
        last_seen = None  # (page, index) of the last body row found so far
        for i, page in enumerate(pages):
            for line in page:
                tokens = line.split()
                start = 0 if last_seen is None else last_seen[1] + 1
                k = next((k for k in range(start, len(rows)) if rows[k](tokens)), None)
                if k is None:
                    continue
                if last_seen is not None and last_seen[0] < i and k > 0:
                    found.append((part, k))
                    break
                last_seen = (i, k)
            if found and found[-1][0] is part:
                break
    return found


def _chapter(number: str) -> str:
    return number.split(".")[0]


def split_tables(xml: str, pages: list[list[str]], section_breaks: bool = True) -> tuple[str, int]:
    """``xml`` with the first unlabelled page break of each chapter's tables made a labelled one;
    and how many were made."""
    done: set[str] = set()
    edits = []
    for part, k in _breaks(xml, pages):
        if _chapter(part.number) in done:
            continue
        done.add(_chapter(part.number))
        # as in the PDF, the next page takes at least the table's last three rows
        k = min(k, len(part.body) - 3)
        if k < 2:
            continue
        table = xml[part.start : part.end]
        props = table[: table.index("<w:tr>")]
        label = (
            '<w:p><w:pPr><w:pStyle w:val="TableContinued"/><w:pageBreakBefore/><w:keepNext/>'
            '</w:pPr><w:r><w:t xml:space="preserve">'
            f"{htmlmod.escape(part.label, quote=False)}</w:t></w:r></w:p>"
        )
        first = props + "".join(part.head + part.body[:k]) + "</w:tbl>"
        rest = props + "".join(part.head + part.body[k:]) + "</w:tbl>"
        edits.append((part.start, part.end, first + label + rest))
    for start, end, text in sorted(edits, reverse=True):
        xml = xml[:start] + text + xml[end:]
    return xml, len(edits)


# ----------------------------------------------------------------- contents and page count


def _heading_key(text: str) -> str:
    return " ".join(text.upper().split())


def fill_contents(xml: str, pages: list[list[str]]) -> str:
    """The contents' entries with the page their heading is on, the page count's field with the
    number of pages."""
    entries = list(
        re.finditer(
            r'<w:p>(?:(?!</w:p>).)*?<w:pStyle w:val="TOC[12]" ?/>(?:(?!</w:p>).)*?</w:p>', xml, re.S
        )
    )
    first = _heading_key(_text(entries[0].group(0))) if entries else None
    # the contents' page: its first entry, alone or followed by its dots and page number
    listed = re.compile(rf"{re.escape(first)}[\s.]*\d*") if first else None
    contents_page = next(
        (
            i
            for i, page in enumerate(pages)
            if listed and any(listed.fullmatch(_heading_key(line)) for line in page)
        ),
        0,
    )
    out, position, page_index = [], 0, contents_page + 1
    for m in entries:
        key = _heading_key(_text(m.group(0)))
        chapter = 'w:val="TOC1"' in m.group(
            0
        )  # a chapter starts a page; a subsection is anywhere on one
        found = next(
            (
                i
                for i in range(page_index, len(pages))
                if any(
                    _heading_key(line).startswith(key)
                    or key.startswith(_heading_key(line))
                    and len(line) > 8
                    for line in (pages[i][:3] if chapter else pages[i])
                )
            ),
            None,
        )
        paragraph = m.group(0)
        if found is not None:
            page_index = found
            number = f"<w:r><w:tab/></w:r><w:r><w:t>{found + 1}</w:t></w:r>"
            # before the field's end when the entry is the last one, else at the paragraph's end
            end = paragraph.rfind('<w:r><w:fldChar w:fldCharType="end"/></w:r>')
            end = end if end > 0 else paragraph.rfind("</w:p>")
            paragraph = paragraph[:end] + number + paragraph[end:]
        out += [xml[position : m.start()], paragraph]
        position = m.end()
    xml = "".join(out) + xml[position:]
    return re.sub(
        r'(<w:instrText xml:space="preserve"> NUMPAGES </w:instrText></w:r>'
        r'<w:r><w:fldChar w:fldCharType="separate"/></w:r><w:r><w:t>)[^<]*(</w:t>)',
        lambda m: f"{m.group(1)}{len(pages)}{m.group(2)}",
        xml,
    )


# --------------------------------------------------------------------------- the pass


def _replace_document(docx: bytes, xml: str) -> bytes:
    out = io.BytesIO()
    with (
        zipfile.ZipFile(io.BytesIO(docx)) as source,
        zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as target,
    ):
        for item in source.infolist():
            data = (
                xml.encode("utf-8")
                if item.filename == "word/document.xml"
                else source.read(item.filename)
            )
            target.writestr(item, data)
    return out.getvalue()


def lay_out(docx: bytes) -> bytes:
    """``docx`` with continuation labels, the contents' page numbers and the page count as
    LibreOffice lays it out; unchanged when LibreOffice is not available or fails."""
    program = libreoffice()
    if program is None:
        return docx
    with tempfile.TemporaryDirectory(prefix="crankdyn-docx-layout-") as tmp:
        try:
            return _lay_out(docx, Path(tmp), program)
        except (OSError, subprocess.SubprocessError, UnicodeDecodeError):
            return docx  # the document as it is: its fields filled in by Word


def _lay_out(docx: bytes, folder: Path, program: str) -> bytes:
    profile_dir = profile(folder / "profile")
    xml = zipfile.ZipFile(io.BytesIO(docx)).read("word/document.xml").decode("utf-8")
    pages: list[list[str]] = []
    for layout in range(MAX_LAYOUTS + 1):
        source = folder / "report.docx"
        source.write_bytes(_replace_document(docx, xml))
        pdf = to_pdf(source, folder, program, profile_dir)
        if pdf is None:
            return docx
        pages = page_texts(pdf)
        if layout == MAX_LAYOUTS:  # the last splits' pages, laid out once more
            break
        xml, made = split_tables(xml, pages)
        if not made:
            break
    return _replace_document(docx, fill_contents(xml, pages))
