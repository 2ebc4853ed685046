"""XML for the URDF reader (and the MJCF and SDF readers, which share ``_parse_xml``).

Parsing with DTDs refused (so no entities of any kind), lxml for big files, and the top-level elements
robkin keeps as text. The kinematic tree of a URDF is read without a tree (``compiled.scanners.urdf_scan``); these
trees are built only for the link contents and the extras, when first asked for.
"""

from __future__ import annotations

from typing import Any

from ...errors import InputError

__all__ = ["LXML_FROM"]

#: Below this size (characters) a URDF is parsed with the standard library's C parser unless lxml is
#: already loaded: its whole parse then takes ~1-2 ms, less than importing lxml (10-20 ms measured),
#: which matters for one-shot commands. Above it lxml (libxml2) wins: ~5x faster on a 110 kB humanoid.
LXML_FROM = 64 * 1024


def _refuse_dtd(text: str, source: str) -> None:
    """A URDF (or MJCF, SDF) never needs a DTD, and without one there can be no entity declarations (so
    no entity expansion attacks, no external entities): a document that declares one is refused."""
    if "<!DOCTYPE" in text or "<!ENTITY" in text:
        raise InputError(f"{source}: refused XML construct (a DTD or entity declaration); a URDF needs no DTD, "
                         f"entities or external references")


def _parse_xml(text: str, source: str) -> Any:
    """Root element (``xml.etree``) of XML with no DTD, parsed by the standard library's C parser;
    InputError for malformed or refused XML. Shared with the MJCF and SDF readers."""
    from xml.etree.ElementTree import ParseError, XMLParser

    _refuse_dtd(text, source)
    try:
        parser = XMLParser()
        parser.feed(text)
        return parser.close()
    except ParseError as exc:
        line, col = exc.position
        raise InputError(f"{source}: not well-formed XML (line {line}, column {col + 1})") from None
    except (ValueError, RecursionError) as exc:
        raise InputError(f"{source}: not valid XML ({exc})") from None


def _parse_urdf_xml(text: str, source: str) -> Any:
    """Root element of a URDF: lxml's (libxml2) for big inputs (see LXML_FROM), else ``_parse_xml``'s.

    lxml is told to resolve no entities, touch no network and load no DTD (and ``_refuse_dtd`` runs
    first); expat resolves no external entities either. Both trees answer the ElementTree calls the
    URDF reader makes.
    """
    import sys

    if len(text) < LXML_FROM and "lxml.etree" not in sys.modules:
        return _parse_xml(text, source)
    try:
        from lxml import etree  # type: ignore[import-untyped, unused-ignore]
    except ImportError:  # pragma: no cover - lxml is a dependency; the standard library still works
        return _parse_xml(text, source)
    _refuse_dtd(text, source)
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False, huge_tree=False,
                             remove_comments=True, remove_pis=True, encoding="utf-8")
    try:
        # the text is already decoded (UTF-8 by read_text_file); an encoding declaration must not
        # re-decode it, so the bytes are handed over with the encoding fixed
        return etree.fromstring(text.encode("utf-8", "surrogatepass"), parser)
    except etree.XMLSyntaxError as exc:
        line, col = getattr(exc, "position", (None, None))
        where = f" (line {line}, column {col})" if line else ""
        raise InputError(f"{source}: not well-formed XML{where}") from None
    except (ValueError, RecursionError, UnicodeError) as exc:
        raise InputError(f"{source}: not valid XML ({exc})") from None


#: top-level elements that robkin reads (or, for <mujoco>, writes its own of)
_KNOWN_TOP = {"link", "joint", "material", "mujoco"}


def _extras(root: Any) -> list[str]:
    """The top-level elements robkin does not interpret, as XML text (see ``UrdfModel.extras``)."""
    if "lxml.etree" in type(root).__module__:
        from lxml import etree  # type: ignore[import-untyped, unused-ignore]

        return [etree.tostring(el, encoding="unicode", with_tail=False) for el in root
                if isinstance(el.tag, str) and el.tag not in _KNOWN_TOP]
    from xml.etree.ElementTree import tostring

    out = []
    for el in root:
        if el.tag not in _KNOWN_TOP:
            el.tail = None
            out.append(tostring(el, encoding="unicode"))
    return out
