"""The fuzzer for RK 512 (``ptpcert fuzz`` with an RK 512 profile), level 2: generated partner
behaviour against an IUT, the RK 512 model as the oracle.

For every example hypothesis draws the tester's behaviour step by step while the model plays
the IUT in virtual time (co-simulation through the ``sim:`` transport, exactly as the runner
will replay it): what the tester does next depends on what a conforming IUT has just done.
The tester sends commands, valid or with one thing wrong - a header byte 1..10 (the nibbles
of byte 10 included), the frame class, the data length against the header length, the chunk
boundaries 127/128/129, the frame order against the open request - and answers the IUT's own
requests (from a drawn request script) correctly, with a wrong response, late around T_RES
or not at all; it places DLEs in the header, the data, the REATEL and the BCC, corrupts a
BCC, pauses inside a block around CDT, and sends its STX while a response is owed (crossing
the IUT's). What the model does becomes the expectation: its frames as ``receive`` steps,
its quiet periods as silence, its request results and STATUS events. A divergence is a
finding unless a model with another reading of an open point of the manual (the fields of
:class:`~ptpcert.procedures.rk512.model.readings.Rk512Readings`) does what the IUT did.

Timing stimuli keep a margin from every limit a real process can honour: T_RES is probed at
30 %, 70 % and 150 %, CDT at 50 % and 150 %, and no stimulus lands within 15 % of the
shortest link timer (plus two characters) of one of the model's deadlines. Exact edges are
level 1's (tests/procedures/rk512/test_fuzz_rk512_model.py).

The kit in modules along its jobs: :mod:`.cosim` (the model IUT in virtual time and the
steps of the vector), :mod:`.requests` (a request in progress, a command header),
:mod:`.generator` (drawing an example: the IUT's request script, the set-up, valid
commands), :mod:`.example` (the tester's side of one example: taking what the IUT sends,
sending frames, the vector) with its two roles :mod:`.passive` (the tester commands) and
:mod:`.active` (the tester answers the IUT's requests), and :mod:`.kit` (the kit the campaign
gets, with the other readings of the open points). This face re-exports their names.
"""

from .cosim import RkCoSim
from .example import INFORMATIONAL, RkExample
from .generator import RkGenerator
from .kit import ALTERNATIVE_READINGS, FUZZ_KIT

__all__ = ["FUZZ_KIT", "RkCoSim", "RkGenerator", "RkExample", "ALTERNATIVE_READINGS", "INFORMATIONAL"]
