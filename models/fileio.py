"""Atomic file output: nothing half-written (developers' guide, "Standards").

Every file swarmproof writes goes through :func:`atomic_write_bytes` or
:func:`atomic_write_text`: the data goes to a temporary file in the same
folder, is flushed and fsynced, then renamed over the target.  Readers see
the old file or the new one, never a fragment.

Examples
--------
>>> import tempfile, os
>>> d = tempfile.mkdtemp()
>>> p = atomic_write_text(os.path.join(d, "a.json"), '{"ok": true}\\n')
>>> open(p).read()
'{"ok": true}\\n'
"""

from __future__ import annotations

import json
import os
import tempfile
from typing import Any

from .errors import UsageError

__all__ = ["atomic_write_bytes", "atomic_write_text", "atomic_write_json", "dumps_json"]


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> str:
    """Write ``data`` to ``path`` atomically; return the path as a string.

    Raises
    ------
    UsageError
        If the folder does not exist or is not writable (names the path).
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise UsageError(f"path={path!r}: folder {folder!r} does not exist",
                         fix="create the folder first or choose another path")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".tmp-", suffix=os.path.basename(path), dir=folder)
    except OSError as exc:
        raise UsageError(f"path={path!r} cannot be written ({exc.strerror})",
                         fix="choose a writable folder") from None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    return path


def atomic_write_text(path: str | os.PathLike, text: str) -> str:
    """Write UTF-8 ``text`` atomically."""
    return atomic_write_bytes(path, text.encode("utf-8"))


def dumps_json(obj: Any) -> str:
    """Deterministic JSON: sorted keys, 2-space indent, trailing newline, no NaN."""
    return json.dumps(obj, sort_keys=True, indent=2, allow_nan=False) + "\n"


def atomic_write_json(path: str | os.PathLike, obj: Any) -> str:
    """Write ``obj`` as deterministic JSON atomically."""
    return atomic_write_text(path, dumps_json(obj))
