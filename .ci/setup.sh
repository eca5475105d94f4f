#!/usr/bin/env bash
# Sets up crankdyn on a Debian-based machine, in the active Python environment (a virtual
# environment is best: `python3 -m venv .venv && . .venv/bin/activate`).
#
#   bash .ci/setup.sh          what a report needs: the system libraries WeasyPrint renders PDF
#                              with, serif fonts with Cyrillic (Liberation = Times metrics), and
#                              crankdyn with its runtime dependencies (requirements/runtime-lock.txt)
#   bash .ci/setup.sh --dev    also what the tests need: poppler-utils (PDF pages to PNG), pandoc
#                              (the Word export), LibreOffice Writer (the slow test opens the .docx),
#                              Debian's chromium (the live-preview test drives it headless), and
#                              crankdyn editable with the test extra (requirements/lock.txt)
#
# System packages already installed are not installed again, so without root the script works
# wherever they are present; a missing one is installed with sudo, or named for the administrator.
set -euo pipefail
cd "$(dirname "$0")/.."

DEV=0
case "${1:-}" in
  "") ;;
  --dev) DEV=1 ;;
  -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  *) echo "crankdyn setup: unknown option '$1' (allowed: --dev)" >&2; exit 2 ;;
esac

say() { echo "crankdyn setup: $*"; }

RUNTIME_PACKAGES="libpango-1.0-0 libpangoft2-1.0-0 libharfbuzz-subset0 fonts-liberation fonts-dejavu-core"
DEV_PACKAGES="poppler-utils chromium pandoc"

# Installs the Debian packages of "$@" that are missing; "$APT_OPTIONS" are extra apt-get options.
install_system_packages() {
  local missing="" pkg
  for pkg in "$@"; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing="$missing $pkg"
  done
  if [ -z "$missing" ]; then
    say "system packages present: $*"
    return 0
  fi
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null 2>&1; then
      say "missing system packages:$missing" >&2
      say "ask an administrator to run: apt-get install${APT_OPTIONS:+ $APT_OPTIONS}$missing" >&2
      exit 1
    fi
    sudo="sudo"
  fi
  say "installing system packages:$missing"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update
  # shellcheck disable=SC2086
  $sudo apt-get install -y ${APT_OPTIONS:-} $missing
}

if command -v apt-get >/dev/null 2>&1 && command -v dpkg >/dev/null 2>&1; then
  install_system_packages $RUNTIME_PACKAGES
  if [ "$DEV" -eq 1 ]; then
    install_system_packages $DEV_PACKAGES
    # LibreOffice Writer and Math (without Math a document's equations are not drawn), without
    # their recommended extras (Java, the GUI's help): the Word export lays its pages out with it,
    # the slow tests convert report.docx to PDF with it.
    APT_OPTIONS="--no-install-recommends" install_system_packages libreoffice-writer libreoffice-math
  fi
else
  say "not a Debian-based system: install Pango (with pangoft2) and HarfBuzz, and serif fonts with"
  say "Cyrillic, with the system's package manager (see WeasyPrint's installation notes)"
fi

# The exact, hash-checked versions from a lock, then crankdyn itself against them: no dependency is
# resolved afresh, so every machine gets the same stack (docs/development.md: refreshing the locks).
PIP="python3 -m pip --disable-pip-version-check"
if [ "$DEV" -eq 1 ]; then
  say "installing the runtime and test dependencies of requirements/lock.txt"
  $PIP install --require-hashes -r requirements/lock.txt
  # Editable: the tests read the source tree, including the data kept out of the wheel.
  say "installing crankdyn (editable, from $(pwd))"
  $PIP install --no-deps --no-build-isolation --editable .
  $PIP check
else
  say "installing the runtime dependencies of requirements/runtime-lock.txt"
  $PIP install --require-hashes -r requirements/runtime-lock.txt
  say "installing crankdyn from $(pwd)"
  $PIP install --no-deps .
fi
say "done: $(python3 -m crankdyn --version 2>/dev/null || echo 'crankdyn installed')"
