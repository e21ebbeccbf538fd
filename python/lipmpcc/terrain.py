"""Stepping stones: paper B's profiles I–IV, user stone files and the approach walk.

World frame: the robot starts standing at the origin facing +x with its feet at
``(0, +w/2)`` (left) and ``(0, -w/2)`` (right). It walks :data:`N_APPROACH` = 6
approach steps (right foot first, lengths ramping up to ``L_app`` = 0.3 m) and ends
them on its left foot at :func:`entry_foothold` = (1.05, 0.14) m. The stones follow,
the first one for the **right** foot, then alternating (paper B: "enters the stones
with a right swing").

A stone is a rectangle ``size = (size_x, size_y)`` [m] around ``center``; the
foothold (foot centre) must land inside it. Paper B: 0.2 x 0.1 m. A region with an
infinite size is a free foothold (only the kinematic limits apply): the approach uses
such regions, its centres being targets.

Profiles (32 stones, relative positions ``[L^j, w_{l/r} + W^j]`` from the previous
foothold, ``w = 0.28`` m):

=======  =========================  =============================
profile  L^j [m]                    W^j [m]
=======  =========================  =============================
I        fixed (0.2, 0.4 or 0.55)   fixed (-0.15 or +0.15)
II       U[0.2, 0.5]                U[-0.15, 0.15]
III      (0.2 x8, 0.5 x8) x2        U[-0.15, 0.15]
IV       U[0.2, 0.5]                (-0.1 x8, 0.1 x8) x2
=======  =========================  =============================

Stone files (``load_stones``): CSV rows ``x,y[,size_x,size_y]`` in the world frame,
one row per footstep in order; blank lines, ``#`` comments and a header line are
skipped. The paper's cases (with our seeds for the random profiles) are stored under
``data/stones/``.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterator, Sequence

import numpy as np

from .exceptions import InvalidInputError, ParameterError, TerrainError
from .models.alip import LEFT, RIGHT, KinematicLimits, parse_side
from .validation import count, finite_array, finite_number, positive_number, read_text_file

__all__ = [
    "MAX_STONE_SIZE",
    "STONE_SIZE",
    "STEP_WIDTH",
    "N_APPROACH",
    "L_APPROACH",
    "N_STONES",
    "PROFILES",
    "Stone",
    "StoneSequence",
    "approach_footholds",
    "entry_foothold",
    "initial_feet",
    "make_profile",
    "profile_steps",
    "stones_from_steps",
    "load_stones",
    "save_stones",
    "paper_case_path",
    "paper_cases",
    "check_reachable",
]

#: Largest stone in a stone file [m] (a larger one is taken for a mistake; a free foothold is a row of the
#: approach, not of the file).
MAX_STONE_SIZE = 10.0
STONE_SIZE: tuple[float, float] = (0.2, 0.1)  # [m] paper B
STEP_WIDTH: float = 0.28  # w [m] paper B
N_APPROACH: int = 6
L_APPROACH: float = 0.3  # [m] approach step length reached at the 6th step
N_STONES: int = 32
PROFILES: tuple[str, ...] = ("I", "II", "III", "IV")


@dataclass(frozen=True)
class Stone:
    """One foothold region.

    Attributes:
        center: (x, y) world position of the rectangle's centre [m].
        size: (size_x, size_y) [m]; ``inf`` means unconstrained in that axis.
    """

    center: tuple[float, float]
    size: tuple[float, float] = STONE_SIZE

    def __post_init__(self) -> None:
        c = finite_array("center", self.center, (2,), "m", error=TerrainError, what="an (x, y) position")
        sz = _sizes("size", self.size, (2,))
        object.__setattr__(self, "center", (float(c[0]), float(c[1])))
        object.__setattr__(self, "size", (float(sz[0]), float(sz[1])))

    @property
    def lower(self) -> np.ndarray:
        return np.asarray(self.center, float) - 0.5 * np.asarray(self.size, float)

    @property
    def upper(self) -> np.ndarray:
        return np.asarray(self.center, float) + 0.5 * np.asarray(self.size, float)

    @property
    def is_free(self) -> bool:
        """True for an unconstrained (approach) region."""
        return not all(math.isfinite(s) for s in self.size)

    def contains(self, p: Sequence[float], tol: float = 1e-9) -> bool:
        """True if the world point ``p`` [m] lies in the rectangle."""
        q = np.asarray(p, float)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))


@dataclass(frozen=True)
class StoneSequence:
    """Ordered footholds: ``centers`` (n, 2) and ``sizes`` (n, 2) [m], ``sides`` (n,)
    the swing foot landing on each (+1 left, -1 right), ``is_stone`` (n,) False for free
    approach footholds."""

    centers: np.ndarray
    sizes: np.ndarray
    sides: np.ndarray
    is_stone: np.ndarray
    name: str = "stones"
    meta: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        c = finite_array("centers", self.centers, None, "m", error=TerrainError, what="(n, 2) stone centres")
        if c.size % 2:
            raise TerrainError("centers", self.centers, "(n, 2) stone centres [m]", f"got shape {c.shape}")
        c = np.array(c, dtype=float).reshape(-1, 2)
        s = _sizes("sizes", self.sizes, None).reshape(-1, 2)
        sd = np.array(self.sides, dtype=int).reshape(-1) if _all_sides(self.sides) else None
        if sd is None:
            raise TerrainError("sides", self.sides, "one side per stone: +1 (left) or -1 (right)")
        st = np.array(self.is_stone, dtype=bool).reshape(-1)
        if not (len(c) == len(s) == len(sd) == len(st)):
            raise TerrainError("stones", (len(c), len(s), len(sd), len(st)), "equal lengths of centers, sizes, sides, is_stone")
        for a in (c, s, sd, st):
            a.flags.writeable = False
        object.__setattr__(self, "centers", c)
        object.__setattr__(self, "sizes", s)
        object.__setattr__(self, "sides", sd)
        object.__setattr__(self, "is_stone", st)

    def __len__(self) -> int:
        return len(self.centers)

    def __getitem__(self, i: int) -> Stone:
        return Stone(tuple(self.centers[i]), tuple(self.sizes[i]))  # type: ignore[arg-type]

    def __iter__(self) -> Iterator[Stone]:
        for i in range(len(self)):
            yield self[i]

    def stones(self) -> list[Stone]:
        return list(self)

    def head(self, n: int) -> "StoneSequence":
        """The first ``n`` footholds."""
        n = count("n", n, 1)
        return StoneSequence(
            self.centers[:n], self.sizes[:n], self.sides[:n], self.is_stone[:n], self.name, dict(self.meta)
        )

    def __add__(self, other: "StoneSequence") -> "StoneSequence":
        return StoneSequence(
            np.vstack([self.centers, other.centers]),
            np.vstack([self.sizes, other.sizes]),
            np.concatenate([self.sides, other.sides]),
            np.concatenate([self.is_stone, other.is_stone]),
            other.name,
            {**self.meta, **other.meta},
        )


def _sizes(name: str, value: object, shape: tuple[int | None, ...] | None) -> np.ndarray:
    """Stone sizes [m]: numbers > 0, ``inf`` for a free axis (NaN and <= 0 refused)."""
    what = "stone sizes (size_x, size_y) > 0 [m] (inf: free)"
    if isinstance(value, (str, bytes)):
        raise TerrainError(name, value, what)
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise TerrainError(name, value, what) from None
    if (shape is not None and a.shape != shape) or (shape is None and a.size % 2) or np.any(np.isnan(a)) or np.any(a <= 0):
        raise TerrainError(name, value, what)
    return a


def _all_sides(sides: object) -> bool:
    """True when ``sides`` is a flat list of +1/-1."""
    try:
        a = np.asarray(sides).reshape(-1)
    except (TypeError, ValueError):
        return False
    return a.dtype.kind in "iuf" and bool(np.all((a == 1) | (a == -1)))


# ----------------------------------------------------------------------------- approach
def initial_feet(w: float = STEP_WIDTH) -> tuple[np.ndarray, np.ndarray]:
    """Standing feet (left, right) [m] at the start of every run."""
    positive_number("w", w, "m", hi=2.0, error=TerrainError)
    return np.array([0.0, 0.5 * w]), np.array([0.0, -0.5 * w])


def approach_footholds(
    n_steps: int = N_APPROACH, L_app: float = L_APPROACH, w: float = STEP_WIDTH
) -> StoneSequence:
    """Free approach footholds from standing: right foot first, step lengths
    ``L_app * j / n_steps`` (j = 1..n), lateral steps of ``w`` (straight walking)."""
    n = count("n_steps", n_steps, 2, error=ParameterError)
    if n % 2:
        raise ParameterError("n_steps", n_steps, "an even integer >= 2 (the approach ends on the left foot)")
    if not 0 < finite_number("L_app", L_app, "m", error=ParameterError) <= 0.6:
        raise ParameterError("L_app", L_app, "0 < L_app <= 0.6 [m]")
    left, right = initial_feet(w)
    x = 0.0
    centers, sides = [], []
    side = RIGHT
    for j in range(1, n + 1):
        x += L_app * j / n
        centers.append([x, right[1] if side == RIGHT else left[1]])
        sides.append(side)
        side = -side
    sizes = np.full((n, 2), np.inf)
    return StoneSequence(np.array(centers), sizes, np.array(sides), np.zeros(n, bool), "approach")


def entry_foothold(w: float = STEP_WIDTH) -> np.ndarray:
    """Last approach foothold (left foot) [m]; stones are placed relative to it."""
    return approach_footholds(w=w).centers[-1].copy()


# ----------------------------------------------------------------------------- profiles
def profile_steps(
    profile: str, seed: int | None = 0, L: float | None = None, W: float | None = None, n: int = N_STONES
) -> tuple[np.ndarray, np.ndarray]:
    """Relative step parameters ``(L^j, W^j)`` [m] of a profile (see module doc).

    Args:
        profile: "I", "II", "III" or "IV".
        seed: random seed of the U[.] draws (profiles II–IV).
        L, W: profile I step length / lateral offset [m] (defaults 0.4, 0.15); only for I.
        n: number of stones (the patterns of III/IV repeat beyond 32).
    """
    p = _profile_name(profile)
    n = count("n", n, 1)
    if p != "I" and (L is not None or W is not None):
        raise InvalidInputError("L/W", (L, W), "only with profile I (profiles II–IV draw or fix L and W)")
    if seed is not None:
        count("seed", seed, 0)
    rng = np.random.default_rng(seed)
    if p == "I":
        L = finite_number("L", 0.4 if L is None else L, "m", error=TerrainError)
        W = finite_number("W", 0.15 if W is None else W, "m", error=TerrainError)
        Ls, Ws = np.full(n, float(L)), np.full(n, float(W))
    elif p == "II":
        Ls, Ws = rng.uniform(0.2, 0.5, n), rng.uniform(-0.15, 0.15, n)
    elif p == "III":
        Ls = np.resize(np.r_[np.full(8, 0.2), np.full(8, 0.5)], n)
        Ws = rng.uniform(-0.15, 0.15, n)
    else:
        Ls = rng.uniform(0.2, 0.5, n)
        Ws = np.resize(np.r_[np.full(8, -0.1), np.full(8, 0.1)], n)
    return Ls, Ws


def stones_from_steps(
    Ls: Sequence[float],
    Ws: Sequence[float],
    start: Sequence[float] | None = None,
    first_side: int | str = RIGHT,
    w: float = STEP_WIDTH,
    size: Sequence[float] = STONE_SIZE,
    name: str = "stones",
) -> StoneSequence:
    """Chain relative steps ``[L^j, w_{l/r} + W^j]`` from ``start`` (default
    :func:`entry_foothold`) into world stones."""
    Ls = finite_array("Ls", Ls, None, "m", error=TerrainError).ravel()
    Ws = finite_array("Ws", Ws, None, "m", error=TerrainError).ravel()
    if Ls.size == 0 or Ls.shape != Ws.shape or not (np.all(np.isfinite(Ls)) and np.all(np.isfinite(Ws))):
        raise TerrainError("L/W", (Ls.tolist(), Ws.tolist()), "two equal-length, non-empty lists of finite numbers [m]")
    sz = finite_array("size", size, (2,), "m", error=TerrainError, what="(size_x, size_y)")
    if np.any(sz <= 0):
        raise TerrainError("size", size, "(size_x, size_y) > 0 [m]")
    p = entry_foothold(w) if start is None else finite_array("start", start, (2,), "m", error=TerrainError)
    side = parse_side(first_side)
    centers, sides = [], []
    for Lj, Wj in zip(Ls, Ws):
        p = p + np.array([Lj, side * w + Wj])
        centers.append(p)
        sides.append(side)
        side = -side
    n = len(centers)
    seq = StoneSequence(np.array(centers), np.tile(sz, (n, 1)), np.array(sides), np.ones(n, bool), name)
    return seq


def make_profile(
    profile: str,
    seed: int | None = 0,
    L: float | None = None,
    W: float | None = None,
    n: int = N_STONES,
    w: float = STEP_WIDTH,
    size: Sequence[float] = STONE_SIZE,
    limits: KinematicLimits = KinematicLimits(),
) -> StoneSequence:
    """Stones of profile I–IV in the world frame, after the approach (see module doc).

    Raises:
        TerrainError: if a stone cannot be reached from the previous one.
    """
    p = _profile_name(profile)
    Ls, Ws = profile_steps(p, seed, L, W, n)
    label = f"profile {p}" + (f" L={Ls[0]:g} W={Ws[0]:+g}" if p == "I" else f" seed {seed}")
    seq = stones_from_steps(Ls, Ws, w=w, size=size, name=label)
    seq.meta.update({"profile": p, "seed": seed, "L": Ls.tolist(), "W": Ws.tolist()})
    check_reachable(seq, entry_foothold(w), limits)
    return seq


def _profile_name(profile: object) -> str:
    p = str(profile).strip().upper() if isinstance(profile, (str, int)) else ""
    if p not in PROFILES:
        raise InvalidInputError("profile", profile, "one of I, II, III, IV")
    return p


# ----------------------------------------------------------------------------- checks
def check_reachable(seq: StoneSequence, start: Sequence[float], limits: KinematicLimits = KinematicLimits()) -> None:
    """Raise :class:`TerrainError` unless every stone can be reached from some point of
    the previous one (the first from ``start``) within the kinematic limits."""
    if not isinstance(seq, StoneSequence):
        raise TerrainError("stones", seq, "a lipmpcc.terrain.StoneSequence")
    if not isinstance(limits, KinematicLimits):
        raise ParameterError("limits", limits, "a lipmpcc.models.alip.KinematicLimits")
    prev_lo = prev_hi = finite_array("start", start, (2,), "m", error=TerrainError, what="an (x, y) foothold")
    _check_distinct(seq)
    for j in range(len(seq)):
        st = seq[j]
        lo, hi = limits.box(int(seq.sides[j]))
        # relative step range between the two rectangles
        d_lo = st.lower - prev_hi
        d_hi = st.upper - prev_lo
        if np.any(d_hi < lo - 1e-12) or np.any(d_lo > hi + 1e-12):
            side = "left" if seq.sides[j] == LEFT else "right"
            where, frame = f"stone {j}", ""
            if j == 0:  # a file written from the robot's start: say where the approach ends
                where = f"the start foothold ({prev_lo[0]:g}, {prev_lo[1]:g}) m"
                frame = ("; stones are in the world frame: the robot starts at the origin and its approach "
                         "steps end there, so the first stone lies ahead of it (docs/formats.md)")
            raise TerrainError(
                f"stone {j + 1}",
                tuple(float(v) for v in st.center),
                f"a stone reachable from {where} by a {side} step",
                f"|dx| <= {limits.x_max:g} m and {limits.y_min:g} <= |dy| <= {limits.y_max:g} m on the "
                f"{side}; the stones are impossibly spaced{frame}",
            )
        prev_lo, prev_hi = st.lower, st.upper


def _check_distinct(seq: StoneSequence) -> None:
    """Raise :class:`TerrainError` when two consecutive stones are on the same spot (both feet on
    one stone: a stone file with a row written twice)."""
    c = seq.centers
    if len(c) < 2:
        return
    same = np.flatnonzero(np.all(np.abs(np.diff(c, axis=0)) < 1e-6, axis=1) & seq.is_stone[1:] & seq.is_stone[:-1])
    if same.size:
        j = int(same[0]) + 1
        raise TerrainError(
            f"stone {j + 1}", tuple(float(v) for v in c[j]), f"a different position from stone {j}",
            "two consecutive stones are on the same spot: each step lands on its own stone",
        )


# ----------------------------------------------------------------------------- files
def load_stones(
    path: str | Path,
    w: float = STEP_WIDTH,
    default_size: Sequence[float] = STONE_SIZE,
    limits: KinematicLimits = KinematicLimits(),
) -> StoneSequence:
    """Read a stone file: rows ``x,y[,size_x,size_y]`` [m], world frame, one per footstep.

    The first stone is for the right foot and sides alternate; stone 1 must be reachable
    from :func:`entry_foothold`.

    Raises:
        TerrainError: missing/empty file, bad row, NaN/inf, size <= 0, or impossibly spaced
            stones (the message names the row).
    """
    text = read_text_file("stones file", path, "CSV file of rows x,y[,size_x,size_y]", error=TerrainError)
    p = Path(path)
    default_size = tuple(float(v) for v in _sizes("default_size", default_size, (2,)))
    rows: list[list[float]] = []
    with io.StringIO(text, newline="") as f:
        for lineno, row in enumerate(csv.reader(f), start=1):
            cells = [c.strip() for c in row]
            if not cells or all(c == "" for c in cells) or cells[0].startswith("#"):
                continue
            try:
                vals = [float(c) for c in cells if c != ""]
            except ValueError:
                if not rows and any(c.lower() in ("x", "y", "size_x", "size_y") for c in cells):
                    continue  # header
                raise TerrainError(f"{p.name} line {lineno}", ",".join(cells), "numbers x,y[,size_x,size_y] [m]") from None
            if len(vals) not in (2, 4):
                raise TerrainError(f"{p.name} line {lineno}", ",".join(cells), "2 or 4 numbers: x,y[,size_x,size_y] [m]")
            if not all(math.isfinite(v) for v in vals):
                raise TerrainError(f"{p.name} line {lineno}", ",".join(cells), "finite numbers (no NaN or inf)")
            if len(vals) == 2:
                vals += list(default_size)
            if not (0 < vals[2] <= MAX_STONE_SIZE and 0 < vals[3] <= MAX_STONE_SIZE):
                raise TerrainError(f"{p.name} line {lineno}", ",".join(cells), f"stone sizes > 0 and <= {MAX_STONE_SIZE:g} [m]")
            rows.append(vals)
    if not rows:
        raise TerrainError("stones file", str(path), "at least one row x,y[,size_x,size_y]", "the file is empty")
    a = np.array(rows)
    n = len(a)
    sides = np.array([RIGHT if j % 2 == 0 else LEFT for j in range(n)])
    seq = StoneSequence(a[:, :2], a[:, 2:4], sides, np.ones(n, bool), p.stem, {"file": str(p)})
    check_reachable(seq, entry_foothold(w), limits)
    return seq


def save_stones(seq: StoneSequence, path: str | Path, comment: str = "") -> Path:
    """Write the stones of ``seq`` (``is_stone`` rows only) as ``x,y,size_x,size_y``."""
    p = Path(path)
    p.parent.mkdir(parents=True, exist_ok=True)
    with open(p, "w", newline="") as f:
        f.write("# lipmpcc stepping stones, world frame [m]; first stone = right foot\n")
        if comment:
            for line in comment.splitlines():
                f.write(f"# {line}\n")
        f.write("x,y,size_x,size_y\n")
        for c, s, ok in zip(seq.centers, seq.sizes, seq.is_stone):
            if ok:
                f.write(f"{c[0]:.6f},{c[1]:.6f},{s[0]:.6f},{s[1]:.6f}\n")
    return p


def paper_case_path(profile: str, seed: int = 0, L: float | None = None, W: float | None = None) -> Path:
    """Where ``data/stones/`` keeps a paper case."""
    from .resources import data_path

    p = _profile_name(profile)
    if p == "I":
        L = 0.4 if L is None else finite_number("L", L, "m", error=TerrainError)
        W = 0.15 if W is None else finite_number("W", W, "m", error=TerrainError)
        return data_path("stones", f"profile_I_L{L:.2f}_W{W:+.2f}.csv")
    return data_path("stones", f"profile_{p}_seed{count('seed', seed, 0)}.csv")


def paper_cases() -> list[dict]:
    """The study's cases: 6 of profile I, seeds 0–4 of II, III and IV."""
    cases: list[dict] = []
    for W in (0.15, -0.15):
        for L in (0.2, 0.4, 0.55):
            cases.append({"profile": "I", "L": L, "W": W, "seed": 0})
    for p in ("II", "III", "IV"):
        for s in range(5):
            cases.append({"profile": p, "L": None, "W": None, "seed": s})
    return cases
