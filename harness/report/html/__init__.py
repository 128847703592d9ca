"""The HTML report: one self-contained file (inline CSS, inline SVG, a little inline
JavaScript for the verdict filter; readable without it) rendered from the results object.

Per case it shows the rule, the verdict, the STATUS events expected and observed, and a
sequence diagram of the transcript drawn the way the manual draws its figures: the tester's
lane on the left, the IUT's on the right, time flowing down, one arrow per burst of bytes
named as the procedure's view says (:class:`ptpcert.view.ReportView`, handed in by
the caller), the timer windows the steps watched as bars beside the
IUT's lane, BREAK and character errors marked, and the first divergence in red.

The package along its jobs:

* :mod:`~ptpcert.report.html.page`: the page, :func:`render` and :func:`write_html`, with
  the style sheet and script of ``assets/`` inlined;
* :mod:`~ptpcert.report.html.case`: one case's section;
* :mod:`~ptpcert.report.html.diagram`: the SVG sequence diagram (its classes and data
  attributes are documented there), on :mod:`~ptpcert.report.html.layout` (geometry and
  time axis) and :mod:`~ptpcert.report.html.frames` (the procedure's frames);
* :mod:`~ptpcert.report.html.events`: the transcript grouped into arrows and their labels;
* :mod:`~ptpcert.report.html.status`: STATUS codes annotated, and their legend;
* :mod:`~ptpcert.report.html.rules`: the traceability section;
* :mod:`~ptpcert.report.html.markup`: escaping, times, hex and badges.

This module is their face.
"""

from __future__ import annotations

from ptpcert.report.html.case import FAILURES, case_section, transcript_section
from ptpcert.report.html.diagram import sequence_svg
from ptpcert.report.html.events import (
    BURST_SHOWN,
    GROUP_GAP,
    MAX_TOKENS,
    Arrow,
    LineBreak,
    arrow_label,
    burst_hex,
    group_events,
)
from ptpcert.report.html.layout import AXIS_X, IX, MAX_H, TX, W
from ptpcert.report.html.markup import abbreviate_hex, esc, ms, ms_short
from ptpcert.report.html.page import ordered_cases, render, write_html
from ptpcert.report.html.status import status_name

__all__ = [
    "AXIS_X", "BURST_SHOWN", "FAILURES", "GROUP_GAP", "IX", "MAX_H", "MAX_TOKENS", "TX", "W", "Arrow",
    "LineBreak", "abbreviate_hex", "arrow_label", "burst_hex", "case_section", "esc", "group_events", "ms",
    "ms_short", "ordered_cases", "render", "sequence_svg", "status_name", "transcript_section", "write_html",
]
