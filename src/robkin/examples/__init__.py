"""The example robots shipped with robkin, as robot documents (``*.yaml`` beside this file): the conversion
paper's RRPR, arbitrary 3R and SCARA, a KUKA KR6 R700 and an iiwa 14. ``robkin demo`` converts them, the
GUI offers them in its Example selector."""

from pathlib import Path

__all__ = ["EXAMPLES_DIR"]

#: The folder holding the example documents.
EXAMPLES_DIR = Path(__file__).resolve().parent
