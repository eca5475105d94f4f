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
"""

from __future__ import annotations

import contextlib
import ctypes.util
import io
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
        return sys.modules["weasyprint"]
    with _lock:
        if sys.platform.startswith("linux") and "weasyprint" not in sys.modules:
            try:
                # WeasyPrint prints its installation advice to stdout when a library is missing:
                # not for this first attempt, which the usual import below follows
                with _direct_library_names_only(), contextlib.redirect_stdout(io.StringIO()):
                    import weasyprint  # lazy: heavy optional import
                return weasyprint
            except OSError:
                _forget_failed_import()
        import weasyprint  # lazy: heavy optional import

        return weasyprint
