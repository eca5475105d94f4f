"""crankdyn.report.catalog_cache: a catalog file's parsed texts kept between runs, used only while
the file is as it was, never when damaged or foreign, and nothing kept where nothing may be."""

from __future__ import annotations

import os
import tomllib

import pytest

from crankdyn.report import catalog_cache, i18n


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(catalog_cache.CACHE_ENV, str(tmp_path / "cache"))
    return tmp_path / "cache"


def _parsed(path):
    """The catalog's texts as a new process reads them (no texts kept in this one)."""
    stat = path.stat()
    return i18n._parsed_catalog.__wrapped__(str(path), stat.st_mtime_ns, stat.st_size)


def test_a_catalog_is_read_back_as_parsed_without_parsing_it_again(cache, monkeypatch):
    path = i18n.core_catalog_dir() / "uk.toml"
    first = _parsed(path)
    assert len(list(cache.glob("catalog-*.json"))) == 1

    def refused(handle):
        raise AssertionError("parsed again")

    monkeypatch.setattr(tomllib, "load", refused)
    assert _parsed(path) == first
    monkeypatch.undo()
    with open(path, "rb") as fh:
        assert first == i18n._flatten(tomllib.load(fh))


def test_a_changed_damaged_or_foreign_catalog_file_is_parsed_again(cache, tmp_path):
    path = tmp_path / "plugin.en.toml"
    path.write_text('[plugin]\ntitle = "First"\n', encoding="utf-8")
    assert _parsed(path) == {"plugin.title": "First"}
    path.write_text('[plugin]\ntitle = "Second text"\n', encoding="utf-8")
    assert _parsed(path) == {"plugin.title": "Second text"}  # its size and time changed
    (kept,) = cache.glob("catalog-*.json")
    kept.write_text('{"format": 1, "source": ', encoding="utf-8")  # damaged
    assert _parsed(path) == {"plugin.title": "Second text"}
    stat = path.stat()
    other = catalog_cache.load(str(tmp_path / "other.toml"), stat.st_mtime_ns, stat.st_size)
    assert other is None  # another file's name: none kept for it


def test_nothing_is_kept_when_off_unwritable_or_not_json(tmp_path, monkeypatch):
    path = tmp_path / "dates.en.toml"
    path.write_text("[plugin]\nwhen = 2026-01-01\n", encoding="utf-8")
    monkeypatch.setenv(catalog_cache.CACHE_ENV, str(tmp_path / "cache"))
    assert "plugin.when" in _parsed(path)
    assert not list((tmp_path / "cache").glob("catalog-*"))  # a date is no JSON value
    monkeypatch.setenv(catalog_cache.CACHE_ENV, "off")
    path.write_text('[plugin]\ntitle = "T"\n', encoding="utf-8")
    assert _parsed(path) == {"plugin.title": "T"} and catalog_cache.cache_dir() is None
    if os.geteuid() != 0:  # root writes anywhere
        locked = tmp_path / "locked"
        locked.mkdir(mode=0o500)
        monkeypatch.setenv(catalog_cache.CACHE_ENV, str(locked / "cache"))
        assert _parsed(path) == {"plugin.title": "T"}
        assert not (locked / "cache").exists()


def test_the_cache_folder_follows_the_users_cache_home(monkeypatch, tmp_path):
    monkeypatch.delenv(catalog_cache.CACHE_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert catalog_cache.cache_dir() == tmp_path / "crankdyn"
    monkeypatch.setenv("XDG_CACHE_HOME", "relative/cache")  # ignored, as XDG says
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert catalog_cache.cache_dir() == tmp_path / "home" / ".cache" / "crankdyn"
    monkeypatch.setenv("HOME", "not-absolute")
    assert catalog_cache.cache_dir() is None  # never a folder made where the command runs
