"""MkDocs hook: the command-line reference, generated from robkin's argparse parsers.

A page holding the line ``<!-- robkin-cli-reference -->`` gets, in its place, ``robkin --help`` and
every command's ``--help`` exactly as the command line prints them, so the reference cannot drift
from the parsers.
"""

from __future__ import annotations

import argparse
import os
from typing import Any

MARKER = "<!-- robkin-cli-reference -->"


def cli_reference() -> str:
    """Markdown: one section per command with its --help text."""
    from robkin.cli import build_parser

    os.environ["COLUMNS"] = "100"  # argparse wraps at the terminal width: the same page on every machine
    parser = build_parser()
    parts = ["## robkin", "", "```text", parser.format_help().rstrip(), "```", ""]
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, p in sub.choices.items():
        parts += [f"## robkin {name}", "", "```text", p.format_help().rstrip(), "```", ""]
    return "\n".join(parts)


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    if MARKER not in markdown:
        return markdown
    return markdown.replace(MARKER, cli_reference())
