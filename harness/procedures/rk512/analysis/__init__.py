"""RK 512's part of line analysis (``ptpcert analyze``, ``ptpcert monitor``).

The link below RK 512 is 3964(R) (§2.2.1; §2.2.3: every RK 512 frame is the user data of one
3964(R) block), and it is judged exactly as a stand-alone 3964(R) link is
(:class:`~ptpcert.procedures.p3964.analysis.P3964Analyzer`). On top of it, a *frame layer*
judges what the frames say: every block that a seat's model station took from the partner
(the seat's DLE accepted it) and every block of the seat that the partner accepted is one RK
512 frame, fed to two probes built from the model's own RK 512 layer, so the analysis and the
model cannot disagree. The STATUS events of classes 05, 06, 09 and 0A the probes raise are
what a CP 341 in the seat raises (reported with every exchange). :class:`Rk512Analyzer` is
made of:

* :mod:`~ptpcert.procedures.rk512.analysis.analyzer` - the analyzer: 3964's, with model
  stations that carry the seat's frame layer, the link's events handed to it, and the
  exchange labels;
* :mod:`~ptpcert.procedures.rk512.analysis.frames` - one seat's frame layer: what the line
  shows of its frames, fed to its probes, the frames it owes and their deadlines, and a line
  joined while requests may be open;
* :mod:`~ptpcert.procedures.rk512.analysis.judging` - the seat's responses, continuation
  commands and commands judged against what its probes say it owes;
* :mod:`~ptpcert.procedures.rk512.analysis.replays` - the alternatives before a difference in
  the frames stands (a condition the line does not show, another reading of an open point,
  T_RES at the edge of its tolerance), and the header check of a command;
* :mod:`~ptpcert.procedures.rk512.analysis.probe` - the probes: the model's RK 512 layer fed
  what the line shows, and a seat's memory as the line sees it.

This module is the package's face: the procedure's description builds :class:`Rk512Analyzer`
from here.
"""

from ptpcert.procedures.rk512.analysis.analyzer import Rk512Analyzer

__all__ = ["Rk512Analyzer"]
