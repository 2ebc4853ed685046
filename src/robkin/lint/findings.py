"""A lint finding: severity, where (file, line, element), what is wrong and the fix."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Finding", "SEVERITIES", "ERROR", "WARNING", "INFO"]

#: error: a simulator refuses the file or the physics is wrong; warning: a tool silently changes it or it
#: looks wrong; info: style
ERROR, WARNING, INFO = "error", "warning", "info"
SEVERITIES = (ERROR, WARNING, INFO)


@dataclass(frozen=True)
class Finding:
    """One thing lint found.

    ``code`` is a short stable identifier of the check (``mass-zero-moving``, ``joint-limits-reversed``, ...),
    used by ``--fix`` and as the SARIF rule; ``line`` is 1-based (None where the format keeps no lines);
    ``element`` names the link or joint (``link 'base'``, ``joint 'j1'``) or is empty for the whole file.
    """

    severity: str
    code: str
    file: str
    line: int | None
    element: str
    message: str
    fix: str

    def to_dict(self) -> dict:
        return {"severity": self.severity, "code": self.code, "file": self.file, "line": self.line,
                "element": self.element, "message": self.message, "fix": self.fix}
