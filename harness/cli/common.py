"""What the commands of the command line share: the argument parser that reports a usage
error in one line, bounded numeric options, reading the profile with a one-line error, and the
time stamp of a report."""

from __future__ import annotations

import argparse
import datetime as _dt
import math
import sys


class Parser(argparse.ArgumentParser):
    """argparse with a usage error on ONE line naming the option and what is allowed (exit
    2), instead of the usage block and a second line."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: {message}; see {self.prog} --help\n")


def number(kind: type, lo: float, hi: float | None, unit: str = ""):
    """An argparse type: a finite ``kind`` (int or float) in [lo, hi] (hi None: no upper
    bound); the error names the range."""
    span = f"from {lo:g} to {hi:g}" if hi is not None else f"{lo:g} or more"
    allowed = f"allowed: {'an integer' if kind is int else 'a number'} {span}" + (f" {unit}" if unit else "")

    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not a number ({allowed})") from None
        if not math.isfinite(value) or value < lo or (hi is not None and value > hi):
            raise argparse.ArgumentTypeError(f"{text!r} is out of range ({allowed})")
        return value
    parse.__name__ = kind.__name__   # argparse names the type in its own messages
    return parse


def load_profile(cmd: str, path):
    """The IUT profile, or None after telling why it is bad (the caller exits 2)."""
    from ptpcert.profile import ProfileError
    from ptpcert.profile import load_profile as read

    try:
        return read(path)
    except ProfileError as exc:
        print(f"ptpcert {cmd}: bad profile: {exc}", file=sys.stderr)
        return None


def now() -> str:
    """The time now, local, to the second (ISO 8601), for reports."""
    return _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds")
