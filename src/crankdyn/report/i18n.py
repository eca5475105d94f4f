"""Translation catalogs and locale-aware number formatting.

A catalog is a TOML file; nested tables flatten to dotted keys. The core catalogs
live in the package's templates/i18n; plugins add theirs through the
``crankdyn_catalogs`` hook. A language is any code with a core catalog, so a new
report language is a new catalog file, not a code change.
"""

from __future__ import annotations

import functools
import math
import re
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

from ..errors import PluginError
from ..plugin.types import Catalog
from . import catalog_cache

FALLBACK = "en"

#: Between a number and its unit and between digit groups: a narrow no-break space (U+202F),
#: so "7,26 мм" and "17 168" never break across lines.
NARROW_NBSP = "\u202f"
MINUS = "\u2212"

#: ``{n@form|form|…}`` in a catalog text: the word form for the number ``n`` by the CLDR plural
#: rules of the report's language, forms in CLDR order of the categories the language has
#: (uk/ru: one, few, many, other; en: one, other).
_PLURAL = re.compile(r"\{(\w+)@([^{}]*)\}")
#: ``{n#form}`` in a catalog text: the count ``n`` in words where it is one to nine (a count
#: without a unit, as ДСТУ 3008 and ГОСТ 2.105 write it), in the grammatical ``form`` of the
#: language's ``numerals.<form>`` ("m_nom": "шість циліндрів", "n_loc": "на трьох колінах");
#: any other number in digits, as ``{n}``.
_NUMERAL = re.compile(r"\{(\w+)#(\w+)\}")
#: ``{=key}`` in a catalog text: the text of catalog key ``key`` (a term whose wording depends on
#: the engine, through the translator's variants: "схема колін" of an in-line engine, "схема
#: двигуна" where the cylinders lie in several planes).
_TERM = re.compile(r"\{=([\w.]+)\}")
_CATEGORIES = ("zero", "one", "two", "few", "many", "other")

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
    path = Path(path)
    stat = path.stat()
    return dict(_parsed_catalog(str(path.resolve()), stat.st_mtime_ns, stat.st_size))


@functools.lru_cache(maxsize=512)
def _parsed_catalog(path: str, mtime_ns: int, size: int) -> dict[str, str]:
    """A catalog file's texts, parsed once per version of the file (a batch or the preview
    builds a translator per report), and kept between runs (:mod:`.catalog_cache`)."""
    kept = catalog_cache.load(path, mtime_ns, size)
    if kept is not None:
        return kept
    with open(path, "rb") as fh:
        texts = _flatten(tomllib.load(fh))
    catalog_cache.keep(path, mtime_ns, size, texts)
    return texts


@functools.lru_cache(maxsize=64)
def _babel_locale(name: str):
    """The Babel locale called ``name`` (English if Babel does not know it), parsed once: every
    number of a report asks for it."""
    from babel import (  # lazy: heavy optional import (babel: only when a number is formatted for a report)
        Locale,
        UnknownLocaleError,
    )

    try:
        return Locale.parse(name)
    except (UnknownLocaleError, ValueError):
        return Locale.parse(FALLBACK)


#: A V, W or X engine's cylinder label: its number and its bank's letter ("1L", "4R").
_BANKED_LABEL = re.compile(r"(\d+)([A-Z])")


@dataclass
class Translator:
    """Looks texts up in one language, falling back to English; records misses.

    ``variant``: the engine's variants of the texts, in order of preference (``"propeller"`` for
    an aircraft engine, whose propeller takes the flywheel's part; ``"banked"`` where the
    cylinders lie in more than one plane): a key ``<key>_<variant>`` a catalog gives is said
    instead of ``<key>``, the first variant that has one, so that a plugin words its texts for
    such an engine by adding keys, without choosing them in code. A text may name a term,
    ``{=key}``, said in the same way."""

    language: str
    # left out of the repr: an error message naming the translator stays one line
    texts: dict[str, str] = field(repr=False)
    fallback: dict[str, str] = field(repr=False)
    missing: set[str] = field(default_factory=set)
    variant: str | tuple[str, ...] | None = None

    def __call__(self, key: str, **params) -> str:
        if self.variant is not None:
            key = self._variant_key(key)
        text = self.texts.get(key)
        if text is None:
            text = self.fallback.get(key)
            if text is None:
                self.missing.add(key)
                return key
            if self.language != FALLBACK:
                self.missing.add(key)
        if "{=" in text:
            text = _TERM.sub(lambda m: self(m.group(1)), text)  # a term is plain words
        if params and "@" in text:
            text = _PLURAL.sub(lambda m: self.plural_word(params.get(m.group(1)), m.group(2)), text)
        if params and "#" in text:
            text = _NUMERAL.sub(lambda m: self.count_words(params[m.group(1)], m.group(2)), text)
        return text.format(**params) if params else text

    def _variant_key(self, key: str) -> str:
        """``<key>_<variant>`` of the first variant a catalog gives, else ``key``."""
        variants = (self.variant,) if isinstance(self.variant, str) else self.variant or ()
        for variant in variants:
            own = f"{key}_{variant}"
            if own in self.texts or own in self.fallback:
                return own
        return key

    def count_words(self, value, form: str = "m_nom") -> str:
        """``value`` in words where it is a whole number from one to nine, in the grammatical
        ``form`` of this language's ``numerals.<form>`` (nine words, "|"-separated); any other
        value as ``str(value)`` writes it (digits: "12", "2.5")."""
        number = _as_number(value)
        words = self.texts.get(f"numerals.{form}") or self.fallback.get(f"numerals.{form}")
        if words is None or number is None or not math.isfinite(number):
            return str(value)
        if number != int(number) or not 1 <= number <= 9:
            return str(value)
        return words.split("|")[int(number) - 1]

    def cylinder(self, label) -> str:
        """A cylinder's label as printed: its bank letter in this language's letters (``bank.L``:
        "1L" → "1Л" in a Cyrillic text); a label without a bank letter as it is."""
        text = str(label)
        found = _BANKED_LABEL.fullmatch(text)
        if found is None:
            return text
        letter = self.texts.get("bank." + found.group(2)) or found.group(2)
        return found.group(1) + letter

    def cylinders(self, labels, separator: str = "–") -> str:
        """Cylinder labels as printed (:meth:`cylinder`), joined: a firing order "1Л–1П–4Л"."""
        return separator.join(self.cylinder(label) for label in labels)

    def firing_order_cell(self, labels) -> str:
        """A firing order for a table's cell: on one line where it fits, else parted once, after
        its middle dash (not "1Л–1П–3Л–3П–2Л–" over a lone "2П"): a word joiner after every
        other dash keeps the halves whole."""
        printed = [self.cylinder(label) for label in labels]
        middle = (len(printed) + 1) // 2
        glued = "–\u2060"
        if len(printed) <= 4:
            return glued.join(printed)
        return glued.join(printed[:middle]) + "–\u200b" + glued.join(printed[middle:])

    def has(self, key: str) -> bool:
        """True if ``key`` has a text in this language or in English."""
        return key in self.texts or key in self.fallback

    @property
    def decimal_separator(self) -> str:
        return self.texts.get("_meta.decimal_separator", ".")

    @property
    def locale(self):
        """The Babel locale of the report language (English if Babel does not know it)."""
        return _babel_locale(self.texts.get("_meta.locale", self.language))

    def plural_word(self, value, forms: str) -> str:
        """The form in ``forms`` ("one|few|many|other") the CLDR rules choose for ``value``."""
        choices = forms.split("|")
        number = _as_number(value)
        if number is None:
            return choices[-1]
        locale = self.locale
        category = locale.plural_form(abs(number))
        present = [c for c in _CATEGORIES if c in locale.plural_form.tags or c == "other"]
        index = present.index(category) if category in present else len(present) - 1
        return choices[min(index, len(choices) - 1)]

    def join_and(self, items) -> str:
        """``items`` as the report language lists them: "5, 6 і 8" (Babel's CLDR list patterns)."""
        from babel.lists import (
            format_list,  # lazy: heavy optional import (babel: only when a report lists)
        )

        return format_list(list(items), locale=self.locale)

    def degrees_and(self, values, significant: int = 4) -> str:
        """Angles as one list: "450° і 270°"; equal angles once ("180°": every interval is 180°);
        a list that repeats a shorter one, as that one taken in turn ("по черзі 90° і 150°")."""
        texts = [self.number_g(v, significant) + "°" for v in values]
        if not texts:
            return ""
        period = next(
            p
            for p in range(1, len(texts) + 1)
            if len(texts) % p == 0 and texts == texts[:p] * (len(texts) // p)
        )
        if period == 1:
            return texts[0]
        listed = self.join_and(texts[:period])
        return listed if period == len(texts) else self("doc.degrees_in_turn", angles=listed)

    # ----------------------------------------------------------------- numbers
    def number(self, value: float, significant: int = 4) -> str:
        """``value`` to ``significant`` digits, plain notation where sensible."""
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "—"
        value = float(value)
        if value == 0:
            return "0"
        magnitude = math.floor(math.log10(abs(value)))
        # rounding may carry into the next decade (0.0099996 to 4 digits is 0.01000, not 0.010000)
        rounded = float(f"{value:.{significant - 1}e}")
        magnitude = math.floor(math.log10(abs(rounded))) if rounded else magnitude
        if -4 <= magnitude < significant + 2:
            decimals = max(significant - 1 - magnitude, 0)
            return self.fixed(value, decimals)
        mantissa, exponent = f"{value:.{significant - 1}e}".split("e")
        return f"{self.fixed(float(mantissa), significant - 1)}·10{superscript(int(exponent))}"

    def number_g(self, value: float, significant: int = 6) -> str:
        """Like ``%g``: no trailing zeros ("180", "7,5", "3·10⁶"), in the report's locale."""
        text = self.number(value, significant)
        mantissa, times, power = text.partition("·")
        separator = self.decimal_separator_babel
        if separator in mantissa:
            mantissa = mantissa.rstrip("0").rstrip(separator)
        return mantissa + times + power

    def angle(self, angle_deg: float, step_deg: float | None = None) -> str:
        """A crank angle as printed: whole degrees as they are; an angle between whole degrees with
        one decimal per decade the computation step ``step_deg`` is finer than 1 deg (at least one),
        since the step is the resolution an angle read off the grid has."""
        angle_deg = float(angle_deg)
        if abs(angle_deg - round(angle_deg)) < 1e-9:
            return self.number_g(float(round(angle_deg)), 6)
        decimals = max(1, math.ceil(-math.log10(step_deg) - 1e-9)) if step_deg else 1
        return self.number_g(round(angle_deg, decimals), 6)

    @property
    def decimal_separator_babel(self) -> str:
        from babel.numbers import (
            get_decimal_symbol,  # lazy: heavy optional import (babel: only when a number is formatted for a report)
        )

        return get_decimal_symbol(self.locale)

    def fixed(self, value: float, decimals: int) -> str:
        """``value`` with ``decimals`` decimals in the report's locale (Babel): decimal comma in
        uk/ru, "−" for minus, digit groups of five-digit and longer numbers by a narrow no-break space."""
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "—"
        rounded = float(f"{float(value):.{decimals}f}")  # the digits printf would show
        if rounded == 0:
            rounded = 0.0  # no "−0,000"
        return _format_fixed(rounded, decimals, self.locale)


@functools.lru_cache(maxsize=16384)
def _format_fixed(rounded: float, decimals: int, locale) -> str:
    """The text of an already rounded number in ``locale`` (a babel Locale), as Babel's
    ``format_decimal`` writes it with the pattern "0.00" (below 10 000) or "#,##0.00": the
    locale's decimal symbol, groups of three digits (the grouping of every language a report is
    written in) by a narrow no-break space, "−" for minus. Written with the locale's symbols
    rather than by Babel, which takes some 0.05 ms a number; kept, since tick labels and table
    cells repeat."""
    decimal, _group = _number_symbols(locale)
    digits = f"{abs(rounded):{',' if abs(rounded) >= 10000 else ''}.{decimals}f}"
    text = digits.replace(",", NARROW_NBSP).replace(".", decimal)
    return MINUS + text if rounded < 0 else text


@functools.lru_cache(maxsize=16)
def _number_symbols(locale) -> tuple[str, str]:
    """(decimal symbol, group symbol) of ``locale`` (CLDR, by Babel)."""
    from babel.numbers import (  # lazy: heavy optional import (babel: only when a number is formatted for a report)
        get_decimal_symbol,
        get_group_symbol,
    )

    return get_decimal_symbol(locale), get_group_symbol(locale)


def _as_number(value) -> float | None:
    """A number from a value or its formatted text ("17 168,5", "−4")."""
    if isinstance(value, (int, float)):
        return float(value)
    if isinstance(value, str):
        text = value.replace(NARROW_NBSP, "").replace("\u00a0", "").replace(" ", "")
        text = text.replace(MINUS, "-").replace(",", ".")
        try:
            return float(text)
        except ValueError:
            return None
    return None


def translator(
    language: str,
    plugin_catalogs: Iterable[Catalog] = (),
    variant: str | tuple[str, ...] | None = None,
) -> Translator:
    """Build the translator for ``language`` from core and plugin catalogs (``variant``: see
    :class:`Translator`)."""
    core_dir = core_catalog_dir()
    per_language: dict[str, dict[str, str]] = {}
    origin: dict[tuple[str, str], str] = {}
    sources = [(p.stem, p) for p in sorted(core_dir.glob("*.toml"))]
    sources += [(c.language, Path(c.path)) for c in plugin_catalogs]
    for lang, path in sources:
        if lang not in (language, FALLBACK):
            continue  # another language's catalogs are read when a report in it is built
        texts = per_language.setdefault(lang, {})
        for key, text in load_catalog_file(path).items():
            if key in texts and not key.startswith("_meta."):
                raise PluginError(
                    f"translation key {key!r} ({lang}) defined twice: in {origin[(lang, key)]} and {path}"
                )
            texts[key] = text
            origin[(lang, key)] = str(path)
    return Translator(
        language, per_language.get(language, {}), per_language.get(FALLBACK, {}), variant=variant
    )
