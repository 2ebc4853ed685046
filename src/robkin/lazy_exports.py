"""Names a package exports but imports only when first used (PEP 562 module ``__getattr__``).

``import robkin`` and every CLI command pay for the modules they load: most of a one-shot
``robkin convert`` is start-up, and each representation module costs its import (a ``dataclass``
definition alone is ~1 ms of CPU). A package lists which of its submodules defines each exported
name; the name is imported on first access and then kept in the package's namespace.
"""

from __future__ import annotations

import importlib
from typing import Any, Callable, Mapping

__all__ = ["lazy_exports"]


def lazy_exports(package: str, namespace: dict[str, Any], where: Mapping[str, str]
                 ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``(__getattr__, __dir__)`` for a package (or module) whose exported names are defined elsewhere.

    Parameters
    ----------
    package : str
        The exporting module's ``__name__`` (for messages).
    namespace : dict
        Its ``globals()``: a name once imported is stored there, so later lookups are plain attribute
        reads.
    where : mapping of str to str
        Exported name -> the module defining it, relative to the module's package (e.g. ``".dh"``).
    """

    def __getattr__(name: str) -> Any:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        # relative to the package holding the module (the module itself, for a package's __init__)
        value = getattr(importlib.import_module(module, namespace["__package__"]), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        # With __all__: the public API and the dunders (not the helpers the module imported for
        # itself, such as os, TYPE_CHECKING or __future__'s annotations); without, everything.
        public = namespace.get("__all__")
        if public is None:
            return sorted(set(namespace) | set(where))
        dunders = {n for n in namespace if n.startswith("__") and n.endswith("__")}
        return sorted(set(public) | set(where) | dunders)

    return __getattr__, __dir__
