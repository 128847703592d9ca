"""The IUT profile: a TOML file describing the implementation under test, like a protocol
conformance statement. Its procedure and parameters, how it can be made to send, which line
conditions it reads, whether it reports STATUS, the setups its command knows, and the
failures expected with their reasons.

```toml
[iut]
procedure = "NAME"               # one of the names a procedure answers to (ptpcert run --help)
# ... the procedure's own [iut] keys: timers, attempts, line settings ...
send_trigger = "echo"            # "echo": sends back every block it receives; "none"
line_conditions = "parmrk"       # "parmrk": reads PARMRK marks on exec:/pty:; "none"
status_from_stderr = true        # prints "STATUS 16#XXXX" lines on stderr
timer_tolerance_ms = 0           # optional: how late the IUT's own timers may act (declared)

[iut.identity]                   # optional: which IUT this is (shown in every report)
vendor = "ACME"                  # vendor, product, version, serial, text: free text each

[iut.setups]                     # optional: words appended to an exec:/pty: command for the
name = "--words"                 # cases that need the IUT in a special state

# ... the procedure's own tables ...

[expected_failures]
"CASE.ID" = "known bug #12: the reason"
```
The procedure's description (:class:`ptpcert.procedure.Procedure`) reads its own keys and
tables; this module reads the rest.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from . import schema
from .procedure import Procedure, ProcedureError

#: [iut] keys every procedure has
COMMON_REQUIRED = ("procedure", "send_trigger", "line_conditions", "status_from_stderr")
COMMON_CHOICES = {"send_trigger": ("echo", "none"), "line_conditions": ("parmrk", "none")}
#: [iut] keys every procedure may have
COMMON_OPTIONAL = ("timer_tolerance_ms", "setups", "identity")
#: the largest timer tolerance a profile may declare (ms)
MAX_TIMER_TOLERANCE_MS = 60_000


class ProfileError(ValueError):
    def __init__(self, path: str, key: str, message: str):
        self.path, self.key = path, key
        super().__init__(f"{path}: {key}: {message}" if key else f"{path}: {message}")


@dataclass(frozen=True)
class Profile:
    procedure: Procedure
    params: Any
    send_trigger: str = "echo"
    line_conditions: str = "parmrk"
    status_from_stderr: bool = True
    expected_failures: dict[str, str] = field(default_factory=dict)
    #: name -> words appended to the exec:/pty: command for the cases that need that setup
    setups: dict[str, str] = field(default_factory=dict)
    path: str = ""
    #: the accuracy the vendor declares for the IUT's own timers (ms): how much later than
    #: due an output that a timer of the IUT causes may come. It widens only the late side
    #: of windows that end on an IUT timer, on top of the harness's own tolerance.
    timer_tolerance_ms: float = 0.0
    #: ``[iut.identity]``: vendor, product, version, serial, text (those given)
    identity: dict[str, str] = field(default_factory=dict)

    @property
    def echo(self) -> bool:
        return self.send_trigger == "echo"

    @property
    def line(self):
        return self.procedure.line(self.params)

    def to_dict(self) -> dict[str, Any]:
        return {
            **self.procedure.profile_dict(self.params),
            "send_trigger": self.send_trigger, "line_conditions": self.line_conditions,
            "status_from_stderr": self.status_from_stderr,
            "timer_tolerance_ms": self.timer_tolerance_ms,
            "setups": dict(self.setups), "expected_failures": dict(self.expected_failures),
        }


def _is_device(path: str | Path) -> bool:
    import stat
    try:
        mode = Path(path).stat().st_mode
    except OSError:
        return False
    return stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISSOCK(mode)


def read_toml(path: str | Path, what: str, error) -> dict[str, Any]:
    """A TOML file as a dict; every way it can be unreadable is one clear error."""
    where = str(path)
    try:
        if _is_device(path):   # /dev/zero would be read for ever
            raise error(where, "", f"is a device, not a {what} file")
        data = Path(path).read_bytes()
    except FileNotFoundError:
        raise error(where, "", "no such file") from None
    except IsADirectoryError:
        raise error(where, "", f"is a directory, not a {what} file") from None
    except OSError as exc:
        raise error(where, "", f"cannot be read: {exc.strerror}") from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise error(where, "", f"is not UTF-8 text (byte {exc.start}); save the {what} as UTF-8") from None
    if text.startswith("\ufeff"):
        text = text[1:]
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise error(where, "", f"not valid TOML: {exc}") from None


def load_profile(path: str | Path) -> Profile:
    return profile_from_dict(read_toml(path, "profile", ProfileError), str(path))


def profile_from_dict(raw: dict[str, Any], where: str = "<profile>") -> Profile:
    from ptpcert.registry import all_names, by_name, procedures

    every = {"iut", "expected_failures"} | {t for p in procedures() for t in p.tables}
    unknown_tables = sorted(set(raw) - every)
    if unknown_tables:
        raise ProfileError(where, unknown_tables[0], "unknown table or key (allowed: "
                           + ", ".join(f"[{t}]" for t in sorted(every)) + ")")
    iut = raw.get("iut")
    if not isinstance(iut, dict):
        raise ProfileError(where, "iut", "missing table [iut]")
    name = iut.get("procedure")
    if name is None:
        raise ProfileError(where, "iut.procedure", "missing (one of " + ", ".join(all_names()) + ")")
    try:
        proc = by_name(name)
    except ProcedureError as exc:
        raise ProfileError(where, "iut.procedure", str(exc).split(": ", 1)[1]) from None
    allowed_tables = {"iut", "expected_failures", *proc.tables}
    foreign = sorted(set(raw) - allowed_tables)
    if foreign:
        raise ProfileError(where, foreign[0], f"not a table of a {proc.title} profile (allowed: "
                           + ", ".join(f"[{t}]" for t in sorted(allowed_tables)) + ")")
    allowed = set(COMMON_REQUIRED) | set(proc.profile_keys()) | set(COMMON_OPTIONAL)
    for key in iut:
        if key not in allowed:
            raise ProfileError(where, f"iut.{key}", "unknown key (allowed: " + ", ".join(sorted(allowed)) + ")")
    for key in COMMON_REQUIRED:
        if key not in iut:
            hint = f"one of {', '.join(COMMON_CHOICES[key])}" if key in COMMON_CHOICES else "required"
            raise ProfileError(where, f"iut.{key}", f"missing ({hint})")
    choices = dict(COMMON_CHOICES, send_trigger=proc.send_triggers)
    for key, options in choices.items():
        if iut[key] not in options:
            raise ProfileError(where, f"iut.{key}", f"{iut[key]!r} is not allowed; allowed values: "
                               + ", ".join(f'"{c}"' for c in options))
    if not isinstance(iut["status_from_stderr"], bool):
        raise ProfileError(where, "iut.status_from_stderr", f"{iut['status_from_stderr']!r}: must be true or false")
    timer_tol = iut.get("timer_tolerance_ms", 0)
    if isinstance(timer_tol, bool) or not isinstance(timer_tol, (int, float)) \
            or not 0 <= timer_tol <= MAX_TIMER_TOLERANCE_MS:
        raise ProfileError(where, "iut.timer_tolerance_ms", f"{timer_tol!r}: must be a number of milliseconds "
                           f"from 0 to {MAX_TIMER_TOLERANCE_MS}")
    own = {k: v for k, v in iut.items()
           if k not in ("send_trigger", "line_conditions", "status_from_stderr") + COMMON_OPTIONAL}
    tables = {t: raw[t] for t in proc.tables if t in raw}
    for t, v in tables.items():
        if not isinstance(v, dict):
            raise ProfileError(where, t, "must be a table")
    for key in proc.profile_schema():   # every key's value against the schema; together below
        table = iut if key.table == "iut" else tables.get(key.table, {})
        if key.name not in table:
            if key.required:
                raise ProfileError(where, key.path, schema.missing(key))
            continue
        why = schema.problem(key, table[key.name])
        if why:
            raise ProfileError(where, key.path, why)
    try:
        params = proc.params_from_profile(own, tables)
    except ProcedureError as exc:
        raise ProfileError(where, exc.key, str(exc).split(": ", 1)[-1] if exc.key else str(exc)) from None
    setups = iut.get("setups", {})
    if not isinstance(setups, dict) or any(not isinstance(v, str) for v in setups.values()):
        raise ProfileError(where, "iut.setups", "a table of setup name = \"words appended to the IUT command\"")
    for name_ in setups:
        if name_ not in proc.setups:
            raise ProfileError(where, f"iut.setups.{name_}", "unknown setup (known for "
                               f"{proc.title}: {', '.join(proc.setups) or 'none'})")
        if not setups[name_].strip():
            raise ProfileError(where, f"iut.setups.{name_}", "must not be empty")
        problem = _setup_problem(setups[name_], proc.reference_setups.get(name_, ""))
        if problem:
            raise ProfileError(where, f"iut.setups.{name_}", problem)
    identity = _identity(iut.get("identity", {}), where)
    xf = raw.get("expected_failures", {})
    if not isinstance(xf, dict) or any(not isinstance(v, str) or not v.strip() for v in xf.values()):
        raise ProfileError(where, "expected_failures", "a table of case id = \"reason\" (each with a reason)")
    return Profile(proc, params, iut["send_trigger"], iut["line_conditions"], iut["status_from_stderr"],
                   dict(xf), dict(setups), where, float(timer_tol), identity)


def _identity(table: Any, where: str) -> dict[str, str]:
    """``[iut.identity]`` checked key by key against :data:`ptpcert.schema.IDENTITY`."""
    if not isinstance(table, dict):
        raise ProfileError(where, "iut.identity", "must be a table ([iut.identity] with "
                           + ", ".join(k.name for k in schema.IDENTITY) + ")")
    keys = {k.name: k for k in schema.IDENTITY}
    for name in table:
        if name not in keys:
            raise ProfileError(where, f"iut.identity.{name}", "unknown key (allowed: " + ", ".join(keys) + ")")
        why = schema.problem(keys[name], table[name])
        if why:
            raise ProfileError(where, f"iut.identity.{name}", why)
    return {k: table[k] for k in keys if k in table and table[k].strip()}



def _placeholders(words: str) -> list[str]:
    """The ``{name}`` placeholders of a setup's words (ValueError where braces do not pair)."""
    import string
    return [f for _, f, _, _ in string.Formatter().parse(words) if f is not None]


def _setup_problem(words: str, reference: str) -> str | None:
    """What is wrong with a setup's words, checked when the profile loads rather than as
    errors of the cases that use it: braces that do not pair, a placeholder the cases do not
    fill in (those of the bundled reference's words for the setup), a quote not closed."""
    import shlex
    try:
        used = _placeholders(words)
    except ValueError as exc:
        return f"{words!r}: the braces of its placeholders do not pair ({exc}); write {{name}}, or {{{{ for a brace"
    known = _placeholders(reference) if reference else []
    for name in used:
        if name not in known:
            filled = ", ".join("{" + k + "}" for k in known) or "none"
            return f"{words!r}: the cases fill in no placeholder {{{name}}} (they fill in: {filled})"
    try:
        shlex.split(words)
    except ValueError as exc:
        return f"{words!r}: the words cannot be split as a shell would ({exc})"
    return None
