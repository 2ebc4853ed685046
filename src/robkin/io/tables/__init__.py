"""Tables of a representation, in and out.

- ``terminal``: readable tables for a terminal or a log (``robkin convert`` without ``-o``);
- ``views``: the layout of each table and result type that ``str()`` and the CLI print;
- ``files``: CSV, Markdown and LaTeX at full precision; ``reader``: those CSV files and bare rows back in;
- ``pasted``: bare tables as people paste them from a paper.
"""
