"""Readable tables of every representation, for a terminal or a log.

``render`` gives plain text (the same in a pipe, a file and a test). ``show`` prints the same content
as rich tables when stdout is a terminal and the optional ``rich`` package is installed (imported
lazily, only then), and as the plain text otherwise (``io.tables.text``). ``NO_COLOR`` or
``ROBKIN_PLAIN`` in the environment force plain text. Every registered representation
(``robkin.representations.registry``) can be shown; its layout is ``io.tables.views``'s.
"""

from __future__ import annotations

from ...robot import Robot
from ...representations.registry import LiveMapping, by_name, representations
from .text import Block, blocks_text, fmt_num, matrix_text, show_blocks, show_table, text_table, use_rich

__all__ = ["FORMATS", "fmt_num", "text_table", "matrix_text", "render", "show", "show_table", "use_rich"]

#: Representation names accepted by ``render`` (and the CLI's --to), with a one-line description: a
#: live view of the registry (``robkin.representations.registry``).
FORMATS = LiveMapping(lambda: {r.name: r.description for r in representations()})


def blocks(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> list[Block]:
    """The robot in representation ``fmt`` (a key of FORMATS) as tables and text lines.

    ``layout='paper'`` puts a DH table in the conversion paper's n+1-row layout (row 0 is the fixed
    base row) when the base is one DH row. ``degrees`` shows the angle columns of DH, modified DH,
    Hayati and RPY-XYZ tables in degrees. Values within ``views.DISPLAY_ZERO`` of 0 are shown
    as 0, with a note (the display rule; files keep full precision).
    """
    from .views import frames_blocks, table_blocks

    rep = by_name(fmt)  # its converter is imported on first use: only the one asked for
    title = f"{robot.name or 'robot'}: {rep.description}"
    if rep.layout == "frames":
        labels = [f"J{i + 1} ({j.name}, {j.type})" for i, j in enumerate(robot.joints)] + [f"J{robot.n + 1} (tool)"]
        return [title, *frames_blocks(rep.table_of(robot), labels, robot.scale)]
    return table_blocks(rep.table_of(robot), title, layout, degrees, robot.scale)


def render(robot: Robot, fmt: str, layout: str = "robkin", degrees: bool = False) -> str:
    """The robot in representation ``fmt`` (a key of FORMATS) as plain text (see ``blocks``)."""
    return blocks_text(blocks(robot, fmt, layout, degrees))


def show(robot: Robot, fmt: str, layout: str = "robkin", stream=None) -> None:
    """Print the robot in representation ``fmt``: rich tables on a terminal, plain text otherwise."""
    show_blocks(blocks(robot, fmt, layout), stream)


