"""The RV-6S's links as capsules (a segment and a radius) for collision checks.

Each capsule runs between two DH frame origins (`solver.frames_batch`), so it follows the
kinematic model; the radii are estimates from the arm's outline drawing (rv6s.md §2:
upper arm about 130 mm across, forearm about 100 mm, the wrist housing about 90 mm) with
a few millimetres to spare, not measured. A tool body on the flange (the cell's gripper)
is one more capsule along the flange's Z axis (`segments(..., tool_length=…)`).

`reach` bounds how far a point of each capsule can move per radian of each joint (the
chain of link lengths from the joint's axis to the capsule's far end), so a path check
knows how far the arm may have moved between two samples without computing it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from melfa.kin.model import BASE_HEIGHT, DH
from melfa.kin.pose import FloatArray
from melfa.kin.solver import frames_batch


@dataclass(frozen=True, slots=True)
class Link:
    """A capsule from frame `start`'s origin to frame `end`'s origin (frame indices of
    `frames_batch`; -1 for the base column's top), `radius` mm; `name` as people say it.
    With `flat_end` the segment stops a radius short of `end`, so the capsule ends there
    (the wrist's housing ends at the flange's face, not a radius beyond it)."""

    name: str
    start: int
    end: int
    radius: float
    flat_end: bool = False


BASE_COLUMN = -1
"""The base column's capsule ends on J1's axis at the shoulder's height (its own point)."""

LINKS: tuple[Link, ...] = (
    Link("base", 0, BASE_COLUMN, 90.0),
    Link("upper arm", 1, 2, 65.0),
    Link("elbow", 2, 3, 65.0),
    Link("forearm", 3, 4, 50.0),
    Link("wrist", 4, 6, 45.0, flat_end=True),
)
TOOL = "gripper"
"""The name of the tool's capsule (after the links)."""


def names(tool: bool) -> tuple[str, ...]:
    return tuple(link.name for link in LINKS) + ((TOOL,) if tool else ())


def segments(
    joints: FloatArray, *, base: FloatArray | None = None, tool_length: float = 0.0
) -> tuple[FloatArray, FloatArray]:
    """Capsule ends (N, C, 3) each for joint rows (N, 6) in degrees, in the world frame
    (`base`: the robot's base as seen from the world, 4×4); with `tool_length` > 0 the
    tool's capsule, from the flange along its Z axis, is the last."""
    starts, ends, _, _ = placed(joints, base=base, tool_length=tool_length)
    return starts, ends


def placed(
    joints: FloatArray, *, base: FloatArray | None = None, tool_length: float = 0.0
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """`segments`, and each joint's axis (N, 6, 3): a point on it and its direction."""
    frames = frames_batch(joints)
    if base is not None:
        frames = base @ frames
    n = frames.shape[0]
    origins = frames[:, :, :3, 3]
    column_top = (
        base @ np.array([0.0, 0.0, BASE_HEIGHT, 1.0])
        if base is not None
        else np.array([0.0, 0.0, BASE_HEIGHT, 1.0])
    )
    points = np.concatenate([origins, np.broadcast_to(column_top[:3], (n, 1, 3))], axis=1)
    starts = points[:, [link.start for link in LINKS]]
    ends = points[:, [link.end for link in LINKS]].copy()
    for c, link in enumerate(LINKS):
        if link.flat_end:
            axis = ends[:, c] - starts[:, c]
            length = np.linalg.norm(axis, axis=1, keepdims=True)
            ends[:, c] -= axis * (link.radius / np.maximum(length, 1e-9))
    if tool_length > 0:
        flange = frames[:, -1]
        tip = flange[:, :3, 3] + tool_length * flange[:, :3, 2]
        starts = np.concatenate([starts, flange[:, None, :3, 3]], axis=1)
        ends = np.concatenate([ends, tip[:, None]], axis=1)
    return starts, ends, frames[:, :-1, :3, 3], frames[:, :-1, :3, 2]


def axis_distance(
    starts: FloatArray, ends: FloatArray, origins: FloatArray, dirs: FloatArray
) -> FloatArray:
    """(N, 6, C): the farthest any point of each capsule's axis is from each joint's
    axis (a segment's distance to a line is largest at one of its ends)."""
    far = []
    for p in (starts, ends):
        rel = p[:, None, :, :] - origins[:, :, None, :]  # (N, 6, C, 3)
        along = np.einsum("njck,njk->njc", rel, dirs)
        far.append(np.linalg.norm(rel - along[..., None] * dirs[:, :, None, :], axis=3))
    return np.asarray(np.maximum(far[0], far[1]), dtype=float)


def radii(tool_radius: float | None = None) -> FloatArray:
    """The capsules' radii (C,), the tool's last when given."""
    r = [link.radius for link in LINKS]
    return np.array(r + ([tool_radius] if tool_radius is not None else []), dtype=float)


def reach(tool_length: float = 0.0, tool_radius: float | None = None) -> FloatArray:
    """(6, C): an upper bound, mm per radian of joint j, on how far any point of capsule c
    (its surface included) moves when joint j turns."""
    lengths = [math.hypot(row.a, row.d) for row in DH]  # frame i-1 origin to frame i origin
    ends = [link.end if link.end != BASE_COLUMN else 0 for link in LINKS]
    rs = [link.radius for link in LINKS]
    if tool_length > 0 or tool_radius is not None:
        ends.append(len(DH) + 1)  # the tool's tip: one segment past the flange
        lengths.append(tool_length)
        rs.append(tool_radius or 0.0)
    out = np.zeros((len(DH), len(ends)))
    for c, (end, r) in enumerate(zip(ends, rs, strict=True)):
        for j in range(len(DH)):
            # joint j+1 turns about frame j's Z axis, through frame j's origin
            if end <= j:
                continue  # the capsule is before this joint: it does not move
            # frame j+1's origin is on joint j+1's own axis when its row has no `a`
            on_axis = DH[j].a == 0.0
            out[j, c] = sum(lengths[j + 1 if on_axis else j : end]) + r
    return out
