"""The sheet frame and title block of a text document (``[report] frame = "eskd"``), for the PDF.

ДСТУ ГОСТ 2.104:2006 (ГОСТ 2.104-68) "Основні написи", with ГОСТ 2.106-96 (text documents) and
ГОСТ 2.301 (formats): on every A4 sheet of the explanatory note a frame line 20 mm from the left
edge (the binding) and 5 mm from the others; along its bottom the title block, 185 mm wide:

* form 2 (185 × 40 mm) on the note's first sheet: columns 7, 10, 23, 15, 10 mm (Зм., Арк.,
  № докум., Підпис, Дата) in rows of 5 mm — two rows for changes, the header row, then Розроб.,
  Перевір., a free row (Т. контр.), Н. контр., Затв. —; to their right the designation
  (120 × 15 mm), the document's name (70 × 25 mm), Літ. (3 × 5 mm), Арк. (15 mm), Аркушів
  (20 mm) over their values (5 + 5 mm), and the organisation (50 × 15 mm);
* form 2а (185 × 15 mm) on every following sheet: the same five columns in three rows of 5 mm,
  the designation (110 × 15 mm) and the sheet number (10 mm: "Арк." in 7 mm over the number in 8 mm).

Source: the drawings of forms 2 and 2а in ГОСТ 2.104-68, kept by ГОСТ 2.104-2006 and its Ukrainian
adoption ДСТУ ГОСТ 2.104:2006; the sizes are written down from memory of those drawings, not
checked against a printed copy here. Lines after ГОСТ 2.303 (outlines and column lines thick, the
rows thin).

Here the note's first sheet is the abstract (реферат), the first sheet after the title page and
the assignment, which have no frame (ДСТУ 3008:2015 puts the abstract before the contents; its
sheet is then the first of the note). The sheets are counted from the title page, as the page
numbers of the unframed note are (ДСТУ 3008:2015: the title page is counted, not numbered).

The frame is drawn with the page (templates/frame-eskd.css, a background of each page kind);
the blocks are running elements (templates/frame-eskd.html.j2) in a page-margin box, where
WeasyPrint fills ``counter(page)`` and ``counter(pages)`` with the sheet's number and the total.
On a landscape page (a wide table) the sheet is the same portrait sheet turned clockwise, as a
reader turns the bound note to read it: the binding edge is at the top, the block along the left.
The Word export has no frame (report/docx.py leaves the blocks out).
"""

from __future__ import annotations

from dataclasses import dataclass

from markupsafe import Markup

#: The font sizes a cell's text may take, largest first (pt).
_SIZES = (16.0, 14.0, 12.0, 11.0, 10.0, 9.0, 8.0, 7.5, 7.0, 6.5, 6.0, 5.5)
_PT = 25.4 / 72  # mm per point
#: Line height of the cells' text, in ems (templates/frame-eskd.css).
_LEADING = 1.15


def text_width_em(text: str) -> float:
    """Width of ``text`` in Liberation Serif (Times metrics), in ems: the font's mean advances of
    upper-case letters (0,69 Cyrillic, 0,67 Latin), lower-case (0,51; 0,46), digits (0,5), the
    space and . , : ; (0,25) and other punctuation (0,41), measured from its hmtx table. An estimate to choose a
    cell's size by, a few per cent on the generous side."""
    width = 0.0
    for c in text:
        width += (
            0.25
            if c.isspace() or c in ".,:;"
            else 0.69
            if c.isupper()
            else 0.51
            if c.isalpha() or c.isdigit()
            else 0.41
        )
    return width


def _lines_needed(text: str, width_em: float) -> int:
    """Lines of ``text`` set in a column ``width_em`` wide, breaking at spaces (each ``\\n`` starts a line)."""
    lines = 0
    for paragraph in text.split("\n"):
        lines += 1
        used = 0.0
        for word in paragraph.split():
            w = text_width_em(word)
            if used and used + 0.25 + w > width_em:
                lines, used = lines + 1, w
            else:
                used += (0.25 if used else 0.0) + w
    return lines


def fitting_size(
    text: str, width_mm: float, height_mm: float, largest: float = 14.0, lines: int = 0
) -> float:
    """The largest font size (pt, at most ``largest``) at which ``text`` fits a cell of
    ``width_mm`` × ``height_mm`` (each ``\\n`` starts a line; with ``lines`` = 1 it must stay on
    one line, a word wider than the cell never does)."""
    for size in (s for s in _SIZES if s <= largest):
        em = size * _PT
        needed = _lines_needed(text, width_mm / em)
        widest = max((text_width_em(word) for word in text.split()), default=0.0)
        if (
            widest * em > width_mm
            or (lines and needed > lines)
            or needed * em * _LEADING > height_mm
        ):
            continue
        return size
    return _SIZES[-1]


@dataclass(frozen=True)
class Cell:
    """A text of the title block and the size it is set in."""

    text: str
    size: float

    @property
    def style(self) -> Markup:
        return Markup(f"font-size: {self.size:g}pt")


def person_in_block(name: str) -> str:
    """A name as the title block writes it, surname and initials: the academic title a title page
    gives before it ("доц.", "проф.", "ст. викл.": words in small letters ending in a full stop)
    left out ("доц. Петренко В. М." → "Петренко В. М."), and a name given in full, surname first,
    cut to its initials ("Коваленко Марія Андріївна" → "Коваленко М. А.": the block's column is
    the surname's, ГОСТ 2.104). A name with an initial or a full stop is written as given."""
    words = name.split()
    while len(words) > 1 and words[0][:1].islower() and words[0].endswith((".", ",")):
        words.pop(0)
    if len(words) in (2, 3) and all(_full_name_word(word) for word in words):
        words = [words[0], *(_initials(word) for word in words[1:])]
    return " ".join(words)


def _full_name_word(word: str) -> bool:
    """A capitalised word of letters (an apostrophe or a hyphen inside: Дем'ян, Анна-Марія)."""
    letters = word.replace("-", "").replace("'", "").replace("\u2019", "").replace("\u02bc", "")
    return len(letters) > 1 and word[:1].isupper() and letters.isalpha()


def _initials(word: str) -> str:
    """ "Марія" → "М.", "Анна-Марія" → "А.-М."."""
    return "-".join(part[:1] + "." for part in word.split("-") if part)


def title_block(t, meta, title: str) -> dict:
    """What the blocks hold: the designation, the names of the author, the supervisor, the
    standards controller and the approver, the letter (Літ., a character a cell), the document's
    name (the report's title and "Пояснювальна записка") and the organisation (university,
    department, group), each in the largest size that fits its cell."""
    organisation = "\n".join(
        part
        for part in (
            meta.university,
            meta.department,
            t("frame.group", group=meta.group) if meta.group else "",
        )
        if part
    )
    name = f"{title}\n{t('doc.explanatory_note')}"
    people = {
        role: person_in_block(getattr(meta, role))
        for role in ("student", "supervisor", "standards_controller", "approver")
    }
    # the column's names in one size (a longer name set smaller than the one above it looked odd)
    names = min(fitting_size(person, 21, 4.5, 8.0, lines=1) for person in people.values())
    return {
        "designation": Cell(meta.designation, fitting_size(meta.designation, 116, 13)),
        "designation_small": Cell(meta.designation, fitting_size(meta.designation, 106, 13)),
        **{role: Cell(person, names) for role, person in people.items()},
        "letter": [Cell(character.strip(), 8.0) for character in meta.letter.ljust(3)],
        "name": Cell(name, fitting_size(name, 66, 23, 12.0)),
        "organisation": Cell(organisation, fitting_size(organisation, 48, 13.5, 9.0)),
    }


def frame_html(env, t, meta, title: str) -> Markup:
    """The running title blocks of the framed note (nothing without a frame), put at the start of
    the body: form 2 for the first sheet, form 2а for the others, form 2а turned for landscape pages."""
    if meta.frame != "eskd":
        return Markup("")
    return Markup(
        env.get_template("frame-eskd.html.j2").render(_=t, block=title_block(t, meta, title))
    )
