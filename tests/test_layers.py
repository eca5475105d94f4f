"""The architecture rules of docs/architecture.md, checked on the source itself.

* the one-way layer contract of ``[tool.importlinter]`` in pyproject.toml (``lint-imports``);
* no function-local import except the documented lazy imports of heavy optional libraries;
* no function over 80 lines in ``src/`` or ``plugins/``.
"""

from __future__ import annotations

import ast
import io
import subprocess
import sys
from contextlib import redirect_stdout
from pathlib import Path

from importlinter.cli import lint_imports

ROOT = Path(__file__).resolve().parents[1]
SOURCES = sorted([*(ROOT / "src").rglob("*.py"), *(ROOT / "plugins").rglob("*.py")])
LAZY_MARK = "lazy: heavy optional import"
MAX_FUNCTION_LINES = 80

# Modules exempt from the function-local-import rule: none. Every function-local import carries the
# lazy mark with its reason (matplotlib, weasyprint, babel, jinja2, pandas, openpyxl, pandoc, pint,
# watchfiles; the command line's per-command computation stack); this set may only stay empty.
LAZY_ENTRY_POINTS: set[str] = set()


def _functions(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]


def _rel(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def test_import_layers_hold(monkeypatch):
    """`lint-imports` with the contracts of pyproject.toml: every layer imports only those below."""
    monkeypatch.chdir(ROOT)
    out = io.StringIO()
    with redirect_stdout(out):
        code = lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True)
    report = out.getvalue()
    assert code == 0, report
    assert "0 broken" in report and "3 kept" in report


def test_the_layer_contract_can_fail(tmp_path, monkeypatch):
    """The same checker refuses a back-import, so the test above can fail: with the hook types
    put above the report, report/i18n's import of plugin.types.Catalog breaks the contract."""
    (tmp_path / "pyproject.toml").write_text(
        '[tool.importlinter]\nroot_packages = ["crankdyn"]\n\n[[tool.importlinter.contracts]]\n'
        'name = "upside down"\ntype = "layers"\nlayers = ["crankdyn.plugin.types", "crankdyn.report"]\n',
        encoding="utf-8",
    )
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with redirect_stdout(out):
        code = lint_imports(config_filename=str(tmp_path / "pyproject.toml"), no_cache=True)
    assert code != 0 and "crankdyn.report.i18n -> crankdyn.plugin.types" in out.getvalue()


def test_function_local_imports_are_documented_lazy_imports():
    unmarked = []
    for path in SOURCES:
        if _rel(path) in LAZY_ENTRY_POINTS:
            continue
        lines = path.read_text(encoding="utf-8").splitlines()
        for function in _functions(path):
            for node in ast.walk(function):
                if not isinstance(node, (ast.Import, ast.ImportFrom)):
                    continue
                if LAZY_MARK not in "\n".join(
                    lines[node.lineno - 1 : node.end_lineno]
                ):  # any line of it
                    unmarked.append(f"{_rel(path)}:{node.lineno} in {function.name}")
    assert not unmarked, "function-local imports without the lazy mark: " + ", ".join(unmarked)


def test_no_function_over_80_lines():
    """No exceptions: long functions are split along their physical and report steps."""
    too_long = []
    for path in SOURCES:
        for function in _functions(path):
            length = function.end_lineno - function.lineno + 1
            if length > MAX_FUNCTION_LINES:
                too_long.append(f"{_rel(path)}:{function.lineno} {function.name} ({length} lines)")
    assert not too_long, "functions too long: " + "; ".join(too_long)


def test_a_json_only_report_imports_no_rendering_library(tmp_path):
    """Start-up: the JSON-only path imports what it uses, nothing of the rendering stack."""
    heavy = [
        "pandas",
        "matplotlib",
        "jinja2",
        "babel",
        "pint",
        "weasyprint",
        "openpyxl",
        "pypandoc",
        "docx",
    ]
    code = (
        "import sys\nfrom crankdyn.cli import main\n"
        f"code = main(['report', {str(ROOT / 'examples' / 'petrol-1cyl.toml')!r}, '-o', {str(tmp_path)!r}, "
        "'--format', 'json', '-q'])\n"
        f"print(sorted(m for m in {heavy!r} if m in sys.modules), code)\n"
        # the same check can fail: a table read builds a DataFrame and so imports pandas (in the
        # same fresh interpreter, after the report's modules were listed)
        "import crankdyn.plugin.types as t; t.Tables(a={'x': [1]})['a']\n"
        f"print(sorted(m for m in {heavy!r} if m in sys.modules))"
    )
    first, then = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.splitlines()
    assert first.split() == ["[]", "0"] and (tmp_path / "results.json").is_file()
    assert "'pandas'" in then


#: Top-level modules outside the layer contract: the package's start, the version, the bundled
#: examples' finder and ``python -m crankdyn``. Every other module sits in a package the contract
#: names, or is a shim of an old path (a star import of the new module, nothing else).
UNLAYERED = {"__init__", "__main__", "version", "bundled"}


def _layered_names() -> set[str]:
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    contract = next(c for c in config["tool"]["importlinter"]["contracts"] if c["type"] == "layers")
    return {
        name.strip() for layer in contract["layers"] for name in layer.replace("|", ":").split(":")
    }


def _is_shim(path: Path) -> bool:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    body = [node for node in tree.body if not isinstance(node, ast.Expr)]  # the docstring aside
    return all(isinstance(node, (ast.Import, ast.ImportFrom, ast.Assign)) for node in body) and any(
        isinstance(node, ast.ImportFrom) and node.names[0].name == "*" for node in body
    )


def test_every_core_module_belongs_to_a_layer():
    """A new module inside a layered package is covered without editing the contract."""
    layered = _layered_names()
    outside = []
    for path in sorted((ROOT / "src" / "crankdyn").rglob("*.py")):
        module = ".".join(
            ("crankdyn", *path.relative_to(ROOT / "src" / "crankdyn").with_suffix("").parts)
        )
        covered = any(module == name or module.startswith(name + ".") for name in layered)
        if not covered and path.stem not in UNLAYERED and not _is_shim(path):
            outside.append(module)
    assert not outside, "modules in no layer of [tool.importlinter]: " + ", ".join(outside)
    assert {"crankdyn.plugin", "crankdyn.scene", "crankdyn.engine"} <= layered  # the check can fail
