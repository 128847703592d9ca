"""The site's reference pages, generated from the code each time the site is built
(``mkdocs build``, ``mkdocs serve``), so that they cannot drift from it.

A plain MkDocs hook (``hooks:`` in ``mkdocs.yml``): it adds the pages to the build's files
(``on_files``) and their entries to the navigation's "Reference" section (``on_config``);
nothing is written into ``docs/``. Every page comes from what ptpcert itself uses:

* ``reference/profile-keys.md``: every key of every registered procedure's profile, from the
  schema that validates profiles (:data:`ptpcert.schema.COMMON` and each
  ``Procedure.profile_schema()``);
* ``reference/cases-NAME.md``: every case and golden vector a run generates for the bundled
  example profile ``NAME`` (:func:`ptpcert.suite.load_suite`), with its group, rules and the
  manual's reference;
* ``reference/status.md``: the STATUS catalogue of Tables 8-1/8-2 (:mod:`ptpcert.status`) and
  RK 512's Table 8-3 (REATEL <-> STATUS, from the RK 512 model's codec);
* ``reference/rules.md``: the rules catalogues (:mod:`ptpcert.rules`);
* ``reference/cli.md``: the ``--help`` of every command, from the parser ``ptpcert`` runs.

A line ``<!-- ptpcert:profile NAME -->`` in any page becomes the text of the bundled example
profile ``NAME`` (``on_page_markdown``), so the guides show the profiles the package ships.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import re
from collections.abc import Callable, Iterator

from mkdocs.structure.files import File

REFERENCE = "Reference"


# -- Markdown helpers ----------------------------------------------------------------------
def cell(text: object) -> str:
    """``text`` as the content of one table cell: Markdown and HTML characters escaped."""
    s = str(text).replace("\\", "\\\\").replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
    for ch in "|*_[]`":
        s = s.replace(ch, "\\" + ch)
    return " ".join(s.split())


def code(text: object) -> str:
    """``text`` as an inline code span in a table cell (a ``|`` escaped for the table)."""
    s = str(text).replace("|", "\\|")
    tick = "``" if "`" in s else "`"
    return f"{tick}{s}{tick}"


def table(head: tuple[str, ...], rows: list[tuple[str, ...]]) -> str:
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def _without_empty(head: tuple[str, ...], rows: list[tuple[str, ...]]) -> tuple[tuple[str, ...], list[tuple[str, ...]]]:
    """``head`` and ``rows`` without the columns that say "-" in every row."""
    keep = [i for i in range(len(head)) if any(r[i] != "-" for r in rows)]
    return tuple(head[i] for i in keep), [tuple(r[i] for i in keep) for r in rows]


def toml_value(v: object) -> str:
    """A value as a profile file writes it."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    return str(v)


GENERATED = ("*Generated from the code when the site was built "
             "(`docs/hooks/generate.py`); do not edit.*\n\n")


# -- the pages -----------------------------------------------------------------------------
def profile_keys() -> str:
    from ptpcert.registry import all_names, procedures
    from ptpcert.schema import COMMON, IDENTITY

    def rows(keys) -> list[tuple[str, ...]]:
        out = []
        for k in keys:
            if k.required:
                default = "required"
            elif k.default is None:
                default = "optional (left out: see the description)"
            else:
                default = code(toml_value(k.default))
            domain = cell(k.domain())
            if k.floor is not None:
                other, by = k.floor
                domain += "; at least " + ", ".join(f"{v} where {other} = {toml_value(o)}" for o, v in by.items())
            when = "; ".join(f"{code(o)} is " + " or ".join(code(toml_value(v)) for v in vs)
                             for o, vs in k.when.items())
            out.append((code(k.path), cell(k.kind), domain, default, when or "always", cell(k.ref) or "-",
                        cell(k.doc)))
        return out

    head = ("key", "kind", "allowed values", "default", "applies where", "manual", "what it says")
    text = ["# Profile keys\n\n", GENERATED,
            "Every key an IUT profile takes, from the schema that checks profiles when they are loaded "
            "(`ptpcert profile --keys PROCEDURE` prints the same list; `ptpcert profile --check FILE` "
            "checks a profile). A key that does not apply (\"applies where\") is still checked for its kind, "
            "and otherwise ignored. Beyond each key's own values, the procedure checks the keys together "
            "(e.g. a timer below the baud rate's minimum) and refuses a profile in one line naming the key.\n\n",
            "## Keys of every procedure\n\n",
            f"`[iut] procedure` selects the procedure: one of "
            + ", ".join(code(toml_value(n)) for n in all_names()) + ". Every procedure's `[iut]` table also has:\n\n",
            table(head, rows(COMMON)),
            "\nThe optional table `[iut.identity]` names the IUT in every report and on the certificate of an "
            "evidence bundle ([Evidence](../evidence.md)):\n\n", table(head, rows(IDENTITY))]
    for proc in procedures():
        names = ", ".join(code(toml_value(n)) for n in proc.names)
        text += [f"\n## {proc.title}\n\n", f"`procedure = {names.replace('`', '')}`"
                 if len(proc.names) == 1 else f"`procedure` is one of {names}", ".\n\n",
                 table(head, rows(proc.profile_schema()))]
    text.append("\n## Setups\n\nThe `[iut.setups]` each procedure's cases may use, and the words the bundled "
                "reference takes for them (`{name}` is replaced by the case's value; what each does: "
                "[IUT interfaces](../iut-interfaces.md#setups)).\n\n")
    text.append(table(("procedure", "setup", "the bundled reference's words"),
                      [(cell(p.title), code(name), code(p.reference_setups.get(name, "-")))
                       for p in procedures() for name in p.setups]))
    text.append("\n## Tables of their own\n\n"
                "`[iut.setups]` names the words appended to an `exec:`/`pty:` command for the cases that need "
                "the IUT in a special state (see [IUT interfaces](../iut-interfaces.md#setups)); "
                "`[expected_failures]` maps a case id to the reason it is expected to fail "
                "(see [Verdicts](../verdicts.md)).\n")
    return "".join(text)


def bundled_profiles() -> list[tuple[str, object]]:
    """(name, path) of every example profile ptpcert ships, by name."""
    from ptpcert.paths import bundled_profiles as where

    return [(f.name[:-5], f) for f in sorted(where().iterdir(), key=lambda f: f.name) if f.name.endswith(".toml")]


def cases_page(name: str, path) -> str:
    from ptpcert.profile import load_profile
    from ptpcert.scenario import load_vector_sets
    from ptpcert.suite import load_suite

    with contextlib.ExitStack() as stack:
        from importlib.resources import as_file
        real = stack.enter_context(as_file(path))
        profile = load_profile(real)
    cases = load_suite(profile, load_vector_sets())
    suite = sum(1 for v in cases if v.id.startswith("SUITE."))
    text = [f"# Cases for {name}.toml\n\n", GENERATED,
            f"Every case a run generates for the bundled profile `{name}` "
            f"({profile.procedure.title}; `ptpcert profile --example {name}` prints it): "
            f"{len(cases)} in all, {suite} of the conformance suite (`SUITE.`) and {len(cases) - suite} golden "
            f"vectors, in the order a run takes them (the manual's groups). Another profile gets the "
            "cases generated for it: `ptpcert rules --profile FILE` lists them.\n\n"]
    groups: dict[str, list] = {}
    for v in cases:
        groups.setdefault(v.group, []).append(v)
    for group, vs in groups.items():
        text.append(f"\n## {group} ({len(vs)})\n\n")
        rows = [(code(v.id), cell(v.title), cell(v.rule), ", ".join(code(r) for r in v.rules) or "-",
                 cell(v.reference), ", ".join(code(r) for r in v.readings) or "-") for v in vs]
        text.append(table(*_without_empty(("id", "title", "rule", "rule ids", "manual", "open points"), rows)))
    return "".join(text)


def status_page() -> str:
    from ptpcert.status import catalogue

    text = ["# STATUS events\n\n", GENERATED,
            f"The {len(catalogue())} events of the CP 341's Tables 8-1 and 8-2 as ptpcert knows them "
            "(`ptpcert status CODE` explains one, `ptpcert status --list` lists them).\n\n"]
    by_class: dict[str, list] = {}
    for e in sorted(catalogue().values(), key=lambda e: e.code):
        by_class.setdefault(f"{e.event_class} {e.class_name}", []).append(e)
    for cls, events in by_class.items():
        text.append(f"\n## Class {cell(cls)}\n\n")
        for e in events:
            text.append(f"### {e.notation} {cell(e.short)}\n\n")
            text.append(f"{cell(e.text)}\n\n")
            text.append(table(("protocols", "reported by", "on the line", "source"),
                              [(cell(", ".join(e.protocols)), cell(e.side), cell(e.wire_observable),
                                cell(e.reference))]))
            if e.remedy:
                text.append(f"\n*Remedy:* {cell(e.remedy)}\n")
            text.append("\n")
    text.append(table_8_3())
    return "".join(text)


def table_8_3() -> str:
    """RK 512's error numbers and the events on both sides (§8.4 Table 8-3), from the model."""
    from ptpcert.procedures.rk512.model.codec import REATEL_STATUS, STATUS_REATEL
    from ptpcert.status import short

    rows = []
    for reatel, code_ in sorted(REATEL_STATUS.items()):
        senders = sorted(c for c, r in STATUS_REATEL.items() if r == reatel)
        rows.append((f"{reatel:02X}h", f"16#{int(code_):04X} {cell(short(code_))}",
                     "; ".join(f"16#{int(c):04X} {cell(short(c))}" for c in senders) or "none of Table 8-1"))
    return ("\n## RK 512: Table 8-3 (REATEL)\n\n"
            "The error number (REATEL) in an RK 512 response frame, the event the requester reports for it, "
            "and the responder's events that make it send that number (§8.4 Table 8-3; "
            "`ptpcert status --reatel HEX` explains one). Any other non-zero number is reported as "
            "16#090E; 00h means no error.\n\n"
            + table(("REATEL", "the requester reports", "the responder sends it for"), rows))


def rules_page() -> str:
    from ptpcert.rules import catalogues

    text = ["# Rules\n\n", GENERATED,
            "The manual's rules as ptpcert's catalogues hold them: each with a stable id, the manual's "
            "section, figure or table, and one sentence. Cases and vectors cite these ids (`rules = [...]`); "
            "`ptpcert rules` prints the traceability matrix (rule -> cases and vectors), `ptpcert rules "
            "--check` what is missing. Procedures without a catalogue of their own cite the manual in each "
            "case (see the case lists).\n\n"]
    for cat in catalogues():
        testable = sum(1 for r in cat if r.testable)
        text.append(f"\n## {cell(cat.title)}\n\n{cell(cat.manual)}: {len(cat)} rules, {testable} testable on "
                    f"the line, {len(cat) - testable} not.\n\n")
        rows = [(code(r.id), cell(r.ref), cell(r.text), cell(r.scope()) or "everywhere",
                 ", ".join(code(a) for a in r.readings) or "-",
                 cell(r.untestable) if r.untestable else "testable") for r in cat]
        text.append(table(("id", "manual", "rule", "applies", "open points", "on the line"), rows))
        if cat.readings:
            text.append("\n### Open points\n\n")
            text.append(table(("point", "question", "the model's reading", "another reading is graded"),
                              [(code(p.id), cell(p.question), cell(p.model), cell(p.grade))
                               for p in cat.readings.values()]))
    return "".join(text)


def commands(parser: argparse.ArgumentParser, prefix: str) -> Iterator[tuple[str, argparse.ArgumentParser]]:
    """``parser`` and every subcommand's parser below it, depth first."""
    yield prefix, parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from commands(sub, f"{prefix} {name}")


def cli_page() -> str:
    from ptpcert.cli import build_parser

    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"      # the same wrapping on every machine
    try:
        text = ["# Command line\n\n", GENERATED,
                "The `--help` of every `ptpcert` command, as the installed command prints it.\n\n"]
        for name, parser in commands(build_parser(), "ptpcert"):
            buf = io.StringIO()
            parser.print_help(buf)
            text.append(f"\n## {name}\n\n```text\n{buf.getvalue().rstrip()}\n```\n")
    finally:
        if old is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = old
    return "".join(text)


def pages() -> list[tuple[str, str, Callable[[], str]]]:
    """(title in the navigation, path under docs/, maker) of every generated page."""
    out = [("Profile keys", "reference/profile-keys.md", profile_keys)]
    for name, path in bundled_profiles():
        out.append((f"Cases: {name}", f"reference/cases-{name}.md", lambda n=name, p=path: cases_page(n, p)))
    out += [("STATUS events and Table 8-3", "reference/status.md", status_page),
            ("Rules", "reference/rules.md", rules_page),
            ("Command line", "reference/cli.md", cli_page)]
    return out


# -- MkDocs events -------------------------------------------------------------------------
#: a line ``<!-- ptpcert:profile NAME -->`` in a page becomes the bundled profile NAME's text
_PROFILE_MARK = re.compile(r"^<!-- ptpcert:profile ([a-z0-9-]+) -->$", re.M)


def on_page_markdown(markdown, page, config, files):
    """The bundled example profiles a page shows, as the package ships them."""
    found = dict(bundled_profiles())

    def text(m: re.Match) -> str:
        name = m.group(1)
        if name not in found:
            raise ValueError(f"{page.file.src_uri}: no bundled profile {name!r} (known: {', '.join(found)})")
        body = found[name].read_text(encoding="utf-8").rstrip()
        return f"```toml\n# conformance/profiles/{name}.toml\n{body}\n```"
    return _PROFILE_MARK.sub(text, markdown)


def on_config(config):
    """Every generated page not yet in the navigation joins its "Reference" section."""
    nav = config.get("nav")
    if nav is None:
        return config
    section = next((e for e in nav if isinstance(e, dict) and REFERENCE in e), None)
    if section is None:
        section = {REFERENCE: []}
        nav.append(section)
    listed = {next(iter(e.values())) if isinstance(e, dict) else e for e in section[REFERENCE]}
    for title, uri, _ in pages():
        if uri not in listed:
            section[REFERENCE].append({title: uri})
    return config


def on_files(files, config):
    for _, uri, make in pages():
        files.append(File.generated(config, uri, content=make()))
    return files
