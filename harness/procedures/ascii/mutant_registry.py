"""The register of the ASCII driver's broken variants (:data:`MUTANTS`) and the ``@mutant``
decorator that enters one, with the profile settings the variants share. The variants are in
:mod:`.mutants` and :mod:`.mutants_rules`; :mod:`.mutants` loads both."""

from __future__ import annotations

from ptpcert.procedure import Mutant
from ptpcert.variants import registrar

MUTANTS: dict[str, Mutant] = {}

EC = {"end_criterion": "end_chars", "end_chars": [0x03]}
EC2 = {"end_criterion": "end_chars", "end_chars": [0x0D, 0x0A]}
FL = {"end_criterion": "fixed_length", "fixed_length": 8}
XX = {"end_criterion": "end_chars", "end_chars": [0x03], "flow_control": "xon_xoff", "xon_wait_ms": 500}


def _as_iut(cls):
    """A variant's ``make(params, name="iut")``: only the parameters and the name are passed on."""
    return lambda params, name="iut": cls(params, name=name)


mutant = registrar(MUTANTS, make=_as_iut)
