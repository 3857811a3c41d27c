"""The array arithmetic of ``RobotScene`` (``frames.py``): a part's thickness, the joints' axes in a pose's frames,
the free parts in groups of neighbours, boxes' gaps, the broad phase at several poses, and the
moments of a step at which a swept check looks again. Pure functions of numpy arrays."""

from __future__ import annotations

import numpy as np

from valterm.core.collision.thesis import EPS, box_gaps


def thickness(vertices: np.ndarray, k: int) -> float:
    """The polyhedron's smallest width across its own faces (mm): how thin a part is."""
    return float(thicknesses(vertices[None], k)[0])


def thicknesses(vertices: np.ndarray, k: int) -> np.ndarray:
    """``thickness`` of polyhedra of ``k`` sides at once, their vertices (n, 2k, 3); a face of
    no area (degenerate) measures nothing."""
    faces = np.asarray(topology_faces(k))
    p = vertices[:, faces]                                          # (n, F, 3, 3)
    normal = np.cross(p[:, :, 1] - p[:, :, 0], p[:, :, 2] - p[:, :, 0])
    size = np.linalg.norm(normal, axis=2)
    normal /= np.where(size > 0, size, 1.0)[..., None]
    spans = vertices @ normal.transpose(0, 2, 1)                    # (n, 2k, F)
    width = np.where(size > 0, spans.max(axis=1) - spans.min(axis=1), np.inf)
    found: np.ndarray = width.min(axis=1)
    return found


def topology_faces(k: int) -> list[list[int]]:
    """Three vertices of each face of an extruded polyhedron (caps, then side quads)."""
    faces = [[0, 1, 2], [k, k + 1, k + 2]]
    faces += [[i, (i + 1) % k, k + (i + 1) % k] for i in range(k)]
    return faces


# each joint's axis, a column of its frame's rotation (``kinematics.link_frames``): JT1 turns
# about z of frame 1, JT2 and JT3 about y of frames 2 and 3, JT4 about z of frame 4, JT5
# about y of frame 5, JT6 about z of frame 6
AXIS_FRAMES = np.arange(1, 7)
AXIS_COLUMNS = np.array([2, 1, 1, 2, 1, 2])

# x @ LATER sums, for each joint, the columns of the joints after it
LATER = np.tril(np.ones((6, 6)), -1)


def sweep_bends(terms: np.ndarray, turns: np.ndarray) -> np.ndarray:
    """(steps, movers): how far a point of each moving body can leave the straight line between
    where it is at a step's two poses, the joints turning linearly by ``turns`` (steps, joints;
    radians, absolute), ``terms`` (steps, movers, joints) each joint's turn times the most the
    point is from its axis over the step (``RobotScene._path_terms``).

    The point's acceleration is the sum over joint pairs i, j of turn i x turn j x a vector no
    longer than its distance from the later joint's axis (a revolute chain's second derivative),
    so at most sum over j of term j x (turn j + twice the turns before j); a curve leaves its
    chord by at most an eighth of its largest acceleration."""
    weights = turns + 2.0 * (turns @ LATER.T)
    bends: np.ndarray = np.einsum("smj,sj->sm", terms, weights) * 0.125
    return bends


def groups(lo: np.ndarray, hi: np.ndarray, size: int = 8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The free parts in groups of neighbours (halved along the widest spread of their boxes'
    middles until at most ``size`` are left): each group's members, padded to ``size`` by
    repeating its last (a pair checked twice gets the same code), and the box holding them, as
    (3, groups) lows and highs. Built when the parts change; parts stand still between."""
    mid = (lo + hi) * 0.5
    todo, done = [np.arange(len(lo))] if len(lo) else [], []
    while todo:
        group = todo.pop()
        if len(group) <= size:
            done.append(group)
            continue
        axis = int(np.argmax(mid[group].max(axis=0) - mid[group].min(axis=0)))
        ordered = group[np.argsort(mid[group, axis], kind="stable")]
        todo += [ordered[: len(ordered) // 2], ordered[len(ordered) // 2:]]
    members = np.array([np.pad(g, (0, size - len(g)), mode="edge") for g in done], dtype=np.intp).reshape(-1, size)
    group_lo = np.array([lo[g].min(axis=0) for g in done]).reshape(-1, 3).T.copy()
    group_hi = np.array([hi[g].max(axis=0) for g in done]).reshape(-1, 3).T.copy()
    return members, group_lo, group_hi


# mm: how much nearer than the fine test's EPS two boxes are taken to meet between poses
# (room for the rounding of boxes worked out in another order; far above it)
HAIR = 1e-3

# the joints' axes as flat indices into a pose's (links, 4, 4) frames
AXIS_FLAT = (AXIS_FRAMES[:, None] * 16 + np.arange(3)[None, :] * 4 + AXIS_COLUMNS[:, None])


def candidates_batch(centres: np.ndarray, grow: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """``RobotScene._candidates`` at several poses: (poses, free parts) near the box of the
    movers' centres (poses, movers, 3) grown by ``grow`` (poses,)."""
    cmin = centres.min(axis=1) - grow[:, None]
    cmax = centres.max(axis=1) + grow[:, None]
    gap = np.maximum(lo[None] - cmax[:, None], cmin[:, None] - hi[None])
    near: np.ndarray = gap.max(axis=2) <= 0.0
    return near


def moments(pick: np.ndarray, sel: np.ndarray, b0: np.ndarray, both: np.ndarray, reach: np.ndarray,
             need: np.ndarray, n_pairs: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The moments of steps at risk and the pairs at each: per step (a row of each argument),
    the picked columns (pair positions ``sel``) with their gaps at start, gaps at start plus
    end, bounds and steps needed. Returns each moment's step (a row), the moments (fractions
    of their steps) and their rows of pairs, step by step in order."""
    steps = np.ceil(np.where(pick, need, -np.inf).max(axis=1)).astype(np.intp)   # steps of each
    count = np.maximum(steps - 1, 0)
    step = np.repeat(np.arange(len(pick)), count)
    nth = np.arange(len(step)) - np.repeat(np.cumsum(count) - count, count) + 1
    moments = nth / steps.take(step)
    reach = reach + 2.0 * EPS
    # each pair only where its boxes can meet: from b0 / reach to 1 - b1 / reach of the step
    # (``both`` is b0 + b1 less 2 EPS)
    early, late = (b0 - 2.0 * EPS) / reach, 1.0 - (both - b0) / reach
    at = moments[:, None]
    live = pick[step] & (early[step] <= at) & (at <= late[step])
    used = live.any(axis=1)
    rows = np.zeros((int(used.sum()), n_pairs), dtype=bool)
    rows[:, sel] = live[used]
    return step[used], moments[used], rows


def largest_of(d: np.ndarray) -> np.ndarray:
    """``largest_of_xyz`` of (3, ...) coordinates laid side by side: the largest of the three."""
    out: np.ndarray = np.maximum(d[0], d[1])
    np.maximum(out, d[2], out=out)
    return out


def body_box_gaps(mid: np.ndarray, half: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """How far apart the boxes of bodies a[i] and b[i] are (``box_gaps`` of the bodies' boxes)."""
    return box_gaps(mid.take(a, axis=0), half.take(a, axis=0), mid.take(b, axis=0), half.take(b, axis=0))


def stacked(frames: np.ndarray) -> np.ndarray:
    """(links, 4, 4) frames as one (4, 3 * links) matrix: row vector [x y z 1] times it gives
    the point in every frame at once."""
    stacked: np.ndarray = frames[:, :3, :].transpose(2, 0, 1).reshape(4, -1)
    return stacked


def pick(owner_rows: np.ndarray, n_frames: int) -> np.ndarray:
    """Flat indices into (rows, 3 * n_frames) of each row's three coordinates in its own frame."""
    rows = np.arange(len(owner_rows))[:, None]
    pick: np.ndarray = rows * (3 * n_frames) + owner_rows[:, None] * 3 + np.arange(3)
    return pick


def runs(idx: np.ndarray) -> list[np.ndarray]:
    """Split sorted indices into runs of consecutive numbers."""
    breaks = np.flatnonzero(np.diff(idx) != 1) + 1
    return np.split(idx, breaks)
