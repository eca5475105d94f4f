"""Compiled section templates kept between runs (crankdyn.report.document._bytecode_cache)."""

import os

import jinja2

from crankdyn.report import document


def environment(folder, cache):
    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(folder)),
        bytecode_cache=cache,
        **document.TEMPLATE_OPTIONS,
    )


def test_a_template_compiled_once_is_loaded_from_the_cache_until_its_source_changes(tmp_path):
    (tmp_path / "cache").mkdir()
    cache = document._QuietBytecodeCache(
        str(tmp_path / "cache"), document._bytecode_cache().pattern
    )
    (tmp_path / "section.html.j2").write_text("<p>{{ value }}</p>\n", encoding="utf-8")
    assert (
        environment(tmp_path, cache).get_template("section.html.j2").render(value="<1>")
        == "<p>&lt;1&gt;</p>"
    )
    assert len(os.listdir(tmp_path / "cache")) == 1

    class NoCompiling(jinja2.Environment):
        def compile(self, *args, **kwargs):
            raise AssertionError("compiled again although cached")

    again = NoCompiling(
        loader=jinja2.FileSystemLoader(str(tmp_path)),
        bytecode_cache=cache,
        **document.TEMPLATE_OPTIONS,
    )
    assert again.get_template("section.html.j2").render(value=2) == "<p>2</p>"

    (tmp_path / "section.html.j2").write_text("<div>{{ value }}</div>\n", encoding="utf-8")
    assert (
        environment(tmp_path, cache).get_template("section.html.j2").render(value=3)
        == "<div>3</div>"
    )


def test_the_cache_names_carry_the_version_and_the_compile_options():
    pattern = document._bytecode_cache().pattern
    assert document.__version__ in pattern and pattern.endswith("-%s.cache")


def test_a_cache_that_cannot_be_written_is_no_error(tmp_path):
    (tmp_path / "not-a-folder").write_text("", encoding="utf-8")  # a full or read-only disk alike
    cache = document._QuietBytecodeCache(str(tmp_path / "not-a-folder"))
    (tmp_path / "t.j2").write_text("x", encoding="utf-8")
    assert environment(tmp_path, cache).get_template("t.j2").render() == "x"


def test_a_damaged_cache_file_is_compiled_again(tmp_path):
    (tmp_path / "cache").mkdir()
    cache = document._QuietBytecodeCache(str(tmp_path / "cache"))
    (tmp_path / "t.j2").write_text("{{ 1 + 1 }}", encoding="utf-8")
    assert environment(tmp_path, cache).get_template("t.j2").render() == "2"
    (cached,) = (tmp_path / "cache").iterdir()
    cached.write_bytes(
        cached.read_bytes()[:60]
    )  # cut short inside its checksum (plain jinja2 raises)
    assert environment(tmp_path, cache).get_template("t.j2").render() == "2"
