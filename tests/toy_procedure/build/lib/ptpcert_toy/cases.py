"""The toy procedure's conformance suite: one case per rule of its catalogue."""

from __future__ import annotations

from ptpcert.scenario import Expected, Expr, Step, Vector


def _case(profile, cid: str, title: str, rule: str, rules: tuple[str, ...], steps) -> Vector:
    return Vector(id=f"TOY.SUITE.{cid}", title=title, reference="Toy manual §1", rule=rule, group="reply",
                  iut_role="receiver", params=profile.params, steps=tuple(steps), expected=Expected(),
                  rules=rules, procedure="toy", binds=("reply_delay_ms",))


def cases(profile) -> list[Vector]:
    return [
        _case(profile, "ENQ-ACK", "An ENQ is answered with ACK after the reply delay",
              "A station answers every ENQ with ACK one reply delay after it.", ("TOY.REPLY.ACK",),
              [Step("send", b"\x05", note="ENQ"),
               Step("expect", b"\x06", after=Expr("0.5*RDT"), within=Expr("RDT + 4*CHAR"), note="ACK")]),
        _case(profile, "TWO-ENQ", "Two ENQs are answered with two ACKs",
              "A station answers every ENQ with ACK one reply delay after it.", ("TOY.REPLY.ACK",),
              [Step("send", b"\x05\x05", note="ENQ ENQ"),
               Step("expect", b"\x06\x06", within=Expr("RDT + 6*CHAR"), max_gap=Expr("RDT"), note="ACK ACK")]),
        _case(profile, "OTHER-IGNORED", "A character other than ENQ is not answered",
              "A station answers nothing but ENQ.", ("TOY.REPLY.IGNORE",),
              [Step("send", b"\x41", note="A"), Step("silence", duration=Expr("3*RDT"))]),
    ]
