"""Checks on constant values: the ranges of arguments, DLY, DIM sizes, a DEF list's length.

A mixin of the checker (`melfa.lang.check`), like `melfa.lang.check_names`: each method looks
at one kind of tree node (or one constant argument) and reports through `add`. The limits are
the language model's (`melfa.lang.model`). Sections (§) are those of melfa-basic-iv.md.
"""

from __future__ import annotations

from melfa.lang import ast as A  # noqa: N812
from melfa.lang.diagnostics import Severity
from melfa.lang.model import (
    MAX_DEF_LENGTH,
    MAX_DIM_SIZE,
    MAX_DIMENSIONS,
    MIN_DLY,
    OPEN_LOW,
    RANGES,
)
from melfa.lang.reporter import Reporter

E, W = Severity.ERROR, Severity.WARNING
_OPEN_LOW = frozenset(RANGES[word] for word in OPEN_LOW)
_PALLETS = RANGES["PLT"]


class ValueChecks(Reporter):
    """value-out-of-range, dim-*, def-too-long; mixed into the checker's analyser."""

    def range(self, arg: A.Expr, limits: tuple[float, float, str]) -> None:
        """value-out-of-range when `arg` is a constant outside [low, high]."""
        value = A.constant_number(arg)
        low, high, what = limits
        if value is None:
            return
        if limits in _OPEN_LOW:
            if not low < value <= high:
                self.add(
                    arg.span,
                    E,
                    f"{what}, found {_number_text(value)}",
                    "value-out-of-range",
                    suggestion=f"Use a value above {low:g} and up to {high:g}.",
                )
        elif not low <= value <= high:
            self.add(
                arg.span,
                E,
                f"{what}, found {_number_text(value)}",
                "value-out-of-range",
                suggestion=f"Use a value from {low:g} to {high:g}.",
            )

    def dly_range(self, arg: A.Expr) -> None:
        value = A.constant_number(arg)
        if value is not None and value < MIN_DLY:
            self.add(
                arg.span,
                E if value < 0 else W,
                f"DLY {_number_text(value)} is below the controller's minimum of {MIN_DLY} s",
                "value-out-of-range",
                suggestion=f"Wait at least {MIN_DLY} s, e.g. DLY {MIN_DLY}.",
            )

    def pallet(self, node: A.Pallet) -> None:
        self.range(node.pallet, _PALLETS)

    def def_plt(self, node: A.DefPlt) -> None:
        self.range(node.number, _PALLETS)

    def def_var(self, node: A.DefVar) -> None:
        span = node.span
        length = span.end_column - span.column
        if span.end_line == span.line and length > MAX_DEF_LENGTH:
            self.add(
                A.Span(span.line, span.column + MAX_DEF_LENGTH, span.line, span.end_column),
                E,
                f"DEF {node.type.value} list is {length} characters long; the controller allows "
                f"{MAX_DEF_LENGTH} from DEF on",
                "def-too-long",
                suggestion=f"Split the names over two DEF {node.type.value} lines.",
            )

    def dim(self, node: A.Dim) -> None:
        for array in node.arrays:
            sizes = array.sizes
            shown = array.name.written
            if len(sizes) > MAX_DIMENSIONS:
                self.add(
                    sizes[MAX_DIMENSIONS].span.to(sizes[-1].span),
                    E,
                    f"DIM {shown} has {len(sizes)} dimensions; the limit is {MAX_DIMENSIONS}",
                    "dim-dimensions",
                    "L4370",
                    f"Use at most {MAX_DIMENSIONS} sizes, e.g. DIM {shown}(10, 10, 10).",
                )
            for size in sizes[:MAX_DIMENSIONS]:
                value = A.constant_number(size)
                if value is None:
                    self.add(
                        size.span,
                        E,
                        f"DIM {shown}: array sizes must be constant numbers",
                        "dim-size",
                        "L4370",
                        f"Write the size as a number from 1 to {MAX_DIM_SIZE}, e.g. "
                        f"DIM {shown}(10).",
                    )
                elif value != int(value) or not 1 <= value <= MAX_DIM_SIZE:
                    self.add(
                        size.span,
                        E,
                        f"DIM {shown}: array size {_number_text(value)} is out of range",
                        "dim-size",
                        "L4370",
                        f"Use a whole number from 1 to {MAX_DIM_SIZE}.",
                    )


def _number_text(value: float) -> str:
    return f"{value:g}"


__all__ = ["ValueChecks"]
