"""Tables of a representation, in and out.

- ``text``: the generic blocks every printed table is made of (plain text, rich on a terminal);
- ``terminal``: readable tables for a terminal or a log (``robkin convert`` without ``-o``);
- ``views``: the layout of each representation's table that ``str()`` and the CLI print;
- ``files``: CSV, Markdown and LaTeX at full precision; ``reader``: those CSV files and bare rows back in;
- ``pasted``: bare tables as people paste them from a paper.
"""
