"""Parsed catalogs are kept per version of the file (crankdyn.report.i18n.load_catalog_file):
an edited catalog is read again, an unchanged one is not."""

from __future__ import annotations

import os

from crankdyn.report.i18n import _parsed_catalog, load_catalog_file


def test_an_edited_catalog_is_read_again_and_an_unchanged_one_is_not(tmp_path):
    path = tmp_path / "uk.toml"
    path.write_text('[demo]\ntitle = "Перший"\n', encoding="utf-8")
    assert load_catalog_file(path) == {"demo.title": "Перший"}
    before = _parsed_catalog.cache_info()
    assert load_catalog_file(path) == {"demo.title": "Перший"}
    assert _parsed_catalog.cache_info().hits == before.hits + 1
    path.write_text('[demo]\ntitle = "Другий, довший"\n', encoding="utf-8")
    stat = path.stat()
    os.utime(
        path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000)
    )  # a new version even on a coarse clock
    assert load_catalog_file(path) == {"demo.title": "Другий, довший"}


def test_a_caller_changing_its_copy_does_not_change_the_kept_texts(tmp_path):
    path = tmp_path / "en.toml"
    path.write_text('[demo]\ntitle = "First"\n', encoding="utf-8")
    load_catalog_file(path)["demo.title"] = "changed"
    assert load_catalog_file(path) == {"demo.title": "First"}
