"""Translation catalogs and locale-aware number formatting.

A catalog is a TOML file; nested tables flatten to dotted keys. The core catalogs
live in the package's templates/i18n; plugins add theirs through the
``crankdyn_catalogs`` hook. A language is any code with a core catalog, so a new
report language is a new catalog file, not a code change.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Iterable

from ..errors import PluginError
from ..plugin_types import Catalog

FALLBACK = "en"

_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def superscript(exponent: int) -> str:
    """``-16`` as ``⁻¹⁶``: a power of ten a reader sees typeset, never ``^-16``."""
    return str(int(exponent)).translate(_SUPERSCRIPT)


def core_catalog_dir() -> Path:
    return Path(str(resources.files("crankdyn.templates"))) / "i18n"


def available_languages() -> list[str]:
    return sorted(p.stem for p in core_catalog_dir().glob("*.toml"))


def _flatten(table: dict, prefix: str = "") -> dict[str, str]:
    out: dict[str, str] = {}
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(_flatten(value, name + "."))
        else:
            out[name] = value
    return out


def load_catalog_file(path: Path) -> dict[str, str]:
    with open(path, "rb") as fh:
        return _flatten(tomllib.load(fh))


@dataclass
class Translator:
    """Looks texts up in one language, falling back to English; records misses."""

    language: str
    texts: dict[str, str]
    fallback: dict[str, str]
    missing: set[str] = field(default_factory=set)

    def __call__(self, key: str, **params) -> str:
        text = self.texts.get(key)
        if text is None:
            text = self.fallback.get(key)
            if text is None:
                self.missing.add(key)
                return key
            if self.language != FALLBACK:
                self.missing.add(key)
        return text.format(**params) if params else text

    @property
    def decimal_separator(self) -> str:
        return self.texts.get("_meta.decimal_separator", ".")

    # ----------------------------------------------------------------- numbers
    def number(self, value: float, significant: int = 4) -> str:
        """``value`` to ``significant`` digits, plain notation where sensible."""
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "—"
        value = float(value)
        if value == 0:
            return "0"
        magnitude = math.floor(math.log10(abs(value)))
        if -4 <= magnitude < significant + 2:
            decimals = max(significant - 1 - magnitude, 0)
            text = f"{value:.{decimals}f}"
        else:
            text = f"{value:.{significant - 1}e}"
            mantissa, exponent = text.split("e")
            return f"{self._localise(mantissa)}·10{superscript(int(exponent))}"
        return self._localise(text)

    def fixed(self, value: float, decimals: int) -> str:
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "—"
        text = f"{float(value):.{decimals}f}"
        if text.lstrip("-").strip("0.") == "":
            text = text.lstrip("-")  # no "-0.000"
        return self._localise(text)

    def _localise(self, text: str) -> str:
        text = text.replace("-", "−")
        if self.decimal_separator != ".":
            text = text.replace(".", self.decimal_separator)
        return text


def translator(language: str, plugin_catalogs: Iterable[Catalog] = ()) -> Translator:
    """Build the translator for ``language`` from core and plugin catalogs."""
    core_dir = core_catalog_dir()
    per_language: dict[str, dict[str, str]] = {}
    origin: dict[tuple[str, str], str] = {}
    sources = [(p.stem, p) for p in sorted(core_dir.glob("*.toml"))]
    sources += [(c.language, Path(c.path)) for c in plugin_catalogs]
    for lang, path in sources:
        texts = per_language.setdefault(lang, {})
        for key, text in load_catalog_file(path).items():
            if key in texts and not key.startswith("_meta."):
                raise PluginError(f"translation key {key!r} ({lang}) defined twice: in {origin[(lang, key)]} and {path}")
            texts[key] = text
            origin[(lang, key)] = str(path)
    return Translator(language, per_language.get(language, {}), per_language.get(FALLBACK, {}))
