"""The bundled example scenes, found where the package is installed (a wheel or a source tree)."""

from __future__ import annotations

from pathlib import Path


def examples_folder() -> Path:
    """The folder of the bundled example scenes (``crankdyn example --list`` names them)."""
    from importlib import resources  # lazy: heavy optional import (import crankdyn stays light)

    return Path(str(resources.files("crankdyn.examples")))


def example_names() -> list[str]:
    """The names of the bundled example scenes, sorted (``petrol-1cyl``, ...)."""
    return sorted(path.stem for path in examples_folder().glob("*.toml"))


def example_path(name: str) -> Path:
    """The path of the bundled example scene ``name`` (``"petrol-1cyl"``; ``".toml"`` may be
    given), so that ``crankdyn.load(crankdyn.example_path("petrol-1cyl"))`` works from any folder.

    An unknown name raises :class:`ValueError` naming the value and the available examples.
    """
    if not isinstance(name, str):
        raise ValueError(f"example name must be a text such as 'petrol-1cyl', not {name!r}")
    stem = name[: -len(".toml")] if name.endswith(".toml") else name
    path = examples_folder() / f"{stem}.toml"
    if "/" in stem or "\\" in stem or not path.is_file():
        raise ValueError(f"unknown example {name!r}; available: " + ", ".join(example_names()))
    return path
