"""Sending (§2.2.4 'sending'; Fig. 2-20; Table 6-2): the pause between frames, the three
send variants of the end-character criterion and the lengths. The IUT sends what it
receives back (the echo convention), or the jobs of the send_job setup."""

from __future__ import annotations

import math

from ptpcert.procedures.ascii.model import send_bytes

from ._build import case, data, echoes, expect, frame_of, h, no_flow, quiet_flow, receive_case, send, silence

REF = "§2.2.4 'sending'"
VARIANT = {"up_to_end": ("UP-TO-END", "up to and including the end character", "the data up to and including the "
                         "first end character(s) goes out"),
           "len_with_end": ("LEN-WITH-END", "exactly LEN bytes, the last being the end character",
                            "exactly the LEN bytes go out"),
           "len_append_end": ("APPEND-END", "LEN bytes plus the end character(s)",
                              "the LEN bytes go out followed by the end character(s)")}


def _job(jobs: list[bytes]) -> tuple[str, dict]:
    return ("send_job", {"jobs": ",".join(j.hex().upper() if j else "-" for j in jobs)})


def cases(p):
    out = []
    crit = p.end_criterion
    if p.pauses_between_frames and quiet_flow(p):
        if crit == "cdt":
            # the second frame must be waiting while the first one's echo is still going out
            n = math.ceil((1.5 * p.cdt + 0.1) / p.char_time) + 4
            if n <= 900:
                f1, f2 = data(p, n), data(p, 2, 3)
                out.append(receive_case(
                    p, "TX.PAUSE", "The next frame sent waits for more than the CDT", REF + " (end criterion CDT)",
                    "With the CDT criterion the driver holds the next frame back until more than the CDT has passed "
                    "since the last one was sent.",
                    [send(f1, mark=True, note="a long frame: its echo still goes out when the next one is complete"),
                     send(f2, at="1.5*CDT", note="the next frame"),
                     expect(f1, after="CDT", within="2*CDT + 10*CHAR", since="mark", note="the first echo"),
                     expect(f2, after="CDT + CHAR", within="3*CDT + 20*CHAR",
                            note="the second echo: after more than the CDT of idle line")],
                    [f1, f2], group="send", role="both", echo=False, readings=["Q5"]))
        else:
            a, b = frame_of(p, 0), frame_of(p, 0, 7)
            out.append(receive_case(
                p, "TX.PAUSE", "The next frame sent waits for the CDT", REF + " (end criterion fixed length)",
                "With the fixed-length criterion the driver keeps a pause of the CDT between two frames it sends.",
                [send(a, mark=True), send(b),
                 expect(a, within="CDT + 10*CHAR", since="mark", note="the first echo, at once"),
                 expect(b, after="CDT + CHAR", within="3*CDT + 20*CHAR",
                        note="the second echo: after a pause of the CDT")],
                [a, b], group="send", role="both", echo=False, readings=["Q5"]))
    if crit == "end_chars":
        name, what, rule = VARIANT[p.send_variant]
        f = data(p, 3) + p.end_sequence
        wire = send_bytes(f, p)
        steps = [send(f)]
        if quiet_flow(p):
            steps += [expect(wire, within="CDT + 10*CHAR", note="the echo as the send variant puts it on the line"),
                      silence("3*CDT", note="nothing more")]
        v = receive_case(p, f"TX.VARIANT-{name}", f"Send variant '{what}'", REF + " (end criterion end character)",
                         f"A send job of LEN bytes with the variant '{what}': {rule}.", steps, [f], group="send",
                         role="both", echo=not quiet_flow(p))
        out.append(v)
        if p.send_variant == "up_to_end":
            job = data(p, 2) + p.end_sequence + data(p, 2, 5)
            out.append(case(
                p, "TX.UP-TO-END-CUTS", "Variant 'up to the end character': what follows it is not sent",
                REF + " (end criterion end character, variant 1)",
                "With the variant 'up to and including the end character' the data after the end character is not "
                "sent, even when LEN is larger.",
                "send", "sender", [expect(send_bytes(job, p), after="-1*STARTUP", within="STARTUP",
                                          note="the job " + job.hex(" ").upper()),
                                   silence("3*CDT", note="the rest of the job is not sent")],
                requires=(), setup=_job([job])))
        if no_flow(p):
            big = data(p, 1024 - len(p.end_chars)) + p.end_sequence
            out.append(receive_case(p, "TX.LEN-1024", "A frame of 1024 bytes is received and sent back whole",
                                    "§2.2.4; Table 6-2 LEN 1..1024; Table A-7",
                                    "The longest frame, 1024 bytes with its end character(s), is received and sent back "
                                    "without a gap inside.", [send(big)], [big], group="send", role="both",
                                    timing_sensitive=True))
    if crit == "cdt":
        one = data(p, 1)
        out.append(receive_case(p, "TX.LEN-1", "A frame of one byte", "Table 6-2 LEN 1..1024; " + REF,
                                "The shortest job, LEN 1, is sent.", [send(one)], [one], group="send", role="both"))
    ok = frame_of(p, 2, 9)
    # LEN 1025 fits two codes of the manual: 16#1E41 (Table 8-2, byte count in LEN outside
    # 1..1024) and 16#0517 (Table 8-1, transmission length over 1 KB): either is accepted
    for n, label, codes, ref in ((0, "0", "16#1E41", ""), (1025, "1025", "16#1E41|16#0517", "; Table 8-1 (05)17H")):
        out.append(case(
            p, f"TX.LEN-{label}-REFUSED", f"A send job of LEN {label} is refused",
            "Table 6-2 LEN; Table 8-2 (1E)41H" + ref,
            f"LEN must be 1..1024: a job outside is refused with {codes.replace('|', ' or ')}, nothing of it is "
            "sent, and the next job goes out.", "send", "sender",
            [expect(send_bytes(ok, p), after="-1*STARTUP", within="STARTUP", note="the next job"), silence("3*CDT")],
            status=[codes], requires=(), setup=_job([data(p, n, 3), ok])))
    return out


__all__ = ["cases", "h", "echoes"]
