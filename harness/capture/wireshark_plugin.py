"""The Wireshark dissector shipped with ptpcert (``wireshark/ptpcert.lua``, package data of
``ptpcert.capture``): where it is, the personal Lua plugin folder Wireshark loads it from,
and installing it there (``ptpcert capture --wireshark-plugin``). The dissector is specified
in ``docs/wireshark.md``.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from importlib import resources
from pathlib import Path

from ptpcert.capture.model import CaptureError

PLUGIN_NAME = "ptpcert.lua"


def plugin_path() -> Path:
    """The dissector's file in the installed package."""
    return Path(str(resources.files("ptpcert.capture") / "wireshark" / PLUGIN_NAME))


def personal_plugin_dir() -> Path:
    """Wireshark's personal Lua plugin folder: ``%APPDATA%\\Wireshark\\plugins`` on Windows,
    ``~/.local/lib/wireshark/plugins`` elsewhere (Linux, macOS, the BSDs)."""
    if os.name == "nt" and os.environ.get("APPDATA"):
        return Path(os.environ["APPDATA"]) / "Wireshark" / "plugins"
    return Path.home() / ".local" / "lib" / "wireshark" / "plugins"


def install_plugin(folder: Path | None = None) -> tuple[Path, str]:
    """Copy the dissector into ``folder`` (default: the personal plugin folder), creating the
    folder when missing; written whole to a temporary file first. Returns the file and what
    happened: ``installed``, ``replaced`` (a different copy was there) or ``unchanged``. A folder that cannot hold it raises
    :class:`CaptureError` naming the folder and why."""
    folder = personal_plugin_dir() if folder is None else Path(folder)
    if folder.exists() and not folder.is_dir():
        raise CaptureError(f"{folder}: is not a folder; give the folder Wireshark loads Lua plugins from")
    target = folder / PLUGIN_NAME
    if target.exists() and not target.is_file():
        raise CaptureError(f"{target}: exists and is not a regular file; remove it or give another folder")
    source = plugin_path().read_bytes()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        if target.exists():
            if target.read_bytes() == source:
                return target, "unchanged"
            how = "replaced"
        else:
            how = "installed"
        fd, tmp = tempfile.mkstemp(prefix=".ptpcert-", suffix=".lua", dir=folder)
        try:
            with os.fdopen(fd, "wb") as fp:
                fp.write(source)
            shutil.copymode(plugin_path(), tmp)
            os.replace(tmp, target)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError as exc:
        where = exc.filename or folder
        raise CaptureError(f"{where}: cannot install the plugin there ({exc.strerror or exc})") from None
    return target, how
