"""Findings as text (one line each, ``file:line: severity: element: message; fix: ...``), JSON (a list of
objects) and SARIF 2.1.0 (one run, a rule per check code, results with physical locations)."""

from __future__ import annotations

import json
from typing import Sequence

from .findings import Finding

__all__ = ["as_text", "as_json", "as_sarif"]

_SARIF_LEVEL = {"error": "error", "warning": "warning", "info": "note"}
SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"


def as_text(findings: Sequence[Finding]) -> str:
    lines = []
    for f in findings:
        where = f"{f.file}:{f.line}" if f.line else f.file
        elem = f" {f.element}:" if f.element else ""
        lines.append(f"{where}: {f.severity}:{elem} {f.message}; fix: {f.fix}")
    return "\n".join(lines) + ("\n" if lines else "")


def as_json(findings: Sequence[Finding]) -> str:
    return json.dumps([f.to_dict() for f in findings], indent=2) + "\n"


def as_sarif(findings: Sequence[Finding], version: str = "") -> str:
    codes = sorted({f.code for f in findings})
    rules = [{"id": c, "name": c, "shortDescription": {"text": c.replace("-", " ")}} for c in codes]
    results = []
    for f in findings:
        region = {"startLine": f.line} if f.line else {}
        location = {"physicalLocation": {"artifactLocation": {"uri": f.file.replace("\\", "/")},
                                         **({"region": region} if region else {})}}
        if f.element:
            location["logicalLocations"] = [{"name": f.element}]
        results.append({"ruleId": f.code, "ruleIndex": codes.index(f.code), "level": _SARIF_LEVEL[f.severity],
                        "message": {"text": f"{f.element + ': ' if f.element else ''}{f.message}. Fix: {f.fix}"},
                        "locations": [location]})
    doc = {"$schema": SARIF_SCHEMA, "version": "2.1.0",
           "runs": [{"tool": {"driver": {"name": "robkin lint", "informationUri": "https://github.com/robkin",
                                         **({"version": version} if version else {}), "rules": rules}},
                     "results": results}]}
    return json.dumps(doc, indent=2) + "\n"
