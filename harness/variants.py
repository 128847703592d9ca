"""The kit every procedure's broken variants are written with: their registrar and table patching.

A broken variant (a :class:`ptpcert.procedure.Mutant`) is a procedure's reference station
with one rule of the manual broken. Each procedure keeps its variants in a module or
package of its own (``ptpcert.procedures.<procedure>.mutants``) and hands them out through
its description's ``mutants()``; this module is the procedure-neutral part they share:

* :func:`registrar` makes the ``@mutant(name, rule, **profile)`` class decorator that enters
  each variant, in the order written, into the mapping the procedure exposes as ``MUTANTS``;
* :func:`patched` copies a transition table (state -> input -> row) with some rows replaced,
  which is how a variant breaks a rule that lives in a table row rather than in a hook.

It sits beside :mod:`ptpcert.procedure` in the neutral core and knows no procedure.
"""

from __future__ import annotations

from typing import Any, Callable, Hashable, Mapping, MutableMapping

from ptpcert.procedure import Mutant

__all__ = ["patched", "registrar"]


def registrar(into: MutableMapping[str, Mutant], *, prefix: str = "Mutant_",
              make: Callable[[type], Callable[..., Any]] | None = None) -> Callable[..., Callable[[type], type]]:
    """The ``@mutant(name, rule, **profile)`` class decorator of one procedure's variants.

    Each decorated station class is renamed ``prefix + name`` (dashes as underscores, so
    that traces and reprs show which variant runs) and entered into ``into`` under ``name``
    as ``Mutant(name, rule, make(cls), profile)``; ``make`` turns the class into the
    ``make(params, name=...)`` factory of the :class:`Mutant` and is the class itself by
    default. ``profile`` holds the profile settings under which the broken rule shows. A
    name entered twice is an error: one variant would silently hide the other.
    """
    def mutant(name: str, rule: str, **profile: Any) -> Callable[[type], type]:
        def register(cls: type) -> type:
            if name in into:
                raise ValueError(f"two broken variants are named {name!r}")
            cls.__name__ = prefix + name.replace("-", "_")
            into[name] = Mutant(name, rule, cls if make is None else make(cls), profile)
            return cls
        return register
    return mutant


def patched(table: Mapping[Hashable, Mapping[Hashable, Any]],
            rows: Mapping[tuple[Hashable, Hashable], Any]) -> dict:
    """A copy of a transition table (state -> input -> row) with the rows of ``rows``
    (``(state, input) -> row``) put in; the table itself is left as it is."""
    out = {state: dict(by_input) for state, by_input in table.items()}
    for (state, inp), row in rows.items():
        out[state][inp] = row
    return out
