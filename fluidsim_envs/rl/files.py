"""Writing a run folder's files so that a kill never leaves half a file under its final name,
and checking, before a command starts, that it can write where it was told to.

Every file a run writes (checkpoints, the best model and its statistics, the evaluation
history, ``run.yaml``, ``config.yaml``, the final model) goes first to a temporary file beside it
(``.<name>.<random>.partial<suffix>``: same folder, so the final step is a rename within one
file system) and then takes the final name with :func:`os.replace`, which is atomic on POSIX:
a reader sees the old file or the new one, whole. A killed write leaves only the temporary
file, which :func:`remove_partials` deletes on the next resume.

``FLUIDSIM_WRITE_DELAY_S`` (seconds, a test hook, off when unset) sleeps after each temporary
file is written and before it is renamed: the kill benchmark (``benchmarks/kill_resume.py``)
sets it so that its kills can land inside a write, where code without the rename would have
left a truncated file under the final name.
"""

from __future__ import annotations

import contextlib
import errno
import os
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

PARTIAL = ".partial"  # the marker in a temporary file's name
WRITE_DELAY_ENV = "FLUIDSIM_WRITE_DELAY_S"


class RunError(RuntimeError):
    """A run folder that cannot be used as asked (missing, unwritable, nothing to resume)."""


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` for the caller to write; when the block ends without
    an error it replaces ``path`` (atomically), and when it fails it is removed. The
    temporary name keeps ``path``'s suffix (a writer may add its own suffix to a path
    without one)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(
        dir=path.parent, prefix=f".{path.name}.", suffix=f"{PARTIAL}{path.suffix}"
    )
    os.close(fd)
    tmp_path = Path(tmp)
    # mkstemp makes 0600 files and the rename keeps the mode: give the file the mode a plain
    # open would (0666 less the umask), so that others can read a run folder as before
    os.chmod(tmp_path, 0o666 & ~_umask())
    try:
        yield tmp_path
        _flush_to_disk(tmp_path)
        _test_delay()
        os.replace(tmp_path, path)
    except BaseException as e:
        tmp_path.unlink(missing_ok=True)
        if disk_full(e):
            raise RunError(
                f"{path}: no space left on the disk; this file's last whole version and every "
                "file written before it are kept as they were"
            ) from None
        raise


def disk_full(error: BaseException) -> bool:
    """Whether ``error``, or an error it was raised from or during, is a full disk (or quota):
    libraries wrap the OSError (torch, safetensors)."""
    seen = set()
    while error is not None and id(error) not in seen:
        seen.add(id(error))
        if isinstance(error, OSError) and error.errno in (errno.ENOSPC, errno.EDQUOT):
            return True
        if "No space left on device" in str(error):  # a library's own error, its text kept
            return True
        error = error.__cause__ or error.__context__
    return False


def _umask() -> int:
    """The process's umask (read by setting it, so set back at once)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_with(path: str | Path, write: Callable[[Path], object]) -> None:
    """``write(tmp)`` writes the file, at a temporary path that then replaces ``path``."""
    with atomic_path(path) as tmp:
        write(tmp)


def write_text(path: str | Path, text: str) -> None:
    """``path.write_text(text)``, atomically."""
    write_with(path, lambda tmp: tmp.write_text(text))


def write_bytes(path: str | Path, data: bytes) -> None:
    """``path.write_bytes(data)``, atomically."""
    write_with(path, lambda tmp: tmp.write_bytes(data))


def remove_partials(folder: Path) -> list[Path]:
    """Delete the temporary files killed writes left in ``folder`` and its subfolders; return
    them. Only names this module makes are touched."""
    found = [p for p in folder.rglob(f".*{PARTIAL}*") if p.is_file()]
    for p in found:
        p.unlink(missing_ok=True)
    return found


def _flush_to_disk(path: Path) -> None:
    # a kill does not lose what the kernel holds, but a power cut would: the data reaches the
    # disk before the rename makes it the file
    with open(path, "rb") as f:
        os.fsync(f.fileno())


def _test_delay() -> None:
    delay = os.environ.get(WRITE_DELAY_ENV)
    if delay:
        time.sleep(float(delay))


# --------------------------------------------------------------------------------------------
# where a command may write


def check_writable_folder(path: Path, flag: str) -> None:
    """``path`` is a folder this process can create files in, or can be created as one:
    otherwise a :class:`RunError` that names ``flag``, the path and why."""
    if path.exists() and not path.is_dir():
        raise RunError(f"{flag} {path}: exists and is not a folder")
    _check_can_create_in(_nearest_existing(path), path, flag)


def check_writable_file(path: Path, flag: str) -> None:
    """``path`` is a file this process can write (create or replace): otherwise a
    :class:`RunError` that names ``flag``, the path and why."""
    if path.is_dir():
        raise RunError(f"{flag} {path}: is a folder, not a file")
    if path.exists() and not os.access(path, os.W_OK):
        raise RunError(f"{flag} {path}: not writable (permission denied)")
    _check_can_create_in(_nearest_existing(path.parent), path, flag)


def _nearest_existing(path: Path) -> Path:
    """``path`` or its nearest ancestor that exists (what a ``mkdir -p`` would start from)."""
    path = path.absolute()
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def _check_can_create_in(folder: Path, path: Path, flag: str) -> None:
    """Creating a file in ``folder`` works: tried for real, since permission bits say nothing
    for root, nor for a read-only or virtual file system (/proc, /sys)."""
    if not folder.is_dir():
        raise RunError(f"{flag} {path}: {folder} is not a folder")
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=f".write-check{PARTIAL}"):
            pass
    except OSError as e:
        # ENOENT for a folder that exists: a file system where files cannot be made (/proc)
        why = "no files can be created there" if e.errno == errno.ENOENT else e.strerror
        raise RunError(f"{flag} {path}: cannot write in {folder} ({why or e})") from None


__all__ = [
    "RunError",
    "atomic_path",
    "check_writable_file",
    "check_writable_folder",
    "remove_partials",
    "write_bytes",
    "write_text",
    "write_with",
]
