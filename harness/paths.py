"""Where the project's data lives: the golden vectors and example profiles ship inside the
package and are found with importlib.resources, so an installed wheel works from any
directory; fuzz findings go to the user's current directory, never into the installation."""

from __future__ import annotations

from importlib import resources
from importlib.resources.abc import Traversable
from pathlib import Path

#: Where ``ptpcert fuzz`` writes its findings unless ``--export`` says otherwise.
FINDINGS_DIR = Path("vectors") / "regressions"


def bundled_vectors() -> Traversable:
    """The golden vectors shipped with ptpcert (one folder per procedure)."""
    return resources.files("ptpcert.vectors")


def bundled_profiles() -> Traversable:
    """The example IUT profiles shipped with ptpcert."""
    return resources.files("ptpcert.conformance").joinpath("profiles")


def findings_dir() -> Path:
    """``./vectors/regressions`` in the current directory."""
    return Path.cwd() / FINDINGS_DIR
