"""The 3964/3964R fuzz kit, level 2: generated partner behaviour against an IUT, the model as
oracle (the campaign is :mod:`ptpcert.fuzz.campaign`).

For every example, hypothesis draws the tester's behaviour step by step while a model
station plays the IUT in virtual time (co-simulation): what the tester does next depends on
what a conforming IUT has just done (answer its STX with DLE, NAK, another character, a
crossing STX or silence; interrupt its block; send blocks with wrong BCCs, character
errors, gaps over CDT...). The result is an ordinary vector: the tester's stimuli and, as
expectations, what the model did, with windows derived from why it did it. The vector is
run against the IUT; a divergence is a finding, confirmed by a second run, and not a
finding when a model with another defensible reading of the manual (docs/readings.md) would
have done what the IUT did. Hypothesis shrinks every finding to a minimal transcript,
which is written out as a vector (``vectors/regressions/``).

The tester is a reactive partner: before each stimulus it waits until what the IUT has
begun to send (the replies the protocol requires) is complete and written into the vector
as an expectation, so that the runner, too, sends it only after it has seen them; only a
deliberate violation (interrupting the IUT's block) goes out while the IUT is sending, and
the runner then judges what the IUT actually saw. Timing stimuli keep a margin from every
limit that a real process can honour: "just under" a timer is 70 % of it, "just over" 150 %,
and no stimulus lands closer to one of the IUT's deadlines than the runner's real-time
tolerance can tell apart (before the edge: how late the tester's byte may go out plus two
characters; after it: how late the IUT's timer may act and still pass); the exact edges are
fuzzed in virtual time by level 1 (tests/procedures/p3964/test_fuzz_model.py). Every time in a generated
vector counts forwards: output that began while the tester was still sending is measured
from the step before that stimulus (``since = "mark"``), never with a negative offset.

The kit in modules along its jobs: :mod:`.rules` (the table rules the expectations name),
:mod:`.cosim` (the model IUT in virtual time and the vector it writes), :mod:`.generator`
(the tester's behaviour, drawn action by action) and :mod:`.kit` (the kit the campaign
gets, with the other readings of the open points). This face re-exports their names.
"""

from .cosim import CoSim
from .generator import CONTROL_BIAS, Generator, payloads
from .kit import ALTERNATIVE_READINGS, FUZZ_KIT
from .rules import BLOCK_RULE, UNEXPLAINED_RULE, expectation_note, rule_for, rule_of_note

__all__ = ["ALTERNATIVE_READINGS", "BLOCK_RULE", "CONTROL_BIAS", "CoSim", "FUZZ_KIT", "Generator",
           "UNEXPLAINED_RULE", "expectation_note", "payloads", "rule_for", "rule_of_note"]
