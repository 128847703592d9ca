"""The one results object of a run. JSON is its own format; JUnit, HTML and the console
summary are views of it (:mod:`ptpcert.report`).

The package along its jobs:

* :mod:`~ptpcert.results.cases`: the verdicts, a case's results and its first divergence;
* :mod:`~ptpcert.results.run`: :class:`RunResult`, its counts, verdict and deviations, and
  its JSON form;
* :mod:`~ptpcert.results.reading`: a saved results file read back and checked key by key;
* :mod:`~ptpcert.results.failures`: the frame a divergence falls in, failure signatures
  and their grouping by root cause;
* :mod:`~ptpcert.results.transcripts`: transcripts packed into runs of bytes and read back;
* :mod:`~ptpcert.results.files`: report files written whole or not at all;
* :mod:`~ptpcert.results.merge`: the results of shards of one run joined into one.

This module is their face: ``from ptpcert import results as R`` gives every name below.
"""

from __future__ import annotations

from ptpcert.results.cases import (
    ERROR,
    FAIL,
    FAILING,
    FRAME_FIELDS,
    GRADE_ORDER,
    INFORMATIONAL,
    NON_STRICT,
    NOT_RUN,
    PASS,
    UNSUPPORTED,
    VERDICTS,
    XFAIL,
    XPASS,
    CaseResult,
    Divergence,
    worse_grade,
)
from ptpcert.results.failures import (
    describe_group,
    describe_signature,
    divergence_frame,
    divergence_frame_text,
    failure_signature,
    root_causes,
)
from ptpcert.results.files import directory_problem, report_path_problem, write_atomic
from ptpcert.results.merge import merge_runs, parse_shard
from ptpcert.results.reading import SCHEMA, SCHEMA_V1, SCHEMAS, ResultsError
from ptpcert.results.run import RunResult
from ptpcert.results.transcripts import (
    BYTE_KINDS,
    RUN_KINDS,
    dropped_note,
    pack_transcript,
    run_bytes,
    unpack_transcript,
    wire_events,
    wire_runs,
)

__all__ = [
    "BYTE_KINDS", "ERROR", "FAIL", "FAILING", "FRAME_FIELDS", "GRADE_ORDER", "INFORMATIONAL", "NON_STRICT",
    "NOT_RUN", "PASS", "RUN_KINDS", "SCHEMA", "SCHEMAS", "SCHEMA_V1", "UNSUPPORTED", "VERDICTS", "XFAIL",
    "XPASS", "CaseResult", "Divergence", "ResultsError", "RunResult", "describe_group", "describe_signature",
    "divergence_frame", "divergence_frame_text", "dropped_note", "failure_signature", "merge_runs",
    "pack_transcript", "parse_shard",
    "directory_problem", "report_path_problem", "root_causes", "run_bytes", "unpack_transcript", "wire_events", "wire_runs",
    "worse_grade", "write_atomic",
]
