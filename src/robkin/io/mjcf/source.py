"""An MJCF file as one XML tree: ``<include>`` resolved, ``<compiler>`` settings and ``<default>`` classes read.

Input files are untrusted. An ``<include file>`` is a relative path, resolved against the folder of the
main model file (as MuJoCo resolves every include, nested ones too). One that leads outside that folder
(``../franka_assets/assets.xml`` in gymnasium-robotics' Franka kitchen, a symbolic link leading out) is
read only when it names an ``.xml`` file, and said once, in one warning line for all of them. Absolute
paths, other files outside the folder, loops, more than ``MAX_INCLUDE_DEPTH`` levels, more than
``MAX_INCLUDES`` files and more than ``MAX_BYTES`` in all are refused with one line naming the file and
the include. XML text given as a string cannot include anything.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ...errors import InputError
from ..files.input_files import read_text_file

__all__ = ["MjcfSource", "read_mjcf_source", "MAX_BYTES", "MAX_INCLUDES", "MAX_INCLUDE_DEPTH"]

#: Largest MJCF read, all included files together. Menagerie's largest models are a few hundred kB;
#: this only stops accidental or hostile huge inputs.
MAX_BYTES = 64 * 1024 * 1024
#: Included files at most (robosuite/Menagerie models use a handful), and nesting depth at most.
MAX_INCLUDES = 256
MAX_INCLUDE_DEPTH = 8
#: The element kinds whose attributes ``<default>`` classes carry and that this reader uses.
DEFAULTED = ("joint", "site", "geom", "mesh", "material")
#: Known ``<compiler eulerseq>`` letters; lower case rotate with the frame, upper case stay fixed.
EULER_LETTERS = set("xyzXYZ")


@dataclass
class MjcfSource:
    """The resolved XML tree of an MJCF model and the settings that shape its kinematics.

    Attributes
    ----------
    root : Element
        The ``<mujoco>`` element with every ``<include>`` replaced by the children of the included
        file's top element (``<mujoco>``, ``<mujocoinclude>`` or any other name, as MuJoCo does).
    source : str
        The main file's name, for messages.
    degrees : bool
        ``<compiler angle>``: True (MuJoCo's default) when angles in the file are degrees.
    eulerseq : str
        ``<compiler eulerseq>``, three of x y z X Y Z (default "xyz").
    autolimits : bool
        ``<compiler autolimits>`` (default True): a ``range`` alone makes a joint limited.
    defaults : dict
        Class name -> element kind ("joint", "site", "geom", "mesh", "material") -> attributes, with
        inheritance applied; the top-level class is "main".
    folder : Path or None
        The main file's folder (None for text input): mesh files are looked up inside it.
    meshdir : str
        ``<compiler meshdir>`` (else ``assetdir``), the folder of mesh files relative to ``folder``.
    """

    root: Any
    source: str
    degrees: bool = True
    eulerseq: str = "xyz"
    autolimits: bool = True
    defaults: dict[str, dict[str, dict[str, str]]] = field(default_factory=dict)
    folder: Path | None = None
    meshdir: str = ""

    def angle(self, value: float) -> float:
        """An angle of the file in radians."""
        return math.radians(value) if self.degrees else value


def _parse(text: str, source: str, included: bool = False) -> Any:
    """The root element of an MJCF file. An included file's top element may have any name (MuJoCo
    drops it and inserts its children; older models name it ``<mujocoinclude>``)."""
    from ..trees.xml_parse import _parse_xml  # xml.etree with any DTD refused first, shared with the URDF reader

    root = _parse_xml(text, source)
    if root.tag != "mujoco" and not included:
        hint = {"robot": " (this is a URDF: give it the extension .urdf)",
                "sdf": " (this is an SDF model: give it the extension .sdf)",
                "mujocoinclude": " (this file is meant for <include file> in a model: load the model that "
                                 "includes it)"}.get(root.tag, "")
        raise InputError(f"{source}: root element is <{root.tag}>; an MJCF file has <mujoco>{hint}")
    return root


class _Includes:
    """Resolves ``<include>`` elements in place, within the limits above."""

    def __init__(self, folder: Path | None, used: int):
        self.folder = folder.resolve() if folder is not None else None
        self.total = used
        self.count = 0
        self.outside: list[str] = []  # includes read from outside the model's folder, as written

    def expand(self, root: Any, where: str, stack: tuple[Path, ...]) -> None:
        # iterative walk: an element tree nested thousands deep must not exhaust Python's stack
        todo = [root]
        while todo:
            el = todo.pop()
            children = list(el)
            for i, child in enumerate(children):
                if child.tag == "include":
                    parts = self._load(child, where, stack)
                    el.remove(child)
                    pos = list(el).index(children[i + 1]) if i + 1 < len(children) else len(el)
                    for k, part in enumerate(parts):
                        el.insert(pos + k, part)
                else:
                    todo.append(child)

    def _load(self, el: Any, where: str, stack: tuple[Path, ...]) -> list[Any]:
        name = el.get("file")
        if not name:
            raise InputError(f"{where}: <include> has no file attribute")
        if self.folder is None:
            raise InputError(f"{where}: <include file=\"{name}\"> needs the model as a file (its folder "
                             f"holds the included files); text input cannot include")
        if os.path.isabs(name) or name.startswith(("/", "\\")) or ":" in name:
            raise InputError(f"{where}: <include file=\"{name}\">: only paths relative to the model's folder "
                             f"are read, not absolute ones")
        path = (self.folder / name).resolve()
        if not path.is_relative_to(self.folder):
            if path.suffix.lower() != ".xml":
                raise InputError(f"{where}: <include file=\"{name}\"> leads outside the model's folder "
                                 f"{self.folder} to a file that is not .xml; outside it only .xml files are read")
            if name not in self.outside:
                self.outside.append(name)
        if path in stack:
            raise InputError(f"{where}: <include file=\"{name}\"> includes itself (loop through "
                             f"{' -> '.join(p.name for p in stack)} -> {path.name})")
        if len(stack) > MAX_INCLUDE_DEPTH:
            raise InputError(f"{where}: <include file=\"{name}\"> nests more than {MAX_INCLUDE_DEPTH} levels deep")
        if not path.is_file():
            raise InputError(f"{where}: <include file=\"{name}\">: no such file in the model's folder")
        self.count += 1
        if self.count > MAX_INCLUDES:
            raise InputError(f"{where}: more than {MAX_INCLUDES} included files")
        self.total += path.stat().st_size
        if self.total > MAX_BYTES:
            raise InputError(f"{where}: <include file=\"{name}\">: the model and its includes exceed {MAX_BYTES} bytes")
        text = read_text_file(path, MAX_BYTES, "an MJCF file")
        sub = _parse(text, str(path), included=True)
        if "<include" in text:
            self.expand(sub, str(path), stack + (path,))
        return list(sub)


def _defaults(root: Any, source: str) -> dict[str, dict[str, dict[str, str]]]:
    """Class name -> kind -> attributes, each class inheriting its enclosing class's attributes."""
    out: dict[str, dict[str, dict[str, str]]] = {"main": {k: {} for k in DEFAULTED}}
    todo = [(el, "main", True) for el in root.findall("default")]
    while todo:
        el, parent, top = todo.pop(0)
        name = el.get("class") or ("main" if top else None)
        if name is None:
            raise InputError(f"{source}: a nested <default> has no class attribute")
        if name != "main" and name in out:
            raise InputError(f"{source}: <default class=\"{name}\"> is defined twice")
        mine = out.setdefault(name, {k: dict(v) for k, v in out[parent].items()})
        for child in el:
            if child.tag in DEFAULTED:
                mine[child.tag].update(child.attrib)
            elif child.tag == "default":
                todo.append((child, name, False))
    return out


def _compiler(src: MjcfSource) -> None:
    for el in src.root.findall("compiler"):
        angle = el.get("angle")
        if angle is not None:
            if angle not in ("degree", "radian"):
                raise InputError(f"{src.source}: <compiler angle=\"{angle}\">: expected degree or radian")
            src.degrees = angle == "degree"
        seq = el.get("eulerseq")
        if seq is not None:
            if len(seq) != 3 or not set(seq) <= EULER_LETTERS:
                raise InputError(f"{src.source}: <compiler eulerseq=\"{seq}\">: expected three of x y z X Y Z "
                                 f"(lower case: rotating axes, upper case: fixed axes)")
            src.eulerseq = seq
        meshdir = el.get("meshdir") or (el.get("assetdir") if not src.meshdir else None)
        if meshdir is not None:
            src.meshdir = meshdir
        auto = el.get("autolimits")
        if auto is not None:
            if auto not in ("true", "false"):
                raise InputError(f"{src.source}: <compiler autolimits=\"{auto}\">: expected true or false")
            src.autolimits = auto == "true"


def _expand_includes(root: Any, text: str, name: str, folder: Path | None, main: Path | None) -> None:
    """Resolve the ``<include>``s of the main file's tree ``root`` in place (see ``_Includes``)."""
    includes = _Includes(folder, len(text.encode("utf-8")))
    includes.expand(root, name, (main,) if main is not None else ())
    if includes.outside:
        import warnings

        listed = ", ".join(n[:60] for n in includes.outside[:3])
        more = f" and {len(includes.outside) - 3} more" if len(includes.outside) > 3 else ""
        warnings.warn(f"{name}: {len(includes.outside)} included file(s) outside the model's folder are read: "
                      f"{listed}{more}", UserWarning, stacklevel=4)


def read_mjcf_source(source: str | os.PathLike) -> MjcfSource:
    """The resolved tree of an MJCF file (path) or MJCF text (a string starting with '<')."""
    if isinstance(source, str) and source.lstrip().startswith("<"):
        text, name, folder = source, "<mjcf string>", None
    else:
        p = Path(source)
        text = read_text_file(p, MAX_BYTES, "an MJCF model")
        if not text.strip():
            raise InputError(f"{p}: file is empty; expected an MJCF <mujoco> element")
        name, folder = str(p), p.parent
    root = _parse(text, name)
    if "<include" in text:  # an <include> element is spelled so in the text (XML allows no space after '<')
        _expand_includes(root, text, name, folder, Path(source).resolve() if folder is not None else None)
    src = MjcfSource(root, name, folder=folder)
    _compiler(src)
    src.defaults = _defaults(root, name)
    return src
