"""The procedures ptpcert knows, each described once (:class:`ptpcert.procedure.Procedure`).
Adding one adds a module here and a line to :data:`PROCEDURES`; no runner code changes."""

from __future__ import annotations

from ptpcert.procedures.ascii.description import PAscii
from ptpcert.procedures.p3964.description import P3964
from ptpcert.procedures.rk512.description import Rk512

from ..procedure import Procedure, ProcedureError

PROCEDURES: tuple[Procedure, ...] = (P3964(), Rk512(), PAscii())


def by_name(name: str) -> Procedure:
    """The procedure a profile's ``[iut] procedure`` value (or a vector's) selects."""
    for p in PROCEDURES:
        if name in p.names:
            return p
    raise ProcedureError("procedure", f"{name!r} is not allowed; allowed values: "
                         + ", ".join(f'"{n}"' for n in all_names()))


def by_id(pid: str) -> Procedure:
    for p in PROCEDURES:
        if p.id == pid:
            return p
    raise ProcedureError("procedure", f"unknown procedure id {pid!r}")


def all_names() -> list[str]:
    return [n for p in PROCEDURES for n in p.names]


__all__ = ["PROCEDURES", "Procedure", "ProcedureError", "all_names", "by_id", "by_name"]
