"""Where a displayed formula (an equation, a worked line) may break, and how it is carried over.

A formula is kept whole where it can be; a long one breaks only after an equals sign or before a
plus or minus outside parentheses and elements, into lines of at most :data:`LINE_CHARS` printed
characters, the sign repeated at the start of the next line (DSTU 3008:2015, 6.7).
"""

from __future__ import annotations

import re

#: Where a displayed equation may break: between its formulas (", &nbsp;"), and in a long formula
#: after an equals sign; never inside a fraction or between a quantity and its value (the PDF
#: broke "ΔL/ | (J ω²)" and "M_c = | 108,3 N·m" at the line's end).
_FORMULA_SEPARATOR = ", &nbsp;"
_LONG_FORMULA_CHARS = 60


def unbroken_parts(formula_html: str, line_chars: int | None = None) -> str:
    """``formula_html`` with each part that must not break in a ``<span class="eq-part">``
    (``white-space: nowrap``), the breaks allowed only between the parts.

    A long formula breaks after an equals sign and, in a long side, before a plus or minus that
    stands outside parentheses (the sign then opens the next line); a short left-hand side
    ("p′ᵢ =") stays with what follows it rather than on a line of its own. ``line_chars``: the
    printed characters of a line (default :data:`LINE_CHARS`, an equation's, beside its number)."""
    parts = []
    for formula in formula_html.split(_FORMULA_SEPARATOR):
        formula = formula.strip()
        pieces = [formula]
        if _visible_length(formula) > _LONG_FORMULA_CHARS and " = " in formula:
            chunks = _outside(formula, " = ")
            sides = [c + " =" for c in chunks[:-1]] + [chunks[-1]]
            pieces = [sub for side in sides for sub in _at_operators(side)]
            if (
                len(sides) > 1
                and _visible_length(sides[0]) <= _SHORT_SIDE_CHARS
                and _visible_length(pieces[0] + pieces[1]) <= _LONG_FORMULA_CHARS
            ):
                pieces[:2] = [pieces[0] + " " + pieces[1]]
            if len(pieces) > 2 and _printed_length(pieces[-1]) <= _SHORT_SIDE_CHARS:
                pieces[-2:] = [pieces[-2] + " " + pieces[-1]]  # nor a short result ("14,24 м/с")
        if _printed_length(formula) > (line_chars or LINE_CHARS) and len(pieces) > 1:
            parts.append(_broken_lines(pieces, line_chars or LINE_CHARS))
        else:
            parts.append(_joined(pieces))
    return (_FORMULA_SEPARATOR + " ").join(parts)


def _joined(pieces: list[str]) -> str:
    """The pieces of one line, each unbreakable; the line may break before a sign (the page's
    last resort, where the estimate of a line's length was short), never after an equals sign
    (the value stays with its quantity unless :func:`_broken_lines` carries it over)."""
    out = ""
    for k, piece in enumerate(pieces):
        out += (
            "" if k == 0 else "\u00a0" if pieces[k - 1].endswith(" =") else " "
        ) + f'<span class="eq-part">{piece}</span>'
    return out


#: The characters of a formula's line on the page (about 72 at the equations' size in the PDF):
#: a formula longer than that is broken into lines here, where the sign can be repeated.
LINE_CHARS = 66


def _broken_lines(pieces: list[str], line_chars: int) -> str:
    """The pieces of a long formula packed into lines of at most ``line_chars``, the sign
    where a line breaks repeated at the start of the next (DSTU 3008:2015, 6.7: a formula is
    carried over after =, +, − ..., the sign repeated on the next line). The repeated sign is an
    ``eq-carry`` span (the Word export, whose equation wraps by itself, leaves it out)."""
    lines: list[list[str]] = [[]]
    for piece in pieces:
        line = lines[-1]
        if line and _printed_length(" ".join(line + [piece])) > line_chars:
            lines.append([])
        lines[-1].append(piece)
    for before, after in zip(lines, lines[1:], strict=False):
        if after[0][:2] in ("+ ", "− "):  # broken before a sign: it also ends the line above
            before[-1] += f'<span class="eq-carry"> {after[0][0]}</span>'
        elif before[-1].endswith(" ="):  # broken after an equals sign: it also opens the next line
            after[0] = f'<span class="eq-carry">=\u00a0</span>{after[0]}'
    return '<br class="eq-break">'.join(_joined(line) for line in lines)


#: A left-hand side this short ("p′ᵢ =") is not left alone on a line.
_SHORT_SIDE_CHARS = 12


def _visible_length(html: str) -> int:
    return len(re.sub(r"<[^>]+>|&[a-z]+;", "x", html))


def _printed_length(html: str) -> int:
    """The characters ``html`` prints (a tag none, an entity one)."""
    return len(re.sub(r"<[^>]+>", "", re.sub(r"&[a-z]+;", "x", html)))


def _depths(text: str):
    """(index, character, parentheses open, square brackets open, elements open) for each
    character of ``text`` outside its tags."""
    round_depth = square_depth = open_elements = 0
    in_tag = False
    for i, char in enumerate(text):
        if in_tag:
            in_tag = char != ">"
            continue
        if char == "<":
            in_tag = True
            tag = text[i : text.find(">", i) + 1]
            if tag.startswith("</"):
                open_elements -= 1
            elif not tag.endswith("/>") and not re.match(r"<(br|wbr|img)\b", tag):
                open_elements += 1
            continue
        round_depth += (char == "(") - (char == ")")
        square_depth += (char == "[") - (char == "]")
        yield i, char, round_depth, square_depth, open_elements


def _outside(text: str, separator: str) -> list[str]:
    """``text`` split at each ``separator`` that stands outside brackets and elements (a worked
    line's "(x = 1)" in a group span stays whole)."""
    cuts = [
        i
        for i, char, round_depth, square_depth, open_elements in _depths(text)
        if not (round_depth or square_depth or open_elements) and text.startswith(separator, i)
    ]
    chunks, start = [], 0
    for cut in cuts:
        if cut >= start:
            chunks.append(text[start:cut])
            start = cut + len(separator)
    return chunks + [text[start:]]


def _at_operators(side: str) -> list[str]:
    """``side`` (of a long formula) cut before each " + " and " − " outside parentheses (inside
    one square bracket at most: the bracket of a long sum) and outside any element (an exponent's
    "n − 1" stays in its <sup>); a short side is returned whole."""
    if _visible_length(side) <= _LONG_FORMULA_CHARS:
        return [side]
    cuts = [
        i
        for i, char, round_depth, square_depth, open_elements in _depths(side)
        if char == " "
        and side[i + 1 : i + 3] in ("+ ", "− ")
        and round_depth == 0
        and square_depth <= 1
        and not open_elements
        and i
    ]  # not inside <sub>, <sup>, <i> ...
    pieces, start = [], 0
    for cut in cuts:
        pieces.append(side[start:cut])
        start = cut + 1
    return pieces + [side[start:]]
