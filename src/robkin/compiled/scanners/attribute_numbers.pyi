"""Type stub of the compiled module ``robkin.compiled.scanners.attribute_numbers`` (see attribute_numbers.pyx)."""

MAX_ABS: float

def numbers(text: str | None, count: int, where: str, what: str | None,
            default: tuple[float, ...]) -> tuple[float, ...]: ...
def number(text: str | None, where: str, what: str, infinite_ok: bool = False) -> float | None: ...
