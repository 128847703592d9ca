"""The procedures built into ptpcert, one package each: ``p3964`` (3964/3964R), ``rk512``
(the RK 512 computer link, on the 3964R link) and ``ascii`` (the ASCII driver). Each holds
everything its procedure owns: its model (``model/``, standard library only), its description
(``description.py``, a :class:`ptpcert.procedure.Procedure`), line analysis, broken variants,
fuzz kit and rules catalogue. They register like any other procedure, in the entry-point group
``ptpcert.procedures`` (pyproject.toml); the rest of ptpcert finds them through
:mod:`ptpcert.registry` and never imports this package by name. Nothing crosses between
procedures except RK 512's use of the 3964R link model."""
