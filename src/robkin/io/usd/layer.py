"""One USD file opened as one layer, with nothing it names followed.

A USD file is untrusted input, and USD composes: a layer may pull in other layers (``subLayers``),
other files' prims (``references``, ``payloads``) and animation clips (``clips``), by any asset path
(``@/etc/passwd@``, a URL a resolver would fetch). robkin reads **one self-contained layer**:

* the bytes are read as every input file is (``io.files.input_files``: a regular file, at most
  ``MAX_BYTES``); then ``usd-core`` parses those bytes, never the file by its name again: text
  (``#usda``) with ``Sdf.Layer.ImportFromString``, a binary crate (``PXR-USDC``) from a private
  temporary copy, moved into memory (``TransferContent``) before the copy is removed. Other files
  (``.usdz`` archives, anything else) are refused;
* before any composition, the layer's specs are searched for arcs to other files: a sublayer, a
  reference or payload with an asset path, value clips. Any of them refuses the file with one line
  naming the prim and the asset (``usdcat --flatten`` makes a self-contained copy). References and
  payloads inside the layer (``</Other/Prim>``), inherits and specializes are allowed on instanceable
  prims (as Isaac Sim's importer writes its meshes), where each prototype is composed once; elsewhere
  they could copy copies of prims, exponentially, and are refused (``usdcat --flatten`` writes them
  out). Variants are allowed;
* the stage is then composed from that layer alone (``Usd.Stage.Open`` of the in-memory layer).

USD text nested deeper than ``MAX_DEPTH`` is refused before usd-core parses it (its parser recurses
and crashes the process on ~30 000 nested prims). A crate file is bounded by ``MAX_BYTES`` too, but
neither its nesting nor what the crate reader unpacks from those bytes (it compresses integer arrays,
by at most LZ4's ratio of ~255) is bounded before usd-core reads it: a crafted crate is only as safe
as usd-core's crate reader.
"""

from __future__ import annotations

import os
from typing import Any

from ...errors import InputError, quote
from .format import pxr as _pxr

__all__ = ["open_stage", "MAX_BYTES"]

#: Largest USD file read (bytes): a robot with inline visual meshes is ~5-20 MB of text (Panda: 18 MB .usda).
MAX_BYTES = 256 * 1024 * 1024
#: Deepest nesting of brackets in USD text: usd-core's text parser recurses and crashes the process (a
#: segmentation fault, no exception) somewhere between 10 000 and 30 000 nested prims (usd-core 26.11); a
#: robot is < 20 deep.
MAX_DEPTH = 1000
_OTHER_BYTES = bytes(b for b in range(256) if b not in b"{}[]()")


def _nesting(data: bytes) -> int:
    """The deepest nesting of brackets ({ [ ( together) in USD text: a bound, not a parse (brackets in
    strings count too)."""
    import numpy as np

    marks = np.frombuffer(data.translate(None, _OTHER_BYTES), dtype=np.uint8)
    if not marks.size:
        return 0
    steps = np.where((marks == ord("{")) | (marks == ord("[")) | (marks == ord("(")), 1, -1).astype(np.int32)
    return int(np.cumsum(steps).max())


def _layer_from_bytes(pxr: Any, data: bytes, path: str) -> Any:
    Sdf = pxr.Sdf
    if data.startswith(b"PXR-USDC"):
        import tempfile

        with tempfile.TemporaryDirectory(prefix="robkin-usd-") as folder:
            tmp = os.path.join(folder, "input.usdc")
            with open(tmp, "wb") as fh:
                fh.write(data)
            crate = Sdf.Layer.OpenAsAnonymous(tmp)
            if crate is None:
                raise InputError(f"{path}: not a valid USD crate file")
            layer = Sdf.Layer.CreateAnonymous(".usda")
            layer.TransferContent(crate)
            del crate
        return layer
    text_start = data.lstrip(b"\xef\xbb\xbf")[:5]
    if text_start != b"#usda":
        what = "a .usdz archive" if data.startswith(b"PK") else "neither USD text ('#usda') nor a USD crate"
        raise InputError(f"{path}: {what}; robkin reads .usda text and .usdc crate files")
    if _nesting(data) > MAX_DEPTH:
        raise InputError(f"{path}: brackets nested more than {MAX_DEPTH} deep; a robot's USD text is a few levels deep")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    layer = Sdf.Layer.CreateAnonymous(".usda")
    try:
        ok = layer.ImportFromString(text)
    except Exception as exc:  # noqa: BLE001 - the text parser's error (Tf.ErrorException)
        raise InputError(f"{path}: not valid USD text ({_usd_message(exc)})") from None
    if not ok:
        raise InputError(f"{path}: not valid USD text")
    return layer


def _check_self_contained(pxr: Any, layer: Any, path: str) -> None:
    """InputError if the layer names another file (see the module doc)."""
    Sdf = pxr.Sdf
    if layer.subLayerPaths:
        raise InputError(f"{path}: has sublayers ({quote(layer.subLayerPaths[0])}); robkin reads one self-contained "
                         f"USD file and follows nothing it names (flatten it: usdcat --flatten {path} -o flat.usda)")
    found: list[tuple[str, str, str]] = []
    copies: list[tuple[str, str]] = []

    def items(ops: Any) -> tuple[Any, ...]:
        return (*ops.explicitItems, *ops.prependedItems, *ops.appendedItems, *ops.addedItems)

    def visit(spec_path: Any) -> None:
        if found or not spec_path.IsPrimPath() and not spec_path.IsPrimVariantSelectionPath():
            return
        spec = layer.GetPrimAtPath(spec_path)
        if spec is None:
            return
        for kind, ops in (("reference", spec.referenceList), ("payload", spec.payloadList)):
            for item in items(ops):
                if item.assetPath:
                    found.append((str(spec_path), kind, item.assetPath))
                    return
                if not spec.instanceable:
                    copies.append((str(spec_path), kind))
        for kind, ops in (("inherit", spec.inheritPathList), ("specialize", spec.specializesList)):
            if items(ops) and not spec.instanceable:
                copies.append((str(spec_path), kind))
        for key in ("clips", "clipSets"):
            if spec.HasInfo(key):
                found.append((str(spec_path), "value clips", key))
                return

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    if found:
        prim, kind, asset = found[0]
        raise InputError(f"{path}: prim {quote(prim)} has a {kind} to {quote(asset)}; robkin reads one "
                         f"self-contained USD file and follows nothing it names (flatten it: usdcat --flatten)")
    if copies:
        prim, kind = copies[0]
        raise InputError(f"{path}: prim {quote(prim)} copies another prim by a {kind} without being instanceable; "
                         f"robkin composes a file with itself through instanceable prims only (copies of copies "
                         f"grow exponentially; usdcat --flatten writes them out)")


def _usd_message(exc: Exception) -> str:
    """The useful part of a usd-core error ("':18:36: Expected } at ...'" after its C++ location)."""
    text = " ".join((str(exc) or type(exc).__name__).split())
    if " : " in text:
        text = text.split(" : ", 1)[1]
    return text.strip("'\" ")[:200]


def open_stage(path: str | os.PathLike[str]) -> Any:
    """The stage of the USD file ``path`` composed from that file alone (see the module doc)."""
    from ..files.input_files import read_bytes_file

    pxr = _pxr()
    p = os.fspath(path)
    data = read_bytes_file(p, MAX_BYTES, "a USD file")
    try:
        layer = _layer_from_bytes(pxr, data, p)
        _check_self_contained(pxr, layer, p)
        stage = pxr.Usd.Stage.Open(layer, pxr.Usd.Stage.LoadAll)
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001 - usd-core's parse errors (Tf.ErrorException) as one line
        raise InputError(f"{p}: not valid USD ({_usd_message(exc)})") from None
    if stage is None:
        raise InputError(f"{p}: not valid USD")
    return stage
