"""An assignment read from its files: `assignment.toml` and the files it names.

`load_assignment(files)` takes the folder's files as a mapping of relative path → bytes or
text (from a folder on disk, `melfa.grade.folder.read_folder`; from the server's store;
from an upload) and returns a typed `Assignment`, or raises `AssignmentError` listing
every problem with its file, table and key, in the instructor's words. Pure: no disk.
"""

from __future__ import annotations

import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from pydantic import ValidationError

from melfa.grade.model import CHECK_MODELS, AssignmentFile, Avoids, CheckKind, PartAt, Uses
from melfa.grade.statements import STATEMENTS, normalise
from melfa.grade.variants import Variant, pick
from melfa.lang.encoding import decode_text
from melfa.lang.points_read import parse_points
from melfa.sim.debug.cell import Cell, CellError

MANIFEST = "assignment.toml"


@dataclass(frozen=True, slots=True)
class Problem:
    """One thing wrong with an assignment: the file, where in it (table and key), what."""

    file: str
    where: str
    message: str

    def __str__(self) -> str:
        return (
            f"{self.file}: {self.where}: {self.message}"
            if self.where
            else (f"{self.file}: {self.message}")
        )


class AssignmentError(ValueError):
    """An assignment that cannot be used; `problems` says every what and where."""

    def __init__(self, problems: Iterable[Problem]) -> None:
        self.problems = tuple(problems)
        super().__init__("\n".join(str(p) for p in self.problems))


@dataclass(frozen=True, slots=True)
class Assignment:
    """An assignment ready to grade: its manifest and the texts of the files it names."""

    spec: AssignmentFile
    statement: str  # Markdown
    cell: Cell
    starter: str | None = None
    starter_points: str | None = None

    @property
    def title(self) -> str:
        return self.spec.title

    def variant(self, seed: str | int | None) -> Variant:
        """The offsets of `seed`'s variant (None: the assignment as written)."""
        return pick(self.spec.variants, seed)


def load_assignment(files: Mapping[str, bytes | str]) -> Assignment:
    """The assignment in `files` (relative path → contents); `AssignmentError` if broken."""
    raw = files.get(MANIFEST)
    if raw is None:
        raise AssignmentError([Problem(MANIFEST, "", "missing: an assignment folder has one")])
    try:
        data = tomllib.loads(_text(raw))
    except tomllib.TOMLDecodeError as exc:
        raise AssignmentError([Problem(MANIFEST, "", f"not TOML: {exc}")]) from None
    problems = _kinds(data)
    if problems:
        raise AssignmentError(problems)
    try:
        spec = AssignmentFile.model_validate(data)
    except ValidationError as exc:
        raise AssignmentError(_problems(exc, data)) from None
    problems = []

    def named(key: str, name: str | None) -> str | None:
        if name is None:
            return None
        if name.startswith(("/", "\\")) or ".." in name.replace("\\", "/").split("/"):
            problems.append(Problem(MANIFEST, key, f"{name!r} must be a file in the folder"))
            return None
        found = files.get(name)
        if found is None:
            problems.append(Problem(MANIFEST, key, f"names {name!r}, which is not in the folder"))
            return None
        return _text(found)

    statement = named("statement", spec.statement)
    starter = named("starter", spec.starter)
    starter_points = named("starter_points", spec.starter_points)
    cell_text = named("cell", spec.cell)
    cell = Cell()
    if cell_text is not None:
        try:
            cell = Cell.from_json(cell_text)
        except CellError as exc:
            problems.append(Problem(spec.cell or "cell", "", str(exc)))
    problems += _references(spec, cell, starter, starter_points)
    if problems:
        raise AssignmentError(problems)
    return Assignment(spec, statement or "", cell, starter, starter_points)


def _text(raw: bytes | str) -> str:
    return decode_text(raw) if isinstance(raw, bytes) else raw


def _check_where(index: int, data: Any) -> str:
    kind = data.get("kind") if isinstance(data, dict) else None
    return f"[[checks]] {index + 1}" + (f" (kind = {kind!r})" if isinstance(kind, str) else "")


def _kinds(data: dict[str, Any]) -> list[Problem]:
    """Each check's kind, before pydantic would say it in its own words."""
    checks = data.get("checks")
    if not isinstance(checks, list):
        return []
    known = ", ".join(k.value for k in CheckKind)
    problems = []
    for i, check in enumerate(checks):
        if not isinstance(check, dict):
            continue
        kind = check.get("kind")
        where = f"[[checks]] {i + 1}"
        if kind is None:
            problems.append(Problem(MANIFEST, where, f"kind is missing (one of {known})"))
        elif kind not in CHECK_MODELS:
            problems.append(Problem(MANIFEST, where, f"kind {kind!r} is not a check ({known})"))
    return problems


def _problems(exc: ValidationError, data: dict[str, Any]) -> list[Problem]:
    out = []
    found = exc.errors(include_url=False)
    inner = any(len(e["loc"]) > 1 and e["loc"][0] == "checks" for e in found)
    for err in found:
        loc = list(err["loc"])
        if inner and loc == ["checks"] and err["type"] == "too_short":
            continue  # a check was wrong, not missing: pydantic counts the valid ones
        where = ""
        if loc[:1] == ["checks"] and len(loc) >= 2 and isinstance(loc[1], int):
            where = _check_where(loc[1], data["checks"][loc[1]])
            loc = loc[3:]  # past the index and the union's tag
        elif loc[:1] == ["variants"] and len(loc) >= 2:
            where = f"[variants.{loc[1]}]"
            loc = loc[2:]
        key = ".".join(str(part) for part in loc)
        message = err["msg"].removeprefix("Value error, ")
        if err["type"] == "extra_forbidden":
            message = "is not a key of this table"
        elif err["type"] == "missing":
            message = "is missing"
        where = f"{where}, {key}" if where and key else where or key
        out.append(Problem(MANIFEST, where, message))
    return out


def _references(
    spec: AssignmentFile, cell: Cell, starter: str | None, starter_points: str | None
) -> list[Problem]:
    """Names a check or a group uses that do not exist (a group, a part, a statement…)."""
    problems = []
    parts = part_names(cell)
    groups = spec.variants
    for i, check in enumerate(spec.checks):
        where = f"[[checks]] {i + 1} (kind = {check.kind.value!r})"
        follows = getattr(check, "follows", None)
        if follows is not None and follows not in groups:
            known = ", ".join(sorted(groups)) or "none"
            problems.append(
                Problem(MANIFEST, f"{where}, follows", f"no variant group {follows!r} ({known})")
            )
        if isinstance(check, PartAt) and check.part not in parts:
            known = ", ".join(sorted(parts)) or "the cell has none"
            problems.append(
                Problem(MANIFEST, f"{where}, part", f"no part {check.part!r} ({known})")
            )
        if isinstance(check, Uses | Avoids):
            for name in check.statements:
                if normalise(name) not in STATEMENTS:
                    problems.append(
                        Problem(
                            MANIFEST,
                            f"{where}, statements",
                            f"{name!r} is not a MELFA BASIC IV statement",
                        )
                    )
    point_names = set()
    if starter_points is not None:
        point_names = {n.upper() for n in parse_points(starter_points).names}
    for name, group in groups.items():
        where = f"[variants.{name}]"
        for part in group.parts:
            if part not in parts and part not in {b.name for b in cell.boxes}:
                problems.append(
                    Problem(MANIFEST, f"{where}, parts", f"no part {part!r} in the cell")
                )
        for point in group.points:
            if point.upper() not in point_names:
                problems.append(
                    Problem(MANIFEST, f"{where}, points", f"no point {point!r} in starter_points")
                )
    del starter
    return problems


def part_names(cell: Cell) -> set[str]:
    """The names of the cell's parts."""
    return {p.name for p in cell.parts}
