"""Vectors: timed two-party transcripts, their schema, loading and writing.

A vector file (TOML, one case per file) says who the IUT is, which parameters apply, what
the tester does and what the IUT must do, step by step, with time windows written in terms
of the timers (``CDT``, ``ADT``...) so that one vector serves every timer setting. The
schema is documented in ``vectors/README.md``; :func:`load_vector` reports a broken file
with its path, the field and what is wrong.

This package names no procedure: each is found through :mod:`ptpcert.registry`. Its
modules, along their jobs (each imports only those above it):

* :mod:`~ptpcert.scenario.expr`: time expressions (``"CDT + 2*CHAR"``), parsed and checked;
* :mod:`~ptpcert.scenario.hexnotation`: the bytes of a step in hex, with runs (``41*1024``);
* :mod:`~ptpcert.scenario.steps`: a step of the transcript and the common step kinds;
* :mod:`~ptpcert.scenario.vector`: the vector, its expected outcome and what is computed
  from it (TOML table, digest, timer values, macro steps expanded);
* :mod:`~ptpcert.scenario.load`: a vector from TOML text, a file or a directory, checked;
* :mod:`~ptpcert.scenario.toml_out`: a vector written as a TOML file.

This module is the package's face: it re-exports the names the rest of ptpcert, the
conformance suites and the tests use.
"""

from .expr import BASE_TIME_NAMES, ZERO, Expr, ExprError, names_in
from .hexnotation import MAX_REPEAT, MAX_STEP_BYTES, brief_hex, parse_vector_hex, vector_hex
from .load import (VectorError, check_times, load_dir, load_vector, load_vector_sets, load_vector_text,
                   vector_from_dict)
from .steps import DATA_KINDS, GRADES, SINCE, STEP_KINDS, Step
from .toml_out import dump_vector
from .vector import (BASE_REQUIREMENTS, IUT_ROLES, STARTS, Expected, StatusSpec, Vector, expand, timer_env,
                     vector_set_hash)

__all__ = [
    "BASE_REQUIREMENTS", "BASE_TIME_NAMES", "DATA_KINDS", "GRADES", "IUT_ROLES", "MAX_REPEAT",
    "MAX_STEP_BYTES", "SINCE", "STARTS", "STEP_KINDS", "ZERO",
    "Expected", "Expr", "ExprError", "StatusSpec", "Step", "Vector", "VectorError",
    "brief_hex", "check_times", "dump_vector", "expand", "load_dir", "load_vector", "load_vector_sets",
    "load_vector_text", "names_in", "parse_vector_hex", "timer_env", "vector_from_dict", "vector_hex",
    "vector_set_hash",
]
