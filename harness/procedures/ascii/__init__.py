"""The ASCII driver (CP 341 manual §2.2.4; Figs. 2-20 to 2-24; Tables 2-7 to 2-10): the
reference model (``model/``), the description the core uses (:class:`AsciiProcedure`), the
line analysis, the broken variants and the fuzz kit."""

from .description import AsciiProcedure

__all__ = ["AsciiProcedure"]
