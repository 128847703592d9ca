"""The RK 512 computer link (CP 341 manual §2.2.3, §6.3.2, §8.3/8.4; Figs. 2-13 to 2-19), a
layer over the 3964R link: the reference model (``model/``), the description the core uses
(:class:`Rk512Procedure`), the line analysis, the broken variants and the fuzz kit."""

from .description import Rk512Procedure

__all__ = ["Rk512Procedure"]
