"""Stepping-stone profiles I–IV, the approach, stone files and their errors."""

from __future__ import annotations

import numpy as np
import pytest

from lipmpcc.exceptions import InvalidInputError, ParameterError, TerrainError
from lipmpcc.models.alip import LEFT, RIGHT
from lipmpcc.terrain import (
    N_STONES,
    Stone,
    StoneSequence,
    approach_footholds,
    entry_foothold,
    initial_feet,
    load_stones,
    stones_from_steps,
    make_profile,
    paper_case_path,
    paper_cases,
    profile_steps,
    save_stones,
)


def rel_steps(seq):
    c = np.vstack([entry_foothold(), seq.centers])
    return np.diff(c, axis=0)


@pytest.mark.parametrize("L", [0.2, 0.4, 0.55])
@pytest.mark.parametrize("W", [0.15, -0.15])
def test_profile_I_geometry(L, W):
    seq = make_profile("I", L=L, W=W)
    assert len(seq) == N_STONES == 32
    np.testing.assert_allclose(seq.sizes, np.tile([0.2, 0.1], (32, 1)))
    assert seq.sides[0] == RIGHT and np.all(seq.sides[1:] == -seq.sides[:-1])
    d = rel_steps(seq)
    np.testing.assert_allclose(d[:, 0], L)
    np.testing.assert_allclose(d[:, 1], seq.sides * 0.28 + W)
    assert seq.is_stone.all()


def test_random_profiles_ranges_patterns_and_seeds():
    for p in ("II", "III", "IV"):
        L, W = profile_steps(p, seed=3)
        assert L.shape == W.shape == (32,)
        assert np.all((0.2 <= L) & (L <= 0.5))
        assert np.all((-0.15 <= W) & (W <= 0.15))
        L2, W2 = profile_steps(p, seed=3)
        np.testing.assert_array_equal(L, L2)
        np.testing.assert_array_equal(W, W2)
        L3, W3 = profile_steps(p, seed=4)
        assert not (np.array_equal(L, L3) and np.array_equal(W, W3))
    L, _ = profile_steps("III", seed=0)
    np.testing.assert_array_equal(L, [0.2] * 8 + [0.5] * 8 + [0.2] * 8 + [0.5] * 8)
    _, W = profile_steps("IV", seed=0)
    np.testing.assert_array_equal(W, [-0.1] * 8 + [0.1] * 8 + [-0.1] * 8 + [0.1] * 8)
    seq = make_profile("II", seed=1)
    np.testing.assert_allclose(rel_steps(seq)[:, 0], profile_steps("II", seed=1)[0])


def test_approach_from_standing():
    app = approach_footholds()
    left, right = initial_feet()
    np.testing.assert_allclose(left, [0, 0.14])
    np.testing.assert_allclose(right, [0, -0.14])
    assert len(app) == 6 and not app.is_stone.any()
    assert app.sides[0] == RIGHT and app.sides[-1] == LEFT  # stones start with a right swing
    assert np.all(np.isinf(app.sizes))
    np.testing.assert_allclose(np.diff(np.r_[0.0, app.centers[:, 0]]), 0.3 * np.arange(1, 7) / 6)
    np.testing.assert_allclose(entry_foothold(), [1.05, 0.14])
    assert Stone((0, 0), (np.inf, np.inf)).is_free


def test_saved_paper_cases_match_the_generator():
    for c in paper_cases():
        path = paper_case_path(c["profile"], c["seed"], c["L"], c["W"])
        assert path.is_file(), path
        loaded = load_stones(path)
        gen = make_profile(c["profile"], c["seed"], c["L"], c["W"])
        np.testing.assert_allclose(loaded.centers, gen.centers, atol=1e-6)
        np.testing.assert_allclose(loaded.sizes, gen.sizes, atol=1e-9)
        np.testing.assert_array_equal(loaded.sides, gen.sides)
    assert len(paper_cases()) == 21


def test_load_user_file_formats(tmp_path):
    f = tmp_path / "s.csv"
    f.write_text("# my stones\nx,y,size_x,size_y\n1.45,-0.14\n\n1.85,0.14,0.3,0.2\n")
    seq = load_stones(f)
    np.testing.assert_allclose(seq.centers, [[1.45, -0.14], [1.85, 0.14]])
    np.testing.assert_allclose(seq.sizes, [[0.2, 0.1], [0.3, 0.2]])
    assert list(seq.sides) == [RIGHT, LEFT]
    out = save_stones(seq, tmp_path / "back.csv")
    np.testing.assert_allclose(load_stones(out).centers, seq.centers)


@pytest.mark.parametrize(
    "text, word",
    [
        ("", "empty"),
        ("# only a comment\n", "empty"),
        ("x,y\n", "empty"),
        ("1.45,nan\n", "finite"),
        ("1.45,-0.14,inf,0.1\n", "finite"),
        ("1.45\n", "2 or 4 numbers"),
        ("1.45,-0.14,0.2\n", "2 or 4 numbers"),
        ("1.45,abc\n", "numbers"),
        ("1.45,-0.14,0.2,0\n", "sizes > 0"),
        ("1.45,-0.14\n3.0,0.14\n", "impossibly spaced"),  # 1.55 m gap
        ("1.45,-0.14\n1.85,-0.2\n", "impossibly spaced"),  # left foot right of the right foot
        ("2.5,-0.14\n", "impossibly spaced"),  # out of reach of the entry foothold
    ],
)
def test_bad_stone_files(tmp_path, text, word):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(TerrainError) as e:
        load_stones(f)
    assert word in str(e.value)


def test_a_file_written_from_the_robots_start_is_told_where_the_approach_ends(tmp_path):
    # issue 15: stones written relative to the robot (first stone 0.3 m ahead of the origin) lie behind the
    # approach's last foothold; the one-line error names that foothold and the frame
    f = tmp_path / "from_start.csv"
    f.write_text("x,y\n0.30,-0.14\n0.60,0.14\n")
    with pytest.raises(TerrainError) as e:
        load_stones(f)
    msg = str(e.value)
    assert "stone 1" in msg and "(1.05, 0.14) m" in msg and "world frame" in msg and "\n" not in msg


def test_missing_file_and_bad_arguments(tmp_path):
    with pytest.raises(TerrainError, match="existing CSV"):
        load_stones(tmp_path / "nope.csv")
    with pytest.raises(InvalidInputError, match="profile"):
        make_profile("V")
    with pytest.raises(InvalidInputError, match="only with profile I"):
        make_profile("II", L=0.3)
    with pytest.raises(InvalidInputError, match="seed"):
        make_profile("II", seed=-1)
    with pytest.raises(InvalidInputError, match="n"):
        profile_steps("II", n=0)
    with pytest.raises(TerrainError, match="impossibly spaced"):
        make_profile("I", L=0.9)
    with pytest.raises(TerrainError, match="impossibly spaced"):
        make_profile("I", L=0.4, W=0.3)  # inner lateral step -0.28 + 0.3 > 0 for a right foot
    with pytest.raises(TerrainError, match="finite"):
        make_profile("I", L=float("nan"))
    with pytest.raises(ParameterError, match="n_steps"):
        approach_footholds(n_steps=5)
    with pytest.raises(InvalidInputError, match="n"):
        make_profile("I").head(0)


def test_stone_sequence_rejects_mismatched_arrays():
    from lipmpcc.exceptions import TerrainError

    with pytest.raises(TerrainError):
        StoneSequence(np.zeros((2, 2)), np.ones((3, 2)), np.array([1, -1]), np.array([True, True]))


# ---- issue 14: one validation layer -------------------------------------------------------------
def test_two_stones_on_the_same_spot_are_refused(tmp_path):
    from lipmpcc.terrain import load_stones

    f = tmp_path / "twice.csv"
    f.write_text("x,y\n1.35,-0.14\n1.35,-0.14\n")
    with pytest.raises(TerrainError, match=r"stone 2 = \(1.35, -0.14\): expected a different position from stone 1 .*same spot"):
        load_stones(f)


def test_binary_stone_file_is_refused_clearly(tmp_path):
    from lipmpcc.terrain import load_stones

    f = tmp_path / "stones.csv"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\xff")
    with pytest.raises(TerrainError, match=r"stones.csv.*UTF-8 text.*the file is binary"):
        load_stones(f)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: Stone(("a", 0.0)), r"center = \('a', 0.0\)"),
        (lambda: Stone((0.0, float("nan"))), r"center.*NaN"),
        (lambda: Stone((0.0, 0.0), (0.2, -0.1)), r"size = \(0.2, -0.1\): expected stone sizes"),
        (lambda: StoneSequence([[0, 0]], [[0.2, 0.1]], [2], [True]), r"sides = \[2\]"),
        (lambda: StoneSequence("ab", [[0.2, 0.1]], [1], [True]), r"centers = 'ab'"),
        (lambda: StoneSequence([[0, 0]], [[0.2, float("nan")]], [1], [True]), r"sizes"),
    ],
)
def test_bad_stones_are_named(make, match):
    with pytest.raises(TerrainError, match=match):
        make()


def test_counts_and_numbers_of_profiles():
    from lipmpcc.terrain import make_profile, profile_steps

    Ls, Ws = profile_steps("I", L=np.float32(0.4), W=np.float64(0.15), n=np.int64(3))
    assert len(Ls) == 3 and Ls[0] == pytest.approx(0.4)
    with pytest.raises(InvalidInputError, match=r"n = 2.5"):
        profile_steps("II", n=2.5)
    with pytest.raises(TerrainError, match=r"L = 'long'"):
        profile_steps("I", L="long")
    with pytest.raises(InvalidInputError, match=r"seed = -1"):
        make_profile("II", seed=-1)
    seq = make_profile("II", seed=np.int64(1))
    with pytest.raises(InvalidInputError, match=r"n = 0"):
        seq.head(0)
    assert len(seq.head(np.int64(4))) == 4


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: initial_feet("wide"), r"w = 'wide'"),
        (lambda: approach_footholds(n_steps="x"), r"n_steps = 'x'"),
        (lambda: approach_footholds(L_app=None), r"L_app = None"),
        (lambda: make_profile("II", limits="loose"), r"limits = 'loose'"),
        (lambda: stones_from_steps("x", [0.0]), r"Ls = 'x'"),
        (lambda: stones_from_steps([0.3], [0.0], start="origin"), r"start = 'origin'"),
        (lambda: stones_from_steps([0.3], [0.0], size="big"), r"size = 'big'"),
        (lambda: paper_case_path("I", L="long"), r"L = 'long'"),
        (lambda: paper_case_path("II", seed=1.5), r"seed = 1.5"),
    ],
)
def test_bad_terrain_arguments_are_named(call, match):
    with pytest.raises(InvalidInputError, match=match):
        call()


def test_a_stone_file_with_an_absurd_stone_size_is_refused(tmp_path) -> None:
    import pytest

    from lipmpcc.exceptions import TerrainError
    from lipmpcc.terrain import MAX_STONE_SIZE, load_stones

    f = tmp_path / "s.csv"
    f.write_text("1.35,-0.14,1e9,0.1\n")
    with pytest.raises(TerrainError, match=rf"s.csv line 1 = '1.35,-0.14,1e9,0.1': expected stone sizes > 0 and <= {MAX_STONE_SIZE:g}"):
        load_stones(f)
