"""An assignment folder on disk, read into the mapping `load_assignment` takes.

The one module of `melfa.grade` that touches files: every regular file under the folder
(at most `MAX_FILES`, each at most `MAX_BYTES`), by its path relative to the folder with
`/` separators. Hidden files and folders (``.git``) are skipped.
"""

from __future__ import annotations

from pathlib import Path

from melfa.grade.assignment import MANIFEST, AssignmentError, Problem

MAX_FILES = 200
MAX_BYTES = 2_000_000


def read_folder(folder: Path) -> dict[str, bytes]:
    """The folder's files; `AssignmentError` when it is not an assignment folder."""
    if not folder.is_dir():
        raise AssignmentError([Problem(str(folder), "", "is not a folder")])
    if not (folder / MANIFEST).is_file():
        raise AssignmentError([Problem(str(folder), "", f"has no {MANIFEST}")])
    files: dict[str, bytes] = {}
    for path in sorted(folder.rglob("*")):
        rel = path.relative_to(folder)
        if any(part.startswith(".") for part in rel.parts) or not path.is_file():
            continue
        if len(files) >= MAX_FILES:
            raise AssignmentError([Problem(str(folder), "", f"more than {MAX_FILES} files")])
        if path.stat().st_size > MAX_BYTES:
            continue  # not a file an assignment names (a video, an archive)
        try:
            files[rel.as_posix()] = path.read_bytes()
        except OSError as exc:
            raise AssignmentError(
                [Problem(rel.as_posix(), "", f"cannot be read: {exc.strerror}")]
            ) from None
    return files
