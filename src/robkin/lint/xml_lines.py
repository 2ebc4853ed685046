"""Source lines of the elements of an MJCF or SDF file, by the names robkin's readers give them.

The readers (``io.mjcf``, ``io.sdf``) parse with the standard library and keep no lines; lint parses the
same text again with lxml (no DTD, no entities, no network: the readers' rules) and finds each body,
joint, site, geom, inertial and mesh asset by the name the reader gave it (MJCF's unnamed ``bodyI``,
``jointI``, ``siteI`` are MuJoCo's ids: document order). Elements of files an MJCF ``<include>``s are not
in this tree: their findings carry no line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["XmlLines", "mjcf_lines", "sdf_lines", "parse_lines"]


@dataclass
class XmlLines:
    """Name -> element of one file (``None`` where the element is not in it)."""

    links: dict[str, Any] = field(default_factory=dict)
    joints: dict[str, Any] = field(default_factory=dict)
    meshes: dict[str, Any] = field(default_factory=dict)    # MJCF asset mesh name -> <mesh>
    compiler: list = field(default_factory=list)
    root: Any = None

    @staticmethod
    def line(el: Any) -> int | None:
        return getattr(el, "sourceline", None) if el is not None else None


def parse_lines(path: str) -> Any | None:
    """The lxml root of an XML file with comments dropped, or None when it cannot be parsed (the reader
    says why)."""
    try:
        from lxml import etree  # type: ignore[import-untyped, unused-ignore]

        from ..io.files.input_files import read_text_file
        from ..io.trees.xml_parse import _refuse_dtd

        text = read_text_file(path, 64 * 1024 * 1024, "a robot file")
        _refuse_dtd(text, path)
        parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                                 remove_comments=True, remove_pis=True, encoding="utf-8")
        return etree.fromstring(text.encode("utf-8", "surrogatepass"), parser)
    except Exception:  # lines are a courtesy: any failure here leaves the reader's message to speak
        return None


def _in_bodies(el: Any) -> list[Any]:
    """The elements directly in a body (its ``<frame>``s dissolved), nested bodies excluded, in order."""
    out, todo = [], list(el)[::-1]
    while todo:
        c = todo.pop()
        if not isinstance(c.tag, str):
            continue
        if c.tag == "frame":
            todo.extend(list(c)[::-1])
        else:
            out.append(c)
    return out


def mjcf_lines(root: Any) -> XmlLines:
    """Bodies (and each joint's intermediate ``BODY/JOINT`` link), joints, sites, meshes of an MJCF tree."""
    out = XmlLines(root=root)
    if root is None:
        return out
    counts = {"body": 1, "joint": 0, "site": 0}   # body 0 is the world
    out.links["world"] = root.find("worldbody")
    out.compiler = root.findall("compiler")
    for wb in root.iterfind("worldbody"):
        for el in wb.iter("body", "joint", "freejoint", "site"):
            kind = "joint" if el.tag == "freejoint" else el.tag
            name = el.get("name") or f"{kind}{counts[kind]}"
            counts[kind] += 1
            if kind == "joint":
                out.joints[name] = el
                body = el.getparent()
                while body is not None and body.tag == "frame":
                    body = body.getparent()
                bname = body.get("name") if body is not None else None
                if bname:
                    out.links[f"{bname}/{name}"] = el
            else:
                out.links.setdefault(name, el)
                out.links.setdefault(f"site:{name}", el)
    for asset in root.iterfind("asset"):
        for m in asset.iterfind("mesh"):
            file = m.get("file") or ""
            stem = file.replace("\\", "/").rsplit("/", 1)[-1].rsplit(".", 1)[0]
            out.meshes[m.get("name") or stem] = m
    return out


def sdf_lines(root: Any) -> XmlLines:
    """Links and joints of an SDF tree, by the reader's scoped names (``inner::link`` in a nested model)."""
    out = XmlLines(root=root)
    if root is None:
        return out
    for el in root.iter("link", "joint", "frame"):
        scopes, up = [], el.getparent()
        while up is not None:
            if up.tag == "model" and up.getparent() is not None and up.getparent().tag == "model":
                scopes.append(up.get("name") or "")
            up = up.getparent()
        name = "::".join(list(reversed(scopes)) + [el.get("name") or ""])
        (out.joints if el.tag == "joint" else out.links).setdefault(name, el)
    return out
