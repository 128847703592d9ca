"""3964/3964R's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

Line analysis (:mod:`ptpcert.analysis`) follows each seat of a recorded or live link with a
model station and asks the procedure what it cannot know itself. For 3964/3964R that is
:class:`P3964Analyzer`, made of:

* :mod:`~ptpcert.procedures.p3964.analysis.analyzer` - the analyzer itself: timing, the model
  stations of each seat, the alternatives to try before a difference stands, the exchange
  labels;
* :mod:`~ptpcert.procedures.p3964.analysis.events` - the local events the seat's bytes reveal
  (a send job and its block read ahead from the line, a receive buffer that became free, a
  restart) and where an exchange begins on a line that never goes quiet;
* :mod:`~ptpcert.procedures.p3964.analysis.causes` - why the model sends each byte (rule,
  reference, STATUS code, timing window) and what a byte the model does not send breaks.

RK 512's analysis (:mod:`ptpcert.procedures.rk512.analysis`) builds on it: its link is
3964(R), and it cites :data:`HIGH_KEEPS`. This module is the package's face.
"""

from ptpcert.procedures.p3964.analysis.analyzer import P3964Analyzer
from ptpcert.procedures.p3964.analysis.causes import HIGH_KEEPS

__all__ = ["HIGH_KEEPS", "P3964Analyzer"]
