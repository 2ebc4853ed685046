"""YAML for untrusted robot documents: PyYAML's safe loader with aliases bounded and numbers sane.

``yaml.safe_load`` already builds nothing but plain data, but three things in it can still be turned
against a reader:

* **Alias bombs** ("billion laughs"): a 0.5 kB file whose anchors (``&a``) and aliases (``*a``) nest
  ten deep describes 10^9 nodes. PyYAML shares the aliased objects, so parsing is cheap, but anything
  that walks the result (validation, an error message quoting it) expands it. Here every node's
  *expanded* size (aliases counted as often as they are used) is computed while composing, in time
  linear in the text, and a document larger than ``MAX_NODES`` is refused. Ordinary uses of aliases
  (one identity matrix reused for ``base`` and ``tool``) stay well inside the limit. A recursive alias
  (a list containing itself) is refused outright. Both messages name the field (``dh.rows[0]``) where
  the alias or the oversized node is.
* **Huge integers**: an integer with more digits than Python converts (4300) raised ValueError; one
  beyond the float range overflowed later. Integers longer than ``MAX_INT_DIGITS`` characters are read
  as +-inf, which the number reader then refuses with the field's name.
* Errors other than ``yaml.YAMLError`` (ValueError from the int and timestamp constructors,
  RecursionError from deep nesting) are turned into ``yaml.YAMLError`` here, so the caller has one
  exception to turn into its one-line message.
"""

from __future__ import annotations

from typing import Any

import yaml
from yaml.constructor import SafeConstructor
from yaml.events import AliasEvent
from yaml.nodes import MappingNode, Node, ScalarNode, SequenceNode

from .numbers import MAX_INT_DIGITS

__all__ = ["load_yaml", "MAX_NODES", "MAX_INT_DIGITS"]

#: Largest document, counted in YAML nodes after expanding aliases. A robot document with every
#: section has about 75 nodes per joint, so this admits ~2600 joints, while any walk of the data
#: (validation, a message) stays far below a second.
MAX_NODES = 200_000


class _BoundedLoader(yaml.SafeLoader):
    """SafeLoader that counts each node's expanded size and refuses documents above MAX_NODES."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._sizes: dict[int, int] = {}  # id(node) -> expanded size; the nodes live as long as the loader
        self._path: list[str] = []  # the field being composed, as parts ("dh", ".rows", "[0]")

    def _field(self) -> str:
        return "".join(self._path).lstrip(".") or "the document"

    def compose_node(self, parent: Node | None, index: Any) -> Node:
        if parent is None:
            part = ""
        elif isinstance(index, int):
            part = f"[{index}]"
        elif isinstance(index, ScalarNode):
            part = "." + str(index.value)[:40]
        else:
            part = ".(a key)" if index is None else ".(a complex key)"
        self._path.append(part)
        try:
            return self._compose(parent, index)
        finally:
            self._path.pop()

    def _compose(self, parent: Node | None, index: Any) -> Node:
        if self.check_event(AliasEvent):
            mark = self.peek_event().start_mark
            node = super().compose_node(parent, index)  # the anchored node (or an undefined-alias error)
            if id(node) not in self._sizes:  # its anchor is still open: the node would contain itself
                raise yaml.composer.ComposerError(None, None, f"{self._field()}: found a recursive alias (a "
                                                  "node that contains itself)", mark)
            return node
        node = super().compose_node(parent, index)
        if isinstance(node, SequenceNode):
            children = node.value
        elif isinstance(node, MappingNode):
            children = [part for pair in node.value for part in pair]
        else:
            children = []
        size = 1 + sum(self._sizes[id(child)] for child in children)
        if size > MAX_NODES:
            raise yaml.composer.ComposerError(None, None, f"{self._field()}: more than {MAX_NODES} values after "
                                              f"expanding '*' aliases; a robot document needs far fewer",
                                              node.start_mark)
        self._sizes[id(node)] = size
        return node


def _construct_int(loader: SafeConstructor, node: Node) -> int | float:
    text = loader.construct_scalar(node)  # type: ignore[arg-type]
    if len(text) > MAX_INT_DIGITS:
        return float("-inf") if text.lstrip().startswith("-") else float("inf")
    return SafeConstructor.construct_yaml_int(loader, node)  # type: ignore[arg-type]


_BoundedLoader.add_constructor("tag:yaml.org,2002:int", _construct_int)


def load_yaml(text: str) -> Any:
    """Plain data from YAML ``text``; ``yaml.YAMLError`` for anything it refuses (see the module)."""
    loader = _BoundedLoader(text)
    try:
        return loader.get_single_data()
    except yaml.YAMLError:
        raise
    except RecursionError:
        raise yaml.YAMLError("nested too deeply") from None
    except (ValueError, TypeError, OverflowError) as exc:  # constructors of ints, floats, timestamps
        raise yaml.YAMLError(f"cannot read a value ({exc})") from None
    finally:
        loader.dispose()
