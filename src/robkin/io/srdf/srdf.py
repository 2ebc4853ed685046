"""The ``<disable_collisions>`` elements of an SRDF file, written and read.

Written: ``<robot name=...>`` holding one ``<disable_collisions link1= link2= reason=/>`` per pair, names
quoted (``io.files.xmltext``: input names are untrusted). Read: the file through ``io.files.input_files``
(at most ``MAX_SRDF_BYTES``), parsed without DTDs or entities (``io.trees.xml_parse``); each
``disable_collisions`` must name both links; a missing reason reads as "" (MoveIt's own files often
leave it out). Any other element (groups, states, end effectors) is ignored.
"""

from __future__ import annotations

import os
from typing import Iterable, NamedTuple

from ...errors import InputError, quote
from ..files.xmltext import quoteattr

__all__ = ["srdf_text", "read_srdf", "parse_srdf", "REASONS", "SrdfPair", "MAX_SRDF_BYTES"]

#: MoveIt's reasons for disabling a pair (the Setup Assistant's names).
REASONS = ("Adjacent", "Default", "Always", "Never", "User")
#: Largest SRDF read (a humanoid's is a few hundred kB).
MAX_SRDF_BYTES = 16 * 1024 * 1024


class SrdfPair(NamedTuple):
    """A disabled link pair as the file says it."""

    link1: str
    link2: str
    reason: str


def srdf_text(robot_name: str | None, disabled: Iterable[tuple[str, str, str]], comment: str | None = None) -> str:
    """SRDF text: ``<robot name=...>`` with one ``<disable_collisions>`` per (link1, link2, reason).

    Parameters
    ----------
    robot_name : str or None
        The ``<robot name=...>`` (None: "robot").
    disabled : iterable of (link1, link2, reason)
        The pairs, written in this order (names quoted).
    comment : str, optional
        An XML comment written before ``<robot>`` (``--`` broken up).
    """
    lines = ['<?xml version="1.0" encoding="UTF-8"?>']
    if comment:
        lines.append("<!-- " + comment.replace("--", "- -") + " -->")
    lines.append(f"<robot name={quoteattr(robot_name or 'robot')}>")
    for a, b, reason in disabled:
        lines.append(f"  <disable_collisions link1={quoteattr(a)} link2={quoteattr(b)} reason={quoteattr(reason)}/>")
    lines.append("</robot>")
    return "\n".join(lines) + "\n"


def parse_srdf(text: str, source: str = "<srdf>") -> tuple[str | None, list[SrdfPair]]:
    """(robot name, disabled pairs) of SRDF ``text``; InputError naming ``source`` and the element."""
    from ..trees.xml_parse import _parse_xml

    root = _parse_xml(text, source)
    if root.tag != "robot":
        raise InputError(f"{source}: the root element is <{str(root.tag)[:40]}>, an SRDF's is <robot>")
    out = []
    for k, el in enumerate(root.iter("disable_collisions")):
        a, b = el.get("link1"), el.get("link2")
        if not a or not b:
            raise InputError(f"{source}: disable_collisions[{k}]: needs link1 and link2, got "
                             f"{quote(a)} and {quote(b)}")
        out.append(SrdfPair(a, b, el.get("reason") or ""))
    return root.get("name"), out


def read_srdf(path: str | os.PathLike[str]) -> tuple[str | None, list[SrdfPair]]:
    """(robot name, disabled pairs) of the SRDF file ``path`` (see the module doc)."""
    from ..files.input_files import read_text_file

    return parse_srdf(read_text_file(path, MAX_SRDF_BYTES, "SRDF file"), str(path))
