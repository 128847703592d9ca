"""The fuzzer, level 2: generated partner behaviour against an IUT, the model as oracle.

The engine is procedure-neutral: :mod:`.campaign` runs hypothesis examples drawn by a
procedure's fuzz kit (:class:`.kit.FuzzKit`, from ``Procedure.fuzz_kit()``; the kits live with
their procedures), judges them with the runner and shrinks and exports findings;
:mod:`.workers` runs several campaigns at once over a shared example database
(:mod:`.database`); :mod:`.settings` holds the hypothesis settings profiles, registered where a
program starts. Level 1 (two model stations in virtual time) is in the tests.
"""

from .campaign import Campaign, Finding, divergent_rule, export, finding_key, interruptions, late_violation
from .database import open_database
from .kit import FuzzKit, ms, note_rule, send_receive_codes
from .settings import PROFILES, register_profiles
from .workers import WorkerSpec, WorkersResult, run_workers

__all__ = ["Campaign", "Finding", "FuzzKit", "PROFILES", "WorkerSpec", "WorkersResult", "divergent_rule", "export",
           "finding_key", "interruptions", "late_violation", "ms", "note_rule", "open_database", "register_profiles",
           "run_workers", "send_receive_codes"]
