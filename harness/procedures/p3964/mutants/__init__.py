"""Deliberately broken variants of the 3964(R) reference implementation, each breaking one rule.

They prove the suite's detection power: ``ptpcert iut --mutant NAME`` runs one in real
time, ``sim:?mutant=NAME`` in virtual time; the tests run the suite against each and
check that it fails, naming the cases that caught it. A mutant is the reference station
with one action, decision or table row changed; nothing else differs. A variant overrides the
station's protected hooks (actions, decisions, ``_body``, ``_durations``, the attempt limits) or
patches rows of its table; it never touches the station's private fields.

The variants are grouped by the part of the procedure they break:

* :mod:`.sending` -- the block sent (framing, BCC), the data phase, the initialization conflict;
* :mod:`.attempts` -- a send job's setup and transmission attempts and their counters;
* :mod:`.receiving` -- the receiver: DLE pairs, the end of the block, repetitions, its length;
* :mod:`.line` -- start-up, stray characters in idle, character errors, BREAK;
* :mod:`.timers` -- the CDT, the ADT and T_NAKTIM.

Each enters its variants through :mod:`.registry`; :mod:`.listing` lays them out in the
order they are listed, as :data:`MUTANTS`. The RK 512 variants put some of them under a
correct RK 512 layer (the ``link-`` variants).
"""

from .listing import MUTANTS
from .receiving import Counting

__all__ = ["MUTANTS", "Counting"]
