#!/usr/bin/env bash
# Installs what crankdyn needs on a fresh Debian-based machine: the system libraries
# WeasyPrint renders with, serif fonts with Cyrillic (Liberation = Times metrics),
# poppler-utils (the tests turn PDF pages into PNG), pandoc (the Word export), LibreOffice Writer (the slow test opens the .docx), Debian's chromium (the live-preview test
# drives it headless), then the package with its test extras.
set -euo pipefail
cd "$(dirname "$0")/.."

SYSTEM_PACKAGES="libpango-1.0-0 libpangoft2-1.0-0 libharfbuzz-subset0 fonts-liberation fonts-dejavu-core poppler-utils chromium pandoc"
if command -v apt-get >/dev/null 2>&1 && command -v dpkg >/dev/null 2>&1; then
  missing=""
  for pkg in $SYSTEM_PACKAGES; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing="$missing $pkg"
  done
  if [ -n "$missing" ]; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    # shellcheck disable=SC2086
    $SUDO apt-get install -y -qq $missing >/dev/null
  fi
  # LibreOffice Writer and Math (without Math a document's equations are not drawn), without their
  # recommended extras (Java, the GUI's help): the Word export lays its pages out with it, the slow
  # test converts report.docx to PDF with it.
  if ! command -v soffice >/dev/null 2>&1 || ! dpkg -s libreoffice-math >/dev/null 2>&1; then
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq --no-install-recommends libreoffice-writer libreoffice-math >/dev/null
  fi
fi

# The exact, hash-checked versions from the lock (runtime and test extras, setuptools included),
# then crankdyn itself against them: no dependency is resolved afresh, so every machine gets the
# same stack. Refresh the lock as the README's "Testing" section says.
PIP="python3 -m pip --disable-pip-version-check"
$PIP install --quiet --require-hashes -r requirements/lock.txt
$PIP install --quiet --no-deps --no-build-isolation .
$PIP check
