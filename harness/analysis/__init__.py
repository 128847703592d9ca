"""Line analysis: judge both stations of a recorded or live serial link with the model.

A capture (:mod:`ptpcert.capture`) holds what each of two stations put on its transmit line.
For each seat that is judged, a model station with that seat's parameters is fed what the
*other* seat sent, at the times it arrived, and what the model would send is compared, byte
by byte and in time, with what the seat sent. A difference is a *finding*: the rule the seat
broke (the manual's reference), what the model sent or would have sent, what the seat sent,
and the STATUS events a CP 341 in each seat raises. Before a difference stands, the
alternatives the procedure names (other readings of the manual's open points, the other
seat's bytes moved within the capture's timing resolution) are tried; one that follows the
seat turns the finding into an informational one. The report groups the line into exchanges,
each a case of the run results (``ptpcert analyze``; live, ``ptpcert monitor``).

This package knows no protocol; what a procedure brings is a :class:`ProcedureAnalyzer`
(``Procedure.analyzer(params_a, params_b)``). Its modules, each importing only those before it:

* :mod:`~ptpcert.analysis.interface` - the procedure's part (:class:`ProcedureAnalyzer`,
  :class:`Cause`, :class:`Explanation`, :class:`Variant`) and what both sides pass
  (:class:`Item`, :class:`Finding`, :data:`SEATS`, :data:`OTHER`, :data:`WAIT`, :data:`QUANTUM`);
* :mod:`~ptpcert.analysis.seat` - the seat run: one seat followed by its model, byte by byte
  and in time, with the timing windows;
* :mod:`~ptpcert.analysis.judge` - the seat judge: a seat through the whole capture, the
  alternatives before a difference stands, and following it again after one;
* :mod:`~ptpcert.analysis.line` - the line: both judges fed chunk by chunk (or live), the
  findings graded against what the recording lost, the line cut into exchanges;
* :mod:`~ptpcert.analysis.results` - a whole capture judged, and the outcome as run results;
* :mod:`~ptpcert.analysis.monitor` - reading a live link for ``ptpcert monitor``.

This module is the package's face: it re-exports the names the command line, the procedures'
analyzers, the tests and the benchmarks use.
"""

from ptpcert.analysis.interface import (
    OTHER,
    QUANTUM,
    SEATS,
    WAIT,
    Cause,
    Explanation,
    Finding,
    Item,
    ProcedureAnalyzer,
    Variant,
    clipped,
    resolution_variants,
    strip_section,
)
from ptpcert.analysis.judge import SeatJudge
from ptpcert.analysis.line import Exchange, LineAnalysis
from ptpcert.analysis.results import Analysis, analyze, exchange_cases, summary_line, to_results
from ptpcert.analysis.seat import SeatRun

__all__ = [
    "OTHER", "QUANTUM", "SEATS", "WAIT",
    "Cause", "Explanation", "Finding", "Item", "ProcedureAnalyzer", "Variant", "clipped",
    "resolution_variants", "strip_section",
    "SeatRun", "SeatJudge", "Exchange", "LineAnalysis",
    "Analysis", "analyze", "exchange_cases", "summary_line", "to_results",
]
