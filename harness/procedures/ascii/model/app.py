"""The user program above an ASCII driver: what it does with the frames in the receive
buffer. Pure, like the station.

``echo``: every complete frame in the receive buffer is read (P_RCV_RK), oldest first, but
only while no send job of its own is running, and handed back as one send job with LEN =
the frame's length, end character(s) included; the send side then applies its send variant,
pause and flow control (with "LEN bytes plus automatic end character", ``41 03`` goes out as
``41 03 03``). ``none``: reads every frame and never sends. ``no_read``: never calls
P_RCV_RK, so the buffer fills (a CPU in STOP, a program that forgot to read).

``read_delay`` (seconds): a frame is read only once it has been in the buffer that long (a
slow user program), so the buffer can fill up and flow control can be seen at work.
"""

from __future__ import annotations

from .station import AsciiStation

APPS = ("echo", "none", "no_read")


class AsciiHost:
    """A station plus its application; :meth:`drain` runs the application and returns the
    station's events."""

    def __init__(self, station: AsciiStation, app: str = "echo", *, read_delay: float = 0.0):
        if app not in APPS:
            raise ValueError(f"application {app!r}: allowed values are {', '.join(APPS)}")
        if read_delay < 0:
            raise ValueError("read_delay must not be negative")
        self.station = station
        self.app = app
        self.read_delay = read_delay

    def drain(self, now: float | None = None) -> list:
        """The station's events; the application reads (and echoes) at ``now`` (default:
        the station's own time). A frame that is not due yet asks the station to wake the
        driver when it is."""
        st = self.station
        at = st.now if now is None else now
        out: list = []
        while True:
            events = st.pop_events()
            out.extend(events)
            acted = False
            if self.app != "no_read":
                while st.frames_stored:
                    if self.app == "echo" and st.pending_jobs:
                        break
                    due = st.oldest_stored_at + self.read_delay
                    if due > at + 1e-9:
                        st.wake_at(due)
                        break
                    frame = st.read_frame(at)
                    acted = True
                    if self.app == "echo":
                        st.request_send(at, frame)
            if not events and not acted:
                return out
