"""Where the 3964(R) broken variants are entered: the ``@mutant(name, rule, **profile)`` decorator.

Part of :mod:`ptpcert.procedures.p3964.mutants`. Each topic module of the package
(:mod:`.sending`, :mod:`.attempts`, :mod:`.receiving`, :mod:`.line`, :mod:`.timers`)
decorates its variants with :func:`mutant`, the procedure-neutral registrar of
:mod:`ptpcert.variants`, which enters them into :data:`REGISTERED`. Nothing reads that
mapping but :mod:`.listing`, which lays the variants out in the order they are listed.
"""

from __future__ import annotations

from ptpcert.procedure import Mutant
from ptpcert.variants import registrar

__all__ = ["REGISTERED", "mutant"]

#: every 3964(R) variant by name, in the order the topic modules were imported
REGISTERED: dict[str, Mutant] = {}

#: ``@mutant(name, rule, **profile)``: enters a station class into :data:`REGISTERED`,
#: named ``Mutant_<name>``
mutant = registrar(REGISTERED)
