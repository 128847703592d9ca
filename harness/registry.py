"""The procedures ptpcert knows, found where Python finds plugins: the entry-point group
``ptpcert.procedures``.

Every procedure, the three built in as much as one from a distribution of its own, declares
an entry point in that group whose object is its description (a
:class:`~ptpcert.procedure.Procedure` subclass, or an instance of one)::

    [project.entry-points."ptpcert.procedures"]
    toy = "ptpcert_toy:ToyProcedure"

The descriptions are loaded on first use and kept; nothing here imports a procedure by name,
so this module is a leaf of the import graph (it imports only the interfaces of
:mod:`ptpcert.procedure`) and every layer may look procedures up through it. A description
that cannot be loaded is left out with a warning, so that one broken plugin does not stop
the others; asking for it by name says why it is missing.
"""

from __future__ import annotations

import threading
import warnings
from importlib.metadata import entry_points

from .procedure import Procedure, ProcedureError

#: the entry-point group procedures register in
GROUP = "ptpcert.procedures"

_LOCK = threading.Lock()
_LOADED: tuple[Procedure, ...] | None = None
#: entry points that could not be loaded: name -> why
_BROKEN: dict[str, str] = {}


def _load() -> tuple[Procedure, ...]:
    found: list[Procedure] = []
    for ep in entry_points(group=GROUP):
        try:
            obj = ep.load()
            proc = obj() if isinstance(obj, type) else obj
            if not isinstance(proc, Procedure):
                raise TypeError(f"{ep.value} is not a ptpcert Procedure")
            if not proc.id or not proc.names:
                raise TypeError(f"{ep.value} has no id or no profile names")
        except Exception as exc:   # a broken plugin is reported, never fatal to the others
            _BROKEN[ep.name] = f"{type(exc).__name__}: {exc}"
            warnings.warn(f"ptpcert: the procedure {ep.name!r} ({ep.value}) cannot be loaded: "
                          f"{type(exc).__name__}: {exc}", RuntimeWarning, stacklevel=3)
            continue
        clash = next((p for p in found if p.id == proc.id or set(p.names) & set(proc.names)), None)
        if clash is not None:
            _BROKEN[ep.name] = f"its id or names clash with {clash.title}"
            warnings.warn(f"ptpcert: the procedure {ep.name!r} ({ep.value}) is left out: its id or a "
                          f"name is also {clash.title}'s", RuntimeWarning, stacklevel=3)
            continue
        found.append(proc)
    return tuple(sorted(found, key=lambda p: (p.rank, p.id)))


def procedures() -> tuple[Procedure, ...]:
    """Every procedure registered, in listing order (:attr:`Procedure.rank`, then id)."""
    global _LOADED
    if _LOADED is None:
        with _LOCK:
            if _LOADED is None:
                _LOADED = _load()
    return _LOADED


def all_names() -> list[str]:
    """The values a profile's ``[iut] procedure`` key may take."""
    return [n for p in procedures() for n in p.names]


def by_name(name: str) -> Procedure:
    """The procedure a profile's ``[iut] procedure`` value (or a vector's) selects."""
    for p in procedures():
        if name in p.names:
            return p
    broken = "".join(f"; the procedure plugin {k!r} could not be loaded ({why})" for k, why in _BROKEN.items())
    raise ProcedureError("procedure", f"{name!r} is not allowed; allowed values: "
                         + ", ".join(f'"{n}"' for n in all_names()) + broken)


def by_id(pid: str) -> Procedure:
    """The procedure with this id (the folders of its vectors, the results' ``procedure``)."""
    for p in procedures():
        if p.id == pid:
            return p
    raise ProcedureError("procedure", f"unknown procedure id {pid!r} (known: "
                         + ", ".join(p.id for p in procedures()) + ")")


def by_title(title: str) -> Procedure | None:
    """The procedure with this title (as run results name it), or None."""
    return next((p for p in procedures() if p.title == title), None)


__all__ = ["GROUP", "all_names", "by_id", "by_name", "by_title", "procedures"]
