"""Chain selection for commands with several inputs: --base-link / --tip-link once, or once per input.

Given once, a link name applies to every robot file among the inputs (documents hold one chain and
ignore it). Given once per input, in the order of the inputs, the k-th value belongs to the k-th input;
``-`` there means "the file's default" (and is what a document takes). This keeps file names out of
the option values, so no path (a Windows drive letter, a colon in a name) is ever split.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from ...errors import InputError

__all__ = ["DEFAULT", "CHAIN_HELP", "add_chain_options", "chain_ends"]

DEFAULT = "-"
CHAIN_HELP = ("once for every robot file, or once per input in input order ('-' = the file's default); "
              "may be any link rigidly attached to the chain's end")
#: = io.DOCUMENT_EXTENSIONS, not imported: robkin.io imports numpy, and this module loads with every command
#: (and the table files of io.TABLE_EXTENSIONS: like a document, a table holds one chain)
_DOCUMENTS = (".yaml", ".yml", ".json", ".csv", ".tsv", ".txt")


def add_chain_options(p: argparse.ArgumentParser) -> None:
    """--base-link / --tip-link that may be repeated, once per input."""
    p.add_argument("--base-link", metavar="LINK", action="append",
                   help="URDF/SDF link or MJCF body/site: first of the serial chain; " + CHAIN_HELP)
    p.add_argument("--tip-link", metavar="LINK", action="append",
                   help="URDF/SDF link or MJCF body/site: last of the chain (the tool); " + CHAIN_HELP)


def _per_input(values: list[str] | None, inputs: list[str], option: str) -> list[str | None]:
    if not values:
        return [None] * len(inputs)
    if len(values) == 1:
        if values[0] != DEFAULT and all(Path(i).suffix.lower() in _DOCUMENTS for i in inputs):
            return [values[0]] * len(inputs)  # no robot file to apply it to: the loader says so
        return [None if Path(i).suffix.lower() in _DOCUMENTS or values[0] == DEFAULT else values[0]
                for i in inputs]
    if len(values) != len(inputs):
        raise InputError(f"{option}: given {len(values)} times for {len(inputs)} inputs; give it once (for every "
                         f"robot file) or once per input, in input order, with '{DEFAULT}' for the default")
    out: list[str | None] = []
    for value, path in zip(values, inputs):
        if value != DEFAULT and Path(path).suffix.lower() in _DOCUMENTS:
            raise InputError(f"{option} '{value}' for {path}: a robot document holds one chain; give '{DEFAULT}' "
                             f"for it")
        out.append(None if value == DEFAULT else value)
    return out


def chain_ends(args: argparse.Namespace, inputs: list[str]) -> list[tuple[str | None, str | None]]:
    """(base link, tip link) for each input, from repeated --base-link / --tip-link options."""
    bases = _per_input(getattr(args, "base_link", None), inputs, "--base-link")
    tips = _per_input(getattr(args, "tip_link", None), inputs, "--tip-link")
    return list(zip(bases, tips))
