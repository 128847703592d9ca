"""Report files written whole or not at all, and the check that a report can be written
before a run starts (so that no run ends without its reports).

Part of :mod:`ptpcert.results`; the JSON results, JUnit and HTML views write through
:func:`write_atomic`. Standard library only.
"""

from __future__ import annotations

import errno
import os
import secrets
from pathlib import Path

def write_atomic(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` whole or not at all: into a temporary file in the same
    directory, renamed over ``path`` when complete; the temporary file is removed whatever
    goes wrong."""
    p = Path(path)
    if p.exists() and not p.is_file():   # a device, a FIFO: never replaced by a regular file
        raise OSError(errno.EEXIST, "exists and is not a regular file", str(p))
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.parent / f".{p.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp"
    try:
        with open(tmp, "x", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, p)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise


def report_path_problem(path: str | Path) -> str | None:
    """Why a report cannot be written to ``path``, or None when it can. Checked before a
    run starts, so that no run ends without its reports: missing directories are created,
    and a file is created and removed in the target directory."""
    text = str(path)
    if not text.strip():
        return "is empty; give a file name"
    p = Path(path)
    if p.is_dir():
        return "is a directory; give a file name in it"
    if p.exists() and not p.is_file():
        return "exists and is not a regular file"
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return f"its directory {p.parent} cannot be created ({exc.strerror})"
    failed = _probe(p.parent, p.name)
    return f"no file can be written in {p.parent} ({failed.strerror})" if failed else None


def _probe(directory: Path, name: str) -> OSError | None:
    """Create and remove a file in ``directory`` (named after ``name``): the error where
    none can be created, else None."""
    probe = directory / f".{name}.{os.getpid()}.{secrets.token_hex(4)}.probe"
    try:
        with open(probe, "x", encoding="utf-8"):
            pass
    except OSError as exc:
        return exc
    try:
        probe.unlink()
    except OSError:
        pass
    return None


def directory_problem(path: str | Path) -> str | None:
    """Why files cannot be written into the directory ``path``, or None when they can:
    checked before work whose results are written there at the end (a fuzz campaign's
    findings, an example database). Directories it creates for the check are removed again."""
    text = str(path)
    if not text.strip():
        return "is empty; give a directory"
    p = Path(path)
    if p.exists() and not p.is_dir():
        return "exists and is not a directory"
    made = [d for d in (p, *p.parents) if not d.exists()]
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return f"cannot be created ({exc.strerror})"
    try:
        failed = _probe(p, "ptpcert")
        if failed:
            return f"no file can be written in it ({failed.strerror})"
    finally:
        for d in made:   # deepest first
            try:
                d.rmdir()
            except OSError:
                pass
    return None
