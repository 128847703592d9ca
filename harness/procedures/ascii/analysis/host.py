"""What ASCII line analysis knows of a station's application, and the model station it drives.

Neither an ASCII station's send jobs nor its application's reads of the receive buffer are on
the line (§2.2.4). :class:`AsciiAnalysisHost` pairs a seat's model station with what the
analysis knows of its application: whether it sends back every frame it reads (the echo
convention of ``ptpcert run``), and which frames the model took as read "at once" since the
line last showed a read, which an XOFF from the seat puts back
(:meth:`AsciiAnalysisHost.unread`). :class:`AnalysisReadings` is what the analysis takes where
the line does not say: the model's readings of the manual's open points and a few of its own
(:data:`DEFAULT`, the usual ones).

Here too is the little the analysis does to a model station besides feeding it the partner's
characters: :func:`advance` brings it to an instant, :func:`send_flow` has it send an XON or
XOFF once more, :func:`would_be_full` says whether the frames put back fill its buffer to a
threshold; and its transmitter's FIFO after the partner's XOFF (at most
:data:`MAX_AFTER_XOFF` characters, logged with :data:`AFTER_XOFF_WHY`). The analyzer
(:mod:`~ptpcert.procedures.ascii.analysis.analyzer`), its local events and its causes import
this module; it imports none of them.
"""

from __future__ import annotations

from dataclasses import dataclass

from ptpcert.procedures.ascii.model import AsciiStation
from ptpcert.procedures.ascii.model.readings import READINGS, AsciiReadings
from ptpcert.procedures.ascii.model.records import Why
from ptpcert.procedures.ascii.model.table import FcState

#: how many characters a sender may still send after the partner's XOFF: what its UART's
#: transmit FIFO holds (a 16550A: 16). The manual gives no number (reading Q15).
MAX_AFTER_XOFF = 16


@dataclass(frozen=True)
class AnalysisReadings:
    """What an analysis takes where the line does not say: the model's readings of the
    manual's open points (``model``), and two of its own.

    ``a_reads_at_once``: an echo station's application reads a frame as soon as it is stored
    (True: the echo that follows later was held back by the send side); by default (False) it
    reads when its echo shows it. ``a_fixed_length_job_is_one_frame``: under the fixed-length
    criterion a send job carries one frame of the fixed length (§2.2.4: "the partner's
    configured length must equal LEN"), so N characters back to back begin a new job, held
    back by the pause; the other reading takes any run of characters as one job."""

    model: AsciiReadings = READINGS
    a_reads_at_once: bool = False
    a_fixed_length_job_is_one_frame: bool = True
    #: reading Q15 (no field of the model's: it sends XON and XOFF once): a station holding
    #: its partner repeats its XOFF while the partner keeps sending (True), or not (False)
    a_xoff_repeated: bool = False


DEFAULT = AnalysisReadings()


class AsciiAnalysisHost:
    """A model station and what the analysis knows of its application (see
    :mod:`~ptpcert.procedures.ascii.analysis.events`): ``echo`` - it sends back every frame it
    reads; the frames read "at once" since the line last showed a read (``tentative``), which
    an XOFF puts back."""

    def __init__(self, station: AsciiStation, echo: bool, readings: AnalysisReadings, *, own_jobs: bool = True):
        self.station = station
        self.echo = echo
        #: the application may hand over frames of its own as well (False: the suite's IUT
        #: interface, which sends back what it receives and nothing else)
        self.own_jobs = own_jobs
        self.readings = readings
        #: reads every frame as soon as it is stored (an application that does not echo,
        #: until an XOFF shows it did not)
        self.at_once = not echo or readings.a_reads_at_once
        #: (stored at, frame, read at)
        self.tentative: list[tuple[float, bytes, float]] = []
        #: the frames it read to send back: (time, frame), the latest few
        self.echoes: list[tuple[float, bytes]] = []

    def drain(self, now: float | None = None) -> list:
        st = self.station
        at = st.now if now is None else max(now, st.now)
        out: list = []
        while True:
            events = st.pop_events()
            out.extend(events)
            acted = False
            # never while it holds its partner: the read that lifts an XOFF sends XON, and
            # when that happened the line shows (the XON)
            if self.at_once and st.fc_state is FcState.OPEN:
                while st.frames_stored and st.fc_state is FcState.OPEN and not (self.echo and st.pending_jobs):
                    stored_at = st.oldest_stored_at
                    frame = st.read_frame(at)
                    acted = True
                    if self.echo:
                        self._send_back(at, frame)
                    else:
                        self.tentative.append((stored_at, frame, at))
            if not events and not acted:
                return out

    def read(self, t: float) -> bytes | None:
        """The application reads the oldest frame at ``t`` (and echoes it)."""
        st = self.station
        frame = st.read_frame(t)
        if frame is not None and self.echo:
            self._send_back(t, frame)
        return frame

    def _send_back(self, t: float, frame: bytes) -> None:
        self.echoes = self.echoes[-3:] + [(t, frame)]
        self.station.request_send(t, frame)

    def is_echo(self, payload: bytes) -> bool:
        return any(f == payload for _, f in self.echoes)

    @property
    def echo_at(self) -> float:
        """When it last read a frame to send it back (-1: not since the model began)."""
        return self.echoes[-1][0] if self.echoes else -1.0

    def unread(self, t: float) -> None:
        """The line showed that the application has not read the frames the model read "at
        once" since the last read the line showed: they go back into the receive buffer
        (oldest first), and the model sends XOFF if that reaches a threshold. From here on
        it reads only what the line shows."""
        st = self.station
        advance(st, t)
        # the model's receive buffer, put back as it was (the station keeps no other record)
        for stored_at, frame, _ in reversed(self.tentative):
            st._stored.appendleft((stored_at, frame))
            st._stored_bytes += len(frame)
        self.tentative = []
        self.at_once = False
        st._full_check()


def advance(st: AsciiStation, t: float) -> None:
    """Bring the model station ``st`` to ``t`` as an input at ``t`` does (its deadlines before ``t`` run
    out first): no characters received."""
    st.receive(t, b"")


def send_flow(st: AsciiStation, t: float, code: int) -> None:
    """The station sends the flow-control character ``code`` once more (reading Q15's
    other side: the model itself sends each only once)."""
    advance(st, t)
    st._send_control(code)


def would_be_full(host: AsciiAnalysisHost) -> bool:
    """With the frames read "at once" put back, would the buffer reach a threshold (§2.2.4
    'data flow control': the buffered frames reach the parameter, or 50 characters before the
    1024-byte buffer overflows; reading Q14)?"""
    st = host.station
    r = st.readings
    frames = st.frames_stored + len(host.tentative)
    fill = st.buffer_fill + sum(len(f) for _, f, _ in host.tentative)
    return frames >= max(1, st.params.buffer_frames + r.q14_xoff_frame_offset) or fill >= r.q14_xoff_fill_bytes


#: the record of why the transmitter sent a character it still held when the partner's XOFF came
#: (the model's own records say why it sends everything else)
AFTER_XOFF_WHY = Why("tx", "STOPPED", "FIFO", "after_xoff",
                     "§2.2.4 'data flow control': the characters the transmitter held when the XOFF came")
