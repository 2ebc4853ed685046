"""A measurement report as one HTML file that stands alone: text blocks, tables and PNG pictures
embedded as base64 data URLs (no scripts, no external files).

Every text from the input (file names, joint names, report lines) is escaped (``html.escape``), so a
hostile name stays text.
"""

from __future__ import annotations

import base64
import html
from typing import Sequence, Union

__all__ = ["Section", "html_report"]

#: A section: (heading, content) where content is preformatted text (str), a picture (PNG bytes) or a
#: table (a header row and rows of cells, all str).
Section = tuple[str, Union[str, bytes, tuple[Sequence[str], Sequence[Sequence[str]]]]]

_STYLE = """body{font-family:system-ui,sans-serif;margin:2em auto;max-width:62em;color:#222}
h1{font-size:1.4em}h2{font-size:1.1em;margin-top:1.6em;border-bottom:1px solid #ccc}
pre{background:#f6f6f6;padding:.8em;white-space:pre-wrap;font-size:.85em}
table{border-collapse:collapse;font-size:.85em}td,th{border:1px solid #ccc;padding:.2em .5em;text-align:right}
th{background:#eee}img{max-width:100%}"""


def html_report(title: str, sections: Sequence[Section]) -> str:
    """The HTML text of a report: a title and its sections (see ``Section``)."""
    e = html.escape
    out = ["<!DOCTYPE html>", "<html lang=\"en\"><head><meta charset=\"utf-8\">",
           f"<title>{e(title)}</title><style>{_STYLE}</style></head><body>", f"<h1>{e(title)}</h1>"]
    for heading, content in sections:
        out.append(f"<h2>{e(heading)}</h2>")
        if isinstance(content, bytes):
            data = base64.b64encode(content).decode("ascii")
            out.append(f"<img alt=\"{e(heading)}\" src=\"data:image/png;base64,{data}\">")
        elif isinstance(content, str):
            out.append(f"<pre>{e(content)}</pre>")
        else:
            head, rows = content
            out.append("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in head) + "</tr>")
            out += ["<tr>" + "".join(f"<td>{e(c)}</td>" for c in row) + "</tr>" for row in rows]
            out.append("</table>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"
