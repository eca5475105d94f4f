"""The document's text-node passes applied section by section (report.document.by_sections)."""

from crankdyn.report import document
from crankdyn.report.typeset import typeset_html, unbreakable_html

UNITS = ("мм", "Н", "кг")

DOCUMENT = """<html><head><title>p_z = 5 МПа</title><style>p { x: 1 }</style></head><body>
<section class="title-page"><p>Сила 12 Н, m_п = 0.5 кг</p></section>
<section class="chapter" data-stage="forces"><p>p_z = 6 МПа; v = 3 м/с</p>
<script>var a = "x = 1";
<section class="fake">inside a script: not a place to split</script></section>
<section class="chapter" data-stage="torque"><p>M = 108 Н·м, -5 мм</p></section>
</body></html>"""


def test_section_by_section_equals_the_whole_document_pass():
    for transform, whole, args in (
        (document._typeset_part, typeset_html, ("uk", UNITS, ",")),
        (document._unbreakable_part, unbreakable_html, ()),
    ):
        expected = whole(DOCUMENT, *((args[0], list(args[1]), args[2]) if args else ()))
        assert document.by_sections(transform, DOCUMENT, *args) == expected
        # split where no script is open: the same text as the whole pass
        plain = DOCUMENT.replace(
            '<script>var a = "x = 1";\n<section class="fake">inside a script: not a place to '
            "split</script>",
            "",
        )
        expected = whole(plain, *((args[0], list(args[1]), args[2]) if args else ()))
        assert document.by_sections(transform, plain, *args) == expected


def test_a_document_with_a_section_start_inside_a_script_is_not_split():
    parts = document._SECTION_START.split(DOCUMENT)
    assert len(parts) == 5 and not all(document._balanced(p) for p in parts)
    calls = []

    def transform(html):
        calls.append(html)
        return html

    assert document.by_sections(transform, DOCUMENT) == DOCUMENT and calls == [DOCUMENT]


def test_sections_met_before_are_taken_from_the_cache():
    plain = DOCUMENT.replace(
        '<script>var a = "x = 1";\n<section class="fake">inside a script: not a place to split'
        "</script>",
        "",
    )
    document._typeset_part.cache_clear()
    document.by_sections(document._typeset_part, plain, "uk", UNITS, ",")
    first = document._typeset_part.cache_info()
    assert first.hits == 0 and first.misses == 4  # the head and three sections
    changed = plain.replace("M = 108", "M = 109")  # one section changed
    document.by_sections(document._typeset_part, changed, "uk", UNITS, ",")
    second = document._typeset_part.cache_info()
    assert second.hits == 3 and second.misses == 5
