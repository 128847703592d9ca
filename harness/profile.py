"""The IUT profile: a TOML file describing the implementation under test, like a protocol
conformance statement. Its procedure and parameters, how it can be made to send, which line
conditions it reads, whether it reports STATUS, the setups its command knows, and the
failures expected with their reasons.

```toml
[iut]
procedure = "3964R"              # "3964" | "3964R" | ... (the procedure's own keys follow)
priority = "low"                 # the IUT's own: "low" | "high"
character_delay_ms = 20
acknowledgement_delay_ms = 20
setup_attempts = 6
transmission_attempts = 6
baud_rate = 9600                 # default 9600
data_bits = 8                    # default 8
parity = "even"                  # default "even"
stop_bits = 1                    # default 1
send_trigger = "echo"            # "echo": sends back every block it receives; "none"
line_conditions = "parmrk"       # "parmrk": reads PARMRK marks on exec:/pty:; "none"
status_from_stderr = true        # prints "STATUS 16#XXXX" lines on stderr

[iut.setups]                     # optional: words appended to an exec:/pty: command for the
no_buffer = "--buffer full"      # cases that need the IUT in a special state

[expected_failures]
"3964R.D08.DLE-OTHER" = "known bug #12: NAK sent at once"
```
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .procedure import Procedure, ProcedureError

#: [iut] keys every procedure has
COMMON_REQUIRED = ("procedure", "send_trigger", "line_conditions", "status_from_stderr")
COMMON_CHOICES = {"send_trigger": ("echo", "none"), "line_conditions": ("parmrk", "none")}


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
    from .procedures import PROCEDURES, all_names, by_name

    every = {"iut", "expected_failures"} | {t for p in PROCEDURES for t in p.tables}
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
    allowed = set(COMMON_REQUIRED) | set(proc.profile_keys()) | {"setups"}
    for key in iut:
        if key not in allowed:
            raise ProfileError(where, f"iut.{key}", "unknown key (allowed: " + ", ".join(sorted(allowed)) + ")")
    for key in COMMON_REQUIRED:
        if key not in iut:
            hint = f"one of {', '.join(COMMON_CHOICES[key])}" if key in COMMON_CHOICES else "required"
            raise ProfileError(where, f"iut.{key}", f"missing ({hint})")
    choices = dict(COMMON_CHOICES, send_trigger=getattr(proc, "send_triggers", COMMON_CHOICES["send_trigger"]))
    for key, options in choices.items():
        if iut[key] not in options:
            raise ProfileError(where, f"iut.{key}", f"{iut[key]!r} is not allowed; allowed values: "
                               + ", ".join(f'"{c}"' for c in options))
    if not isinstance(iut["status_from_stderr"], bool):
        raise ProfileError(where, "iut.status_from_stderr", f"{iut['status_from_stderr']!r}: must be true or false")
    own = {k: v for k, v in iut.items() if k not in ("send_trigger", "line_conditions", "status_from_stderr", "setups")}
    tables = {t: raw[t] for t in proc.tables if t in raw}
    for t, v in tables.items():
        if not isinstance(v, dict):
            raise ProfileError(where, t, "must be a table")
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
    xf = raw.get("expected_failures", {})
    if not isinstance(xf, dict) or any(not isinstance(v, str) or not v.strip() for v in xf.values()):
        raise ProfileError(where, "expected_failures", "a table of case id = \"reason\" (each with a reason)")
    return Profile(proc, params, iut["send_trigger"], iut["line_conditions"], iut["status_from_stderr"],
                   dict(xf), dict(setups), where)


def reference_profile(**overrides: Any) -> Profile:
    """The profile matching ``ptpcert iut`` with the given options (tests, self-checks)."""
    base = dict(procedure="3964R", priority="low", character_delay_ms=20,
                acknowledgement_delay_ms=20, setup_attempts=6, transmission_attempts=6,
                send_trigger="echo", line_conditions="parmrk", status_from_stderr=True)
    base.update(overrides)
    xf = base.pop("expected_failures", {})
    return profile_from_dict({"iut": base, "expected_failures": xf})
