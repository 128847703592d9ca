"""Views of the results object: the console summary and the JUnit XML file; the HTML report
lives in :mod:`ptpcert.report.html`.

The package along its jobs: :mod:`~ptpcert.report.text` has the words every view shares
(anchors, step and failure texts, transcript tails, the summary),
:mod:`~ptpcert.report.junit` writes the JUnit file, and :mod:`~ptpcert.view` has
:class:`ReportView`, what the views need to know about a procedure, handed in by the
caller. This module is their face.
"""

from __future__ import annotations

from ptpcert.report.junit import JUNIT_KIND, write_junit
from ptpcert.report.text import (
    anchor,
    case_link,
    deviation_lines,
    failure_text,
    frame_lines,
    progress_line,
    step_text,
    summary,
    timer_tolerance_text,
    transcript_text,
)
from ptpcert.view import NEUTRAL, ReportView

__all__ = [
    "JUNIT_KIND", "NEUTRAL", "ReportView", "anchor", "case_link", "deviation_lines", "failure_text", "frame_lines",
    "progress_line", "step_text", "summary", "timer_tolerance_text", "transcript_text", "write_junit",
]
