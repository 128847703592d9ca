"""The ASCII driver's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

Each judged seat is followed by the reference model of the ASCII driver (§2.2.4), fed the
other seat's characters. What an ASCII station puts on its line is its own frames (its send
jobs) and, with XON/XOFF flow control, the XON and XOFF of its receiver; neither the send
jobs nor the application's reads of the receive buffer are on the line, so the seat's
characters reveal them. :class:`AsciiAnalyzer` is made of:

* :mod:`~ptpcert.procedures.ascii.analysis.analyzer` - the analyzer itself: timing, the model
  stations of each seat, the alternatives to try before a difference stands, the description
  of a seat's characters as frames;
* :mod:`~ptpcert.procedures.ascii.analysis.events` - the local events the seat's characters
  reveal (a send job and its frame read ahead from the line, a read of the receive buffer,
  the characters its transmitter held after the partner's XOFF, a restart);
* :mod:`~ptpcert.procedures.ascii.analysis.causes` - why the model sends each character
  (rule, reference, STATUS code, timing window) and what a character the model does not send
  breaks;
* :mod:`~ptpcert.procedures.ascii.analysis.host` - the model station with what the analysis
  knows of its application (echo, reads "at once"), and the readings the analysis takes
  where the line does not say.

What a line tap cannot show, and is not judged: the application's reads (only inferred from
the line), the contents of the receive buffer (a CP 341 in each seat raises, and each
finding and exchange carries, the STATUS events of its model: 16#0806, 16#080C,
16#080A...), the modem lines (RTS/CTS and the automatic use of the V.24 signals are not
judged), and the send jobs' data beyond what was sent (a job the driver cut after its end
character looks like two jobs: see the tests' NOT_VISIBLE_ON_THE_WIRE).

This module is the package's face: the procedure's description builds :class:`AsciiAnalyzer`
from here.
"""

from ptpcert.procedures.ascii.analysis.analyzer import AsciiAnalyzer
from ptpcert.procedures.ascii.analysis.host import DEFAULT, MAX_AFTER_XOFF, AnalysisReadings, AsciiAnalysisHost

__all__ = ["AsciiAnalyzer", "AsciiAnalysisHost", "AnalysisReadings", "DEFAULT", "MAX_AFTER_XOFF"]
