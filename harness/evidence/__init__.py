"""Certification evidence: one bundle per run that a partner can verify, re-judge offline and
trust (``ptpcert run --evidence FILE.zip``, ``ptpcert verify FILE.zip``).

* :mod:`~ptpcert.evidence.facts` - the tool's identity and the digests of the suite, the
  vector files and the rules catalogues;
* :mod:`~ptpcert.evidence.bundle` - the manifest, the deterministic zip written atomically,
  the OpenSSH signature;
* :mod:`~ptpcert.evidence.make` - a finished run's bundle: reports, capture, PICS, PIXIT,
  certificate;
* :mod:`~ptpcert.evidence.verify` - the checks of ``ptpcert verify``.

The cases are handed in (the command line generates the suite); nothing here names a procedure.
"""

from ptpcert.evidence.bundle import EvidenceError, read_bundle, sign, write_bundle
from ptpcert.evidence.facts import tool_facts
from ptpcert.evidence.make import make_members, run_capture, seal
from ptpcert.evidence.verify import FAIL, NOTE, OK, Check, verify

__all__ = ["Check", "EvidenceError", "FAIL", "NOTE", "OK", "make_members", "read_bundle", "run_capture", "seal",
           "sign", "tool_facts", "verify", "write_bundle"]
