"""WeasyPrint imported without ctypes' library search for its own libraries (crankdyn.report.weasy),
and imported the usual way where only that search finds them. Each case in a fresh interpreter:
an import happens once per process."""

import subprocess
import sys
import textwrap

import pytest

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the quick import is Linux-only"
)

COUNT_SEARCHES = """
import ctypes.util, sys
searched = []
search = ctypes.util.find_library
def counting(name):
    searched.append(name)
    return search(name)
ctypes.util.find_library = counting
"""

RENDER = """
from crankdyn.report.weasy import load_weasyprint
weasyprint = load_weasyprint()
pdf = weasyprint.HTML(string="<p>crankdyn</p>").write_pdf()
assert pdf.startswith(b"%PDF"), pdf[:20]
assert load_weasyprint() is weasyprint
print("searched:", ",".join(n for n in searched if any(k in n for k in ("pango", "gobject", "harfbuzz", "fontconfig"))))
"""


def run(code: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, timeout=120
    )


def test_weasyprint_loads_without_searching_for_its_libraries():
    done = run(COUNT_SEARCHES + RENDER)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "searched:"  # the usual import asks for a dozen names


def test_the_usual_import_follows_when_only_the_search_finds_a_library():
    # A system where the loader opens pango only by the path ctypes' search gives: the quick
    # attempt fails, its advice to stdout is swallowed, and the usual import succeeds.
    only_by_search = """
    import glob
    import cffi.api
    load = cffi.api._load_backend_lib

    def pango_by_search_only(backend, name, flags):
        if isinstance(name, str) and "pango" in name:
            path = ctypes.util.find_library(name)  # the quick import answers None here
            if path is None:
                raise OSError(f"cannot load {name}")
            return backend.load_library(path, flags)
        return load(backend, name, flags)

    def search_finds_pango(name):
        searched.append(name)
        library = "libpangoft2-1.0.so.0" if "pangoft2" in name else "libpango-1.0.so.0"
        if "pango" in name:
            return (glob.glob(f"/usr/lib/*/{library}") + glob.glob(f"/usr/lib*/{library}"))[0]
        return search(name)

    cffi.api._load_backend_lib = pango_by_search_only
    ctypes.util.find_library = search_finds_pango
    """
    done = run(COUNT_SEARCHES + textwrap.dedent(only_by_search) + RENDER)
    assert done.returncode == 0, done.stderr
    assert "pango" in done.stdout  # found by the search, in the second (usual) import
    assert "could not import some external libraries" not in done.stdout
