"""3964 and 3964R (CP 341 manual §2.2; Figs. 2-4 to 2-12; Tables 2-3 to 2-6): the reference
model (``model/``), the description the core uses (:class:`P3964Procedure`), the line
analysis, the broken variants, the fuzz kit, the state chart and the rules catalogue
(``rules.toml``)."""

from .description import P3964Procedure

__all__ = ["P3964Procedure"]
