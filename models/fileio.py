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
from .interrupt import raise_if_interrupted

__all__ = ["check_output_path", "check_output_dir", "atomic_write_bytes", "atomic_write_text", "atomic_write_json", "dumps_json"]


def _umask() -> int:
    """The process's file-mode creation mask (read without changing it for long)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def check_output_path(path: str | os.PathLike, option: str = "path", *, new_folder: bool = False) -> str:
    """Check, before any work, that ``path`` can be written as a file; return it as a string.

    Commands call it on every output option first, so a long run never ends
    in an error about where to write its result.

    >>> check_output_path("")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: path='' is empty; fix: give a file name
    >>> import tempfile
    >>> check_output_path(tempfile.gettempdir(), "--plot")
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: --plot=... is a folder; fix: give a file name (e.g. inside that folder)
    """
    text = os.fspath(path)
    if not text:
        raise UsageError(f"{option}='' is empty", fix="give a file name")
    if os.path.isdir(text):
        raise UsageError(f"{option}={text!r} is a folder", fix="give a file name (e.g. inside that folder)")
    folder = os.path.dirname(os.path.abspath(text))
    if new_folder:   # the writer creates missing folders: check the nearest one that exists
        while folder and not os.path.exists(folder):
            folder = os.path.dirname(folder)
        if not os.path.isdir(folder):
            raise UsageError(f"{option}={text!r}: {folder!r} is a file, not a folder", fix="choose another path")
    if not os.path.isdir(folder):
        raise UsageError(f"{option}={text!r}: folder {folder!r} does not exist",
                         fix="create the folder first or choose another path")
    if not os.access(folder, os.W_OK):
        raise UsageError(f"{option}={text!r}: folder {folder!r} is not writable", fix="choose a writable folder")
    return text


def check_output_dir(path: str | os.PathLike, option: str = "--out") -> str:
    """Check, before any work, that ``path`` is a folder or can be created as one.

    >>> import tempfile, os
    >>> f = tempfile.NamedTemporaryFile(delete=False); f.close()
    >>> check_output_dir(f.name)
    Traceback (most recent call last):
    ...
    swarmproof.models.errors.UsageError: --out=... is a file, not a folder; fix: give a folder (it is created when missing)
    >>> os.unlink(f.name)
    """
    text = os.fspath(path)
    if not text:
        raise UsageError(f"{option}='' is empty", fix="give a folder")
    if os.path.exists(text) and not os.path.isdir(text):
        raise UsageError(f"{option}={text!r} is a file, not a folder", fix="give a folder (it is created when missing)")
    parent = os.path.dirname(os.path.abspath(text))
    while parent and not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if parent and not os.path.isdir(parent):
        raise UsageError(f"{option}={text!r}: {parent!r} is a file, so no folder can be made below it",
                         fix="give a folder path whose existing part is a folder")
    target = text if os.path.isdir(text) else parent
    if target and not os.access(target, os.W_OK):
        raise UsageError(f"{option}={text!r}: {target!r} is not writable", fix="choose a writable folder")
    return text


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> str:
    """Write ``data`` to ``path`` atomically; return the path as a string.

    The file gets the mode a plain ``open(path, "w")`` would give it
    (``0o666`` less the user's umask), not the ``0o600`` of a temporary file.

    Raises
    ------
    UsageError
        If the path is empty or a folder, the folder does not exist or is
        not writable, or the disk is full (names the path and the cause).
    """
    raise_if_interrupted()    # nothing is written once Ctrl-C was pressed (models/interrupt.py)
    path = check_output_path(path)
    folder = os.path.dirname(os.path.abspath(path))
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
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError):
            raise UsageError(f"path={path!r} cannot be written ({exc.strerror or exc})",
                             fix="free disk space, or choose another path") from None
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
