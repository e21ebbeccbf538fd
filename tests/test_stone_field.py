"""The stone field (issue 29): the seeded generator, its validation and the JSON file format."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, TerrainError
from lipmpcc.stone_field import (
    StoneField,
    field_to_dict,
    load_stone_field,
    make_stone_field,
    save_stone_field,
)


def test_same_seed_same_field_other_seed_other_field() -> None:
    a, b, c = make_stone_field(3), make_stone_field(3), make_stone_field(4)
    assert np.array_equal(a.centers, b.centers) and np.array_equal(a.path, b.path)
    assert a.goal_center == b.goal_center
    assert a.centers.shape != c.centers.shape or not np.allclose(a.centers, c.centers)


@pytest.mark.parametrize("seed", [0, 7, 19, 34])
def test_generated_field_has_the_issue_geometry(seed: int) -> None:
    f = make_stone_field(seed, pedestrian_speed=0.45)
    assert np.allclose(f.sizes, (0.2, 0.1))
    assert np.all(np.abs(f.lateral_offset(f.centers)) <= 0.75 + 1e-9)  # 1.5 m corridor
    nb = f.meta["n_backbone"]
    assert f.n_stones > nb + 5  # more stones than the way needs: the planner chooses
    back = f.centers[:nb]
    gaps = np.diff(np.r_[1.05, back[:, 0]]) - 0.2  # edge to edge along the path (the first from the entry foot)
    assert np.all(gaps >= -1e-9) and np.all(gaps <= 0.3 + 1e-9)
    assert f.goal.lower[0] - (back[-1, 0] + 0.1) <= 0.3 + 1e-9
    across = np.abs(np.diff(np.r_[0.14, back[:, 1]]))  # feet alternate: every step within the lateral limits
    assert np.all(across >= 0.16 - 1e-9) and np.all(across <= 0.42 + 1e-9)
    (ped,) = f.pedestrians
    assert ped.axes[0] == pytest.approx(0.25) and np.hypot(*ped.velocity) == pytest.approx(0.45)


def test_no_pedestrian_by_default_and_density_sets_the_count() -> None:
    sparse, dense = make_stone_field(1, density=2.0), make_stone_field(1, density=5.0)
    assert sparse.pedestrians == () and dense.n_stones > sparse.n_stones


@pytest.mark.parametrize(
    "kw, name",
    [({"max_gap": 0.5}, "max_gap"), ({"corridor_width": float("nan")}, "corridor_width"),
     ({"stone_size": (0.2,)}, "stone_size"), ({"pedestrian_speed": -1.0}, "pedestrian_speed"),
     ({"seed": -1}, "seed"), ({"density": 1e9}, "density")],
)
def test_bad_generator_arguments_name_the_value(kw: dict, name: str) -> None:
    with pytest.raises(InvalidInputError, match=name):
        make_stone_field(**kw)


def _field(**kw: object) -> StoneField:
    args = dict(centers=[[1.4, -0.14], [1.7, 0.14]], sizes=[[0.2, 0.1], [0.2, 0.1]], path=[[1.05, 0.0], [2.5, 0.0]],
                corridor_width=1.0, goal_center=(2.8, 0.0), goal_size=(0.6, 1.0))
    args.update(kw)
    return StoneField(**args)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "kw, match",
    [({"centers": [[1.4, -0.14], [1.45, -0.12]]}, "stone 1.*overlap"),
     ({"centers": [[1.4, -0.14], [1.7, 0.9]]}, "stone 1.*corridor"),
     ({"centers": [[1.4, -0.14], [2.8, 0.0]]}, "stone 1.*goal"),
     ({"sizes": [[0.2, 0.1], [0.0, 0.1]]}, "stone 1 size"),
     ({"path": [[2.0, 0.0], [1.0, 0.0]]}, "path"),
     ({"centers": [[1.4, float("nan")], [1.7, 0.14]]}, "centers")],
)
def test_bad_fields_are_refused_naming_the_stone(kw: dict, match: str) -> None:
    with pytest.raises(TerrainError, match=match):
        _field(**kw)


def test_geometry_helpers() -> None:
    f = _field()
    assert f.stone_at((1.45, -0.12)) == 0 and f.stone_at((1.55, 0.0)) is None
    assert f.in_goal((2.7, 0.3)) and not f.in_goal((2.4, 0.0))
    assert f.lateral_offset([[2.0, 0.3], [2.0, -0.2]]) == pytest.approx([0.3, -0.2])


def test_file_round_trip(tmp_path) -> None:
    f = make_stone_field(5, pedestrian_speed=0.3)
    p = save_stone_field(f, tmp_path / "sub" / "field.json")
    g = load_stone_field(p)
    assert np.allclose(g.centers, f.centers) and np.allclose(g.sizes, f.sizes) and np.allclose(g.path, f.path)
    assert g.goal_center == pytest.approx(f.goal_center) and g.seed == 5 and g.corridor_width == f.corridor_width
    assert g.pedestrians[0].position == pytest.approx(f.pedestrians[0].position)
    assert g.pedestrians[0].velocity == pytest.approx(f.pedestrians[0].velocity)


@pytest.mark.parametrize(
    "edit, match",
    [(lambda d: d.update(format="csv"), "format"),
     (lambda d: d.pop("goal"), "goal"),
     (lambda d: d["stones"].append([1.0, 2.0]), "stones"),
     (lambda d: d["pedestrians"].append({"position": [0, 0], "velocity": [50, 0], "radius": 0.2}), "pedestrians"),
     (lambda d: d["stones"].append(list(d["stones"][0])), "overlap")],
)
def test_bad_files_name_the_entry(tmp_path, edit, match: str) -> None:
    d = field_to_dict(make_stone_field(2))
    edit(d)
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(d))
    with pytest.raises(TerrainError, match=match):
        load_stone_field(p)
    p.write_text("{not json")
    with pytest.raises(TerrainError, match="line 1"):
        load_stone_field(p)
