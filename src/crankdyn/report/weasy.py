"""WeasyPrint, imported without its library search starting compilers (Linux).

WeasyPrint loads pango, gobject, harfbuzz and fontconfig through cffi, trying several names for
each (``libpango-1.0-0``, ``pango-1.0-0``, ``pango-1.0``, ``libpango-1.0.so.0``, ...). On Linux
every name before the last is not a file the dynamic loader finds, and cffi then asks
``ctypes.util.find_library``, which runs ``ldconfig -p``, ``gcc`` and ``ld`` in turn for it: some
fifty short processes, about 0.18 s of every start-up that makes a PDF (measured with
``python -X importtime -c "import weasyprint"``: 0.6 s, of which ``weasyprint.text.ffi`` 0.24 s).
The names that do load (``libpango-1.0.so.0``) are opened by the loader directly, without
``find_library``; so while WeasyPrint is imported, ``find_library`` answers "not found" for
those libraries at once. Should that leave WeasyPrint without a library (a system where only
the search finds them), the import is simply done again the usual way.

Once imported, WeasyPrint's font subsetting asks cffi for arrays typed by their length
(``ffi.new(f"hb_codepoint_t[{n}]", items)``): cffi parses every C type string it has not seen
with pycparser, 6 ms each, and a PDF's fonts need a new length each (50 ms a PDF written). Those
arrays are made as ``T[]`` of their items instead (:class:`_ArraysOfTheirItems`), the same array.
"""

from __future__ import annotations

import contextlib
import ctypes.util
import importlib
import io
import re
import sys
import threading
from types import ModuleType

#: The libraries WeasyPrint opens by name (weasyprint/text/ffi.py); no other lookup is touched.
WEASYPRINT_LIBRARIES = ("gobject", "pango", "harfbuzz", "fontconfig")

_lock = threading.Lock()


@contextlib.contextmanager
def _direct_library_names_only():
    search = ctypes.util.find_library

    def find_library(name: str):
        if any(library in name for library in WEASYPRINT_LIBRARIES):
            return None  # the loader opens the name that exists (libpango-1.0.so.0) itself
        return search(name)

    ctypes.util.find_library = find_library
    try:
        yield
    finally:
        ctypes.util.find_library = search


def _forget_failed_import() -> None:
    for name in [m for m in sys.modules if m == "weasyprint" or m.startswith("weasyprint.")]:
        del sys.modules[name]


def load_weasyprint() -> ModuleType:
    """The ``weasyprint`` module, imported once per process (see the module's docstring)."""
    if "weasyprint" in sys.modules:
        _subset_arrays_of_their_items()  # imported elsewhere first, perhaps
        return sys.modules["weasyprint"]
    with _lock:
        if sys.platform.startswith("linux") and "weasyprint" not in sys.modules:
            try:
                # WeasyPrint prints its installation advice to stdout when a library is missing:
                # not for this first attempt, which the usual import below follows
                with _direct_library_names_only(), contextlib.redirect_stdout(io.StringIO()):
                    import weasyprint  # lazy: heavy optional import
                _subset_arrays_of_their_items()
                return weasyprint
            except OSError:
                _forget_failed_import()
        import weasyprint  # lazy: heavy optional import

        _subset_arrays_of_their_items()
        return weasyprint


#: A C array type of a given length, as cffi reads it: ``hb_codepoint_t[12]``.
_SIZED_ARRAY = re.compile(r"(\w+)\[(\d+)\]")


class _ArraysOfTheirItems:
    """cffi's ``ffi`` whose ``new("T[n]", items)`` with n items is ``new("T[]", items)``: the same
    array, from a type string cffi parsed once (everything else is the ``ffi``'s own)."""

    def __init__(self, ffi) -> None:
        self._ffi = ffi

    def new(self, cdecl, init=None):
        sized = _SIZED_ARRAY.fullmatch(cdecl) if isinstance(cdecl, str) else None
        items = isinstance(init, (list, tuple, bytes))  # an array's own items, countable
        if sized is not None and items and len(init) == int(sized.group(2)):
            cdecl = sized.group(1) + "[]"
        return self._ffi.new(cdecl, init)

    def __getattr__(self, name: str):
        return getattr(self._ffi, name)


def _subset_arrays_of_their_items() -> None:
    """WeasyPrint's font subsetting given :class:`_ArraysOfTheirItems` (see the module's
    docstring); a WeasyPrint without that module is left as it is."""
    try:
        fonts = importlib.import_module("weasyprint.pdf.fonts")
    except ImportError:  # another WeasyPrint's layout of its modules
        return
    ffi = getattr(fonts, "ffi", None)
    if ffi is not None and not isinstance(ffi, _ArraysOfTheirItems):
        setattr(fonts, "ffi", _ArraysOfTheirItems(ffi))  # noqa: B010 - a module found by name
