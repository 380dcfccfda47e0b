"""Exceptions raised by geardyn.

Every user-facing error names the item (field, link, gear pair, ...) and the rule it breaks, so
that a user can fix the configuration without reading a traceback.
"""

from __future__ import annotations


class GeardynError(Exception):
    """Base class of all geardyn errors."""


class ConfigError(GeardynError, ValueError):
    """A configuration (TOML file or Python objects) breaks one or more rules.

    ``problems`` holds one human-readable message per broken rule, each naming the item.
    """

    def __init__(self, problems: list[str] | str, source: str | None = None) -> None:
        if isinstance(problems, str):
            problems = [problems]
        self.problems = list(problems)
        self.source = source
        head = f"invalid configuration{f' {source}' if source else ''}"
        if len(self.problems) == 1:
            msg = f"{head}: {self.problems[0]}"
        else:
            msg = head + ":\n" + "\n".join(f"  - {p}" for p in self.problems)
        super().__init__(msg)

    def __reduce__(self) -> tuple:
        """Pickled as its problems and source (an error raised in a worker process reaches
        the caller unchanged)."""
        return (type(self), (self.problems, self.source))


class KinematicsError(GeardynError, ValueError):
    """The mechanism graph cannot be analysed (e.g. a gear pair without a unique carrier)."""


class InputError(GeardynError, ValueError):
    """Inputs given to an analysis are inconsistent with the model (e.g. do not fix the motion)."""
