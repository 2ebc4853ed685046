"""The registry of representations: each one declared once, every reader, writer and view iterates it.

A :class:`Representation` says everything the code around the converters needs: its CLI name
(``poe-body``), its document section (``poe_body``), how it is described, where its converters and
table class live (dotted strings, imported on first use: ``import robkin`` and a ``robkin convert
--to dh`` import none of the other representation modules), its columns (document key, header, LaTeX
header, kind), its layout family and the file formats it can be written in. A new representation is
one module and one :func:`register` call; a new table of an existing layout (a ``LinkTable``
subclass: rows, base, tool) then appears in ``robkin convert --to``, documents, table files, ``check``,
the GUI and the plots without further code.

Layouts (how a section, a text table and a table file are laid out; each has its code in io):

- ``link-table``: n rows of the columns, ``base`` and ``tool`` transforms (DH, modified DH, Hayati);
- ``screws``: n screws (wx .. vz) and the home pose ``M`` (PoE, space or body frame);
- ``rpy``: n + 2 rows (world -> base, one per joint, tool) of roll, pitch, yaw, x, y, z;
- ``frames``: the GJD's n + 1 frames.

This module imports nothing heavy (it loads with every CLI command).
"""

from __future__ import annotations

import importlib
from typing import Any, Callable, Iterator, Mapping, NamedTuple, Sequence

__all__ = ["Column", "Representation", "register", "unregister", "representations", "names", "sections",
           "overlays", "by_name", "by_section", "of_table", "LAYOUTS", "FILE_FORMATS", "LiveNames"]

LAYOUTS = ("link-table", "screws", "rpy", "frames")
#: Every file format a representation may be written in: table files and robot documents.
FILE_FORMATS = ("csv", "markdown", "latex", "yaml", "json")


#: (module, name) -> the object, imported on first use by ``Representation._attr``
_ATTRIBUTES: dict[tuple[str, str], Any] = {}


class Column(NamedTuple):
    """One column of a representation's rows (a named tuple: defining a frozen dataclass costs ~0.9 ms of
    start-up, a named tuple ~0.1 ms, and this module loads with every ``robkin convert``).

    Attributes
    ----------
    key : str
        Its key in a document row (``a``).
    header : str
        Its header in text tables and table files (``a(i-1)`` for modified DH).
    latex : str
        Its LaTeX header (``$a_{i-1}$``).
    kind : {'length', 'angle', 'unit'}
        A length (robot units); an angle (radians: degrees with ``--degrees``, ``k*pi/m`` with
        ``--pi``); or a unitless direction component (rounded like an angle, never converted).
    symbol : str
        Its header in the GUI's tables, in Unicode (``α(i-1)``); empty: ``header``.
    """

    key: str
    header: str
    latex: str
    kind: str = "length"
    symbol: str = ""

    @property
    def angle(self) -> bool:
        return self.kind == "angle"

    @property
    def label(self) -> str:
        """Its header in the GUI (``symbol``, else ``header``)."""
        return self.symbol or self.header


class Representation(NamedTuple):
    """One representation as the registry knows it (see the module; a named tuple, as ``Column``:
    ``representation._replace(name=...)`` makes a variant).

    Attributes
    ----------
    name : str
        CLI name (``--to``, ``--from``, ``plot --overlay``): ``poe-body``.
    section : str
        Document section key: ``poe_body``.
    description : str
        One line (``io.tables.terminal.FORMATS``, the title of the printed table).
    title : str
        Short title of a table file (``"<robot>: <title>"``).
    layout : str
        One of LAYOUTS.
    module : str
        Module defining the converters and the table class (``robkin.representations.poe``).
    from_robot, to_robot : str
        Names in ``module``: robot -> table (called with ``from_robot_args`` after the robot) and
        table -> robot (``to_robot(table, name=...)``).
    table_class : str or None
        Name in ``module`` of the table class (None: the GJD, whose "table" is the frames).
    columns : tuple of Column
        The rows' columns.
    from_robot_args : tuple
        Extra positional arguments of ``from_robot`` (the PoE's frame).
    file_formats : tuple of str
        Formats it can be written in (of FILE_FORMATS).
    frame_based : bool
        Its rows are frames on the joint axes (DH, modified DH, Hayati): the robot remembers them,
        rows carry the links' masses, a flipped joint subtracts q.
    paper_layout : bool
        A section of n + 1 rows without ``base`` is the conversion paper's layout (row 0: the base).
    tool_label : str
        How the printed table calls its tool transform.
    mass_frame : str
        The frame its mass properties are in, as the line under the printed mass table says it.
    help : str
        Its entry in ``robkin convert --help`` (continuation lines as they are indented there).
    overlay_label : str or None
        Legend of its rebuilt robot in ``robkin plot --overlay`` and the GUI (None: not offered).
    gui_title : str
        Heading of its section in the GUI (empty: ``title``).
    document_rank : int
        Documents hold sections in increasing rank (which section defines the GJD when several do).
    gui_mass_frame : str
        The frame of its mass properties as the GUI's caption says it (empty: ``mass_frame``).
    gui_overlay : str or None
        Text of its overlay checkbox in the GUI: empty for ``overlay_label``, None for no checkbox
        (the GJD: the GUI always draws the robot as given). Without ``overlay_label``, no checkbox.
    download_label : str
        Text of its download button in the GUI (empty: ``name``); only representations written as
        YAML have one.
    download_rank : int
        The GUI's download buttons are in increasing rank (then registration order).
    """

    name: str
    section: str
    description: str
    title: str
    layout: str
    module: str
    from_robot: str
    to_robot: str
    table_class: str | None
    columns: tuple[Column, ...]
    from_robot_args: tuple[Any, ...] = ()
    file_formats: tuple[str, ...] = FILE_FORMATS
    frame_based: bool = False
    paper_layout: bool = False
    tool_label: str = "tool"
    mass_frame: str = "link frame {i} (after joint i, on axis i+1)"
    help: str = ""
    overlay_label: str | None = None
    gui_title: str = ""
    document_rank: int = 1000
    gui_mass_frame: str = ""
    gui_overlay: str | None = ""
    download_label: str = ""
    download_rank: int = 1000

    def _attr(self, name: str) -> Any:
        key = (self.module, name)
        if key not in _ATTRIBUTES:
            _ATTRIBUTES[key] = getattr(importlib.import_module(self.module), name)
        return _ATTRIBUTES[key]

    def table_of(self, robot: Any) -> Any:
        """The robot in this representation (its table object; the GJD: the frames)."""
        return self._attr(self.from_robot)(robot, *self.from_robot_args)

    def robot_of(self, table: Any, name: str | None = None) -> Any:
        """The Robot of one of this representation's tables."""
        return self._attr(self.to_robot)(table, name=name)

    def table_type(self) -> type:
        """The table class (imported now)."""
        if self.table_class is None:
            raise TypeError(f"{self.name} has no table class")
        return self._attr(self.table_class)

    def is_table(self, table: Any) -> bool:
        """Whether ``table`` is one of this representation's tables, without importing its module (a
        table of a class whose module is not loaded cannot exist)."""
        import sys

        mod = sys.modules.get(self.module)
        if mod is None or self.table_class is None or not isinstance(table, getattr(mod, self.table_class)):
            return False
        frame = getattr(table, "frame", None)  # the PoE class holds both frames
        return frame is None or not self.from_robot_args or frame == self.from_robot_args[0]

    @property
    def keys(self) -> tuple[str, ...]:
        """The document row keys of the columns."""
        return tuple(c.key for c in self.columns)

    @property
    def headers(self) -> tuple[str, ...]:
        """The text and file headers of the columns."""
        return tuple(c.header for c in self.columns)

    @property
    def angle_keys(self) -> tuple[str, ...]:
        return tuple(c.key for c in self.columns if c.angle)


_REGISTRY: dict[str, Representation] = {}


def register(rep: Representation) -> Representation:
    """Add a representation (after those registered before it); ValueError if its name or section
    is taken or its layout unknown. Returns it."""
    if rep.layout not in LAYOUTS:
        raise ValueError(f"{rep.name}: layout '{rep.layout}' is not one of {', '.join(LAYOUTS)}")
    if rep.name in _REGISTRY or any(r.section == rep.section for r in _REGISTRY.values()):
        raise ValueError(f"representation '{rep.name}' (section '{rep.section}') is already registered")
    bad = [f for f in rep.file_formats if f not in FILE_FORMATS]
    if bad:
        raise ValueError(f"{rep.name}: file format(s) {', '.join(bad)} not among {', '.join(FILE_FORMATS)}")
    _REGISTRY[rep.name] = rep
    return rep


def unregister(name: str) -> None:
    """Remove a registered representation (a test's toy one)."""
    del _REGISTRY[name]


def representations() -> tuple[Representation, ...]:
    """Every representation, in registration (CLI) order."""
    return tuple(_REGISTRY.values())


def names(file_format: str | None = None) -> tuple[str, ...]:
    """CLI names, in registration order (only those writable as ``file_format``, if given)."""
    return tuple(r.name for r in _REGISTRY.values() if file_format is None or file_format in r.file_formats)


def sections() -> tuple[str, ...]:
    """Document section keys, in document order."""
    return tuple(r.section for r in sorted(_REGISTRY.values(), key=lambda r: r.document_rank))


def overlays() -> tuple[Representation, ...]:
    """Representations offered as plot/GUI overlays (an ``overlay_label``): the GJD (the robot as
    given) first, then the others in registration order."""
    offered = [r for r in _REGISTRY.values() if r.overlay_label is not None]
    return tuple(sorted(offered, key=lambda r: r.layout != "frames"))


def by_name(name: str) -> Representation:
    """The representation of a CLI name; KeyError if none."""
    return _REGISTRY[name]


def by_section(section: str) -> Representation:
    """The representation of a document section; KeyError if none."""
    for r in _REGISTRY.values():
        if r.section == section:
            return r
    raise KeyError(section)


def of_table(table: Any) -> Representation:
    """The representation a table object belongs to; TypeError if none."""
    matches = [r for r in _REGISTRY.values() if r.is_table(table)]
    # a subclass of a registered table (a toy DH table) is its own representation's first
    exact = [r for r in matches if r.table_class == type(table).__name__]
    if exact or matches:
        return (exact or matches)[0]
    raise TypeError(f"no registered representation for {type(table).__name__}")


class LiveNames(Sequence[str]):
    """A tuple-like view of registry names, read on each use (so a registered representation shows
    in the module constants built on it: ``SECTIONS``, ``TABLE_INPUTS``, ...)."""

    def __init__(self, read: Callable[[], tuple[str, ...]]) -> None:
        self._read = read

    def __getitem__(self, i: Any) -> Any:
        return self._read()[i]

    def __len__(self) -> int:
        return len(self._read())

    def __iter__(self) -> Iterator[str]:
        return iter(self._read())

    def __contains__(self, x: object) -> bool:
        return x in self._read()

    def __eq__(self, other: object) -> bool:
        return tuple(self) == (tuple(other) if isinstance(other, (tuple, list, LiveNames)) else other)

    def __hash__(self) -> int:
        return hash(self._read())

    def __add__(self, other: Sequence[str]) -> tuple[str, ...]:
        return self._read() + tuple(other)

    def __repr__(self) -> str:
        return repr(self._read())


class LiveMapping(Mapping[str, Any]):
    """A dict-like view ``key -> value`` over the registry, read on each use."""

    def __init__(self, read: Callable[[], dict[str, Any]]) -> None:
        self._read = read

    def __getitem__(self, key: str) -> Any:
        return self._read()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._read())

    def __len__(self) -> int:
        return len(self._read())

    def __repr__(self) -> str:
        return repr(self._read())


def _columns(*spec: tuple[str, ...]) -> tuple[Column, ...]:
    return tuple(Column(*c) for c in spec)


_DH = _columns(("a", "a", "$a_i$", "length"), ("d", "d", "$d_i$", "length"),
               ("alpha", "alpha", r"$\alpha_i$", "angle", "α"), ("theta", "theta", r"$\theta_i$", "angle", "θ"))
_SCREWS = _columns(*((c, c, fr"$\omega_{c[1]}$", "unit", "ω" + c[1]) for c in ("wx", "wy", "wz")),
                   *((c, c, f"$v_{c[1]}$", "length") for c in ("vx", "vy", "vz")))
_MODULE = "robkin.representations."

#: Today's representations, in today's CLI order; ``document_rank`` gives the document order
#: (gjd, dh, mdh, hayati, rpy_xyz, poe, poe_body).
BUILTIN = (
    Representation(
        "dh", "dh", "standard Denavit-Hartenberg table (+ base and residual tool)", "standard DH", "link-table",
        frame_based=True,
        module=_MODULE + "dh", from_robot="dh_from_robot", to_robot="robot_from_dh", table_class="DHTable",
        columns=_DH, paper_layout=True, tool_label="tool (residual T_t)",
        help="standard DH table (+ base, + residual tool)", overlay_label="DH",
        gui_title="Standard DH  A = Rz(θ) Tz(d) Tx(a) Rx(α)", document_rank=1,
        gui_mass_frame="frame {i} (after joint i)", download_label="DH", download_rank=1),
    Representation(
        "mdh", "mdh", "modified (Craig) Denavit-Hartenberg table (+ base and tool)", "modified (Craig) DH",
        "link-table", frame_based=True,
        module=_MODULE + "mdh", from_robot="mdh_from_robot", to_robot="robot_from_mdh", table_class="MDHTable",
        columns=_columns(("a", "a(i-1)", "$a_{i-1}$", "length"), ("d", "d", "$d_i$", "length"),
                         ("alpha", "alpha(i-1)", r"$\alpha_{i-1}$", "angle", "α(i-1)"),
                         ("theta", "theta", r"$\theta_i$", "angle", "θ")),
        mass_frame="link frame {i} (on joint i's axis, where link i starts; Craig)",
        help="modified (Craig) DH table", overlay_label="modified DH",
        gui_title="Modified DH  A = Rx(α) Tx(a) Rz(θ) Tz(d)", document_rank=2,
        gui_mass_frame="frame {i} (on joint i's axis, where link i starts)", download_label="MDH",
        download_rank=2),
    Representation(
        "hayati", "hayati", "Hayati's parameters: DH with beta about y between nearly parallel axes (+ base and "
        "tool)", "Hayati", "link-table", frame_based=True,
        module=_MODULE + "hayati", from_robot="hayati_from_robot", to_robot="robot_from_hayati",
        table_class="HayatiTable", columns=_DH + _columns(("beta", "beta", r"$\beta_i$", "angle", "β")),
        help="Hayati's parameters: DH with a tilt beta about y instead of d between nearly parallel\n"
             "            axes (exact and short there, the calibration standard)",
        gui_title="Hayati  A = Rz(θ) Tz(d) Tx(a) Rx(α) Ry(β)", document_rank=3,
        gui_mass_frame="frame {i} (after joint i)", download_label="Hayati", download_rank=6),
    Representation(
        "poe", "poe", "Product of Exponentials, space frame (M and screws)", "PoE (space frame)", "screws",
        module=_MODULE + "poe", from_robot="poe_from_robot", to_robot="robot_from_poe", table_class="PoE",
        columns=_SCREWS, from_robot_args=("space",), mass_frame="the robot base frame at q = 0",
        help="Product of Exponentials, space frame", overlay_label="DH rebuilt from PoE (space)",
        gui_title="PoE, space frame  T = exp(S1 q1)…exp(Sn qn) M", document_rank=5,
        gui_mass_frame="the base frame at home", gui_overlay="DH from PoE", download_label="PoE",
        download_rank=3),
    Representation(
        "poe-body", "poe_body", "Product of Exponentials, body frame (M and screws)", "PoE (body frame)", "screws",
        module=_MODULE + "poe", from_robot="poe_from_robot", to_robot="robot_from_poe", table_class="PoE",
        columns=_SCREWS, from_robot_args=("body",), mass_frame="the home tool frame M",
        help="PoE, body frame", overlay_label="DH rebuilt from PoE (body)",
        gui_title="PoE, body frame  T = M exp(B1 q1)…exp(Bn qn)", document_rank=6,
        gui_mass_frame="the tool frame M at home", gui_overlay=None, download_label="PoE body",
        download_rank=4),
    Representation(
        "rpy-xyz", "rpy_xyz", "RPY-XYZ table, n+2 rows (world->base, joints, tool)", "RPY-XYZ", "rpy",
        module=_MODULE + "rpy_xyz", from_robot="rpy_from_robot", to_robot="robot_from_rpy", table_class="RPYTable",
        columns=_columns(*((c, c, c, "angle") for c in ("roll", "pitch", "yaw")),
                         *((c, c, f"${c}$", "length") for c in ("x", "y", "z"))),
        mass_frame="joint i's frame (the frame row i leads to, which joint i moves)",
        help="RPY-XYZ table, n+2 rows (URDF convention)", overlay_label="RPY-XYZ",
        gui_title="RPY-XYZ (URDF joint origins)", document_rank=4,
        gui_mass_frame="joint i's frame", download_label="RPY-XYZ", download_rank=5),
    Representation(
        "gjd", "gjd", "Global Joint Description: n+1 frames in the base frame at q = 0",
        "Global Joint Description (frames at q = 0)", "frames",
        module=_MODULE + "gjd", from_robot="gjd_from_robot", to_robot="robot_from_gjd", table_class=None,
        columns=_columns(*((f"m{r}{c}", f"m{r}{c}", f"$m_{{{r}{c}}}$", "length" if c == 4 else "unit")
                           for r in (1, 2, 3) for c in (1, 2, 3, 4))),
        help="Global Joint Description frames", overlay_label="as given (GJD frames)",
        gui_title="GJD: joint frames at home, in the base frame", document_rank=0,
        gui_overlay=None, download_label="GJD", download_rank=7),
)

for _rep in BUILTIN:
    register(_rep)
