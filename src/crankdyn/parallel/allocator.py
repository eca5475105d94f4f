"""The C allocator while a chunk of a sweep computes in a process told to give memory back at once.

A Dask worker is started with ``MALLOC_TRIM_THRESHOLD_=65536`` (``distributed.nanny``'s
``pre-spawn-environ``), so that the memory it frees shows in its reported size. glibc then stops
adapting its mmap threshold: every array above 128 KiB is mapped afresh and unmapped on free, and a
chunk's arrays (points x crank angles, about a megabyte each) fault in their pages again and again,
about a quarter more CPU time per point than in a local worker. While a chunk computes,
:func:`chunk_arrays_reused` raises the thresholds so that freed arrays are reused, and sets back
the ones the environment gave (glibc's default mmap threshold where it gave none) afterwards: the
worker is left as it was configured. Nothing happens where the variable is not set or the C
library has no ``mallopt`` (not glibc).
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import os
from collections.abc import Iterator

#: glibc's ``mallopt`` parameters (malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
#: glibc's mmap threshold when the environment does not set one (malloc.h: 128 KiB).
GLIBC_MMAP_THRESHOLD = 128 * 1024
#: Arrays up to this size come from the heap while a chunk computes; the heap keeps twice as much
#: free memory before it is trimmed. A chunk's arrays are bounded by its points.
CHUNK_MMAP_THRESHOLD = 64 * 1024 * 1024


def _mallopt():
    name = ctypes.util.find_library("c")
    if name is None:
        return None
    try:
        return ctypes.CDLL(name).mallopt
    except (OSError, AttributeError):
        return None


def _environment_value(name: str) -> int | None:
    value = os.environ.get(name, "").strip()
    return int(value) if value.isdigit() else None


@contextlib.contextmanager
def chunk_arrays_reused() -> Iterator[bool]:
    """Inside, freed arrays are reused (yields whether the thresholds were changed): only in a
    process whose environment sets ``MALLOC_TRIM_THRESHOLD_``, with glibc."""
    trim = _environment_value("MALLOC_TRIM_THRESHOLD_")
    mallopt = _mallopt() if trim is not None else None
    if mallopt is None or trim is None:
        yield False
        return
    mmap = _environment_value("MALLOC_MMAP_THRESHOLD_") or GLIBC_MMAP_THRESHOLD
    changed = bool(mallopt(M_MMAP_THRESHOLD, CHUNK_MMAP_THRESHOLD)) and bool(
        mallopt(M_TRIM_THRESHOLD, 2 * CHUNK_MMAP_THRESHOLD)
    )
    try:
        yield changed
    finally:
        mallopt(M_MMAP_THRESHOLD, mmap)
        mallopt(M_TRIM_THRESHOLD, trim)
