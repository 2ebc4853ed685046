"""Error messages in the caller's vocabulary: one mechanism instead of one message per front end.

The library names an option the way a Python caller writes it, as a keyword followed by ``=``:
``tip_link='tool0' is not below base_link='base_link'``, ``pick the chain's end with tip_link=``.
A front end renders those names in its own words with ``render_options``: the CLI turns
``tip_link=`` into ``--tip-link`` (from its parsers' option names), the GUI into its field labels.
"""

from __future__ import annotations

import re
from typing import Mapping

__all__ = ["render_options"]

#: a keyword and its '=' (not '==', not part of a longer name, a dotted field or an XML attribute)
_KEYWORD = re.compile(r"(?<![\w.\-])([a-z][a-z0-9_]*)=(?![=\"])(True(?!\w))?")


def render_options(message: str, names: Mapping[str, str]) -> str:
    """``message`` with every ``keyword=`` found in ``names`` replaced by its name there.

    A value right after it is kept, separated by a space (``tip_link='x'`` -> ``--tip-link 'x'``),
    except ``True``: a switch turned on is its name alone (``allow_xacro=True`` -> ``--allow-xacro``).
    Keywords not in ``names`` are left as they are.
    """
    def one(m: re.Match[str]) -> str:
        name = names.get(m.group(1))
        if name is None:
            return m.group(0)
        if m.group(2):  # a switch: allow_xacro=True -> --allow-xacro
            return name
        following = message[m.end():m.end() + 1]
        return name + (" " if following and following not in " ,;:.)/" else "")

    return _KEYWORD.sub(one, message)
