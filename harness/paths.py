"""Where the project's data lives when the package runs from a checkout."""

from __future__ import annotations

import os
from pathlib import Path

PROJECT = Path(__file__).resolve().parent.parent


def default_vectors_dir() -> Path:
    env = os.environ.get("PTPCERT_VECTORS")
    if env:
        return Path(env)
    for candidate in (PROJECT / "vectors", Path.cwd() / "vectors"):
        if candidate.is_dir():
            return candidate
    return PROJECT / "vectors"
