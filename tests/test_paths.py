"""lipmpcc.paths: arc-length parametrisation, derivatives, CasADi parity, closest point, bad input."""

import math

import casadi as ca
import numpy as np
import pytest

from lipmpcc.exceptions import PathError
from lipmpcc.paths import ArcPath, CompositePath, LinePath, SplinePath, load_path_csv, load_waypoints_csv, path_from_waypoints


def _paths():
    line = LinePath((0, 0), (3, 4))
    arc = ArcPath.circle(2.0, start=(1, 1), heading=0.3)
    spline = SplinePath([[0, 0], [1, 0.5], [2, 0], [3, -0.5], [4, 0]])
    l1 = LinePath((0, 0), (2, 0))
    a1 = ArcPath((2, 1), 1.0, start_angle=-math.pi / 2, sweep=math.pi / 2)
    l2 = LinePath((3, 1), (3, 3))
    return {"line": line, "arc": arc, "spline": spline, "composite": CompositePath([l1, a1, l2])}


@pytest.mark.parametrize("name", ["line", "arc", "spline", "composite"])
def test_arc_length_parametrisation(name):
    p = _paths()[name]
    s = np.linspace(0, p.length, 2001)
    pts = p.position(s)
    chord = np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1))
    assert chord == pytest.approx(p.length, rel=1e-4)
    # unit speed: |dy/dθ| = 1 up to the spline's re-sampling error
    d = np.gradient(pts, s, axis=0)
    assert np.allclose(np.linalg.norm(d[5:-5], axis=1), 1.0, atol=2e-3)


@pytest.mark.parametrize("name", ["line", "arc", "spline", "composite"])
def test_casadi_matches_numeric(name):
    p = _paths()[name]
    th = ca.SX.sym("th")
    f = ca.Function("f", [th], [p.casadi_position(th), p.casadi_slope(th), p.casadi_tangent(th), p.casadi_curvature(th)])
    for s in np.linspace(0.01, p.length - 0.01, 17):
        pos, phi, tan, kap = (np.asarray(v).ravel() for v in f(s))
        assert np.allclose(pos, p.position(s), atol=1e-9)
        assert math.isclose(math.remainder(float(phi[0]) - p.slope(s), 2 * math.pi), 0.0, abs_tol=1e-9)
        assert np.allclose(tan, p.tangent(s), atol=1e-9)
        assert float(kap[0]) == pytest.approx(p.curvature(s), abs=1e-6)


def test_circle_geometry():
    c = ArcPath.circle(2.0)
    assert c.length == pytest.approx(4 * math.pi)
    assert np.allclose(c.position(0.0), [0, 0])
    assert c.slope(0.0) == pytest.approx(0.0)
    assert np.allclose(c.curvature(np.linspace(0, c.length, 9)), 0.5)
    assert np.allclose(c.position(2 * math.pi), [0, 4], atol=1e-12)  # half-way round
    assert np.allclose(c.position(math.pi), [2, 2], atol=1e-12)  # a quarter
    cw = ArcPath((0, 0), 1.0, 0.0, -math.pi)
    assert cw.curvature(0.5) == pytest.approx(-1.0)


def test_spline_passes_through_waypoints_and_is_c2():
    w = np.array([[0, 0], [1, 1], [2, 0], [3, 1]])
    sp = SplinePath(w, ds=0.02)
    s = np.linspace(0, sp.length, 4000)
    d = np.min(np.linalg.norm(sp.position(s)[:, None, :] - w[None], axis=2), axis=0)
    assert np.all(d < 2e-3)
    k = sp.curvature(s)
    assert np.max(np.abs(np.diff(k))) < 0.05  # curvature continuous (C²)


def test_composite_is_continuous():
    p = _paths()["composite"]
    assert p.length == pytest.approx(2 + math.pi / 2 + 2)
    for b in p.offsets[1:-1]:
        assert np.allclose(p.position(b - 1e-9), p.position(b + 1e-9), atol=1e-7)
        assert np.allclose(p.tangent(b - 1e-9), p.tangent(b + 1e-9), atol=1e-6)


@pytest.mark.parametrize("name", ["line", "arc", "spline", "composite"])
def test_closest_point_recovers_offset_points(name):
    p = _paths()[name]
    rng = np.random.default_rng(0)
    for s in rng.uniform(0.2, p.length - 0.2, 10):
        n = np.array([-p.tangent(s)[1], p.tangent(s)[0]])
        q = p.position(s) + 0.05 * n
        assert p.closest_point(q, theta_prev=s - 0.1) == pytest.approx(s, abs=2e-4)
        assert p.closest_point(q) == pytest.approx(s, abs=2e-4)


def test_closest_point_local_search_does_not_jump():
    # a hairpin: the path comes back 0.3 m from itself
    p = SplinePath([[0, 0], [4, 0], [5, 0.15], [4, 0.3], [0, 0.3]], ds=0.02)
    q = np.array([1.0, 0.17])  # nearer the return leg than the outbound leg
    s_global = p.closest_point(q)
    s_local = p.closest_point(q, theta_prev=1.0)
    assert s_global > p.length / 2  # the global argmin jumps to the return leg
    assert s_local == pytest.approx(1.0, abs=0.05)  # the local search stays on the outbound leg
    # the full circle: the start point is also the end point
    c = ArcPath.circle(2.0)
    assert c.closest_point([0.01, -0.01], theta_prev=c.length - 0.1) == pytest.approx(c.length, abs=1e-9)
    assert c.closest_point([0.01, -0.01], theta_prev=0.1) == pytest.approx(0.0099, abs=1e-3)


def test_csv_roundtrip(tmp_path):
    f = tmp_path / "wp.csv"
    f.write_text("x,y\n0,0\n1,0.5\n2,0\n")
    w = load_waypoints_csv(f)
    assert w.shape == (3, 2)
    p = load_path_csv(f)
    assert isinstance(p, SplinePath)
    f2 = tmp_path / "two.csv"
    f2.write_text("y,x\n0,0\n0,2\n")
    assert isinstance(load_path_csv(f2), LinePath)
    assert load_path_csv(f2).length == pytest.approx(2.0)


@pytest.mark.parametrize(
    "content, match",
    [
        ("x,y\n0,0\n", "at least two waypoints"),
        ("a,b\n0,0\n1,1\n", "columns x,y"),
        ("x,y\n0,0\nfoo,1\n", "two numbers"),
        ("x,y\n0,0\nnan,1\n", "finite"),
        ("x,y\n1,1\n1,1\n1,1\n", "two distinct points"),
    ],
)
def test_csv_errors(tmp_path, content, match):
    f = tmp_path / "bad.csv"
    f.write_text(content)
    with pytest.raises(PathError, match=match):
        load_path_csv(f)


def test_csv_missing_file(tmp_path):
    with pytest.raises(PathError, match="existing CSV"):
        load_path_csv(tmp_path / "nope.csv")


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: SplinePath([[0, 0]]), "two distinct points"),
        (lambda: SplinePath([[0, 0], [0, 0]]), "two distinct points"),
        (lambda: SplinePath([[0, 0], [np.nan, 1], [2, 2]]), "NaN"),
        (lambda: SplinePath([1, 2, 3]), r"\(n, 2\)"),
        (lambda: LinePath((0, 0), (0, 0)), "zero length"),
        (lambda: LinePath((0, np.inf), (1, 0)), "finite"),
        (lambda: ArcPath((0, 0), 0.0), "radius > 0"),
        (lambda: ArcPath((0, 0), -1.0), "radius > 0"),
        (lambda: ArcPath.circle(float("nan")), "radius > 0"),
        (lambda: ArcPath((0, 0), 1.0, sweep=0.0), "zero length"),
        (lambda: CompositePath([LinePath((0, 0), (1, 0)), LinePath((2, 0), (3, 0))]), "gap"),
        (lambda: CompositePath([]), "at least one path"),
    ],
)
def test_bad_paths(make, match):
    with pytest.raises(PathError, match=match):
        make()


def test_bad_theta():
    with pytest.raises(PathError, match="finite"):
        LinePath((0, 0), (1, 0)).position(float("nan"))
    with pytest.raises(PathError, match="2-vector"):
        LinePath((0, 0), (1, 0)).closest_point([1, 2, 3])


# ---- issue 14: one validation layer -------------------------------------------------------------
def test_circle_accepts_numpy_numbers():
    c = ArcPath.circle(np.int64(2))
    assert c.radius == 2.0 and c.length == pytest.approx(4 * np.pi)
    assert ArcPath.circle(np.float32(1.5), heading=np.float64(0.1), turns=np.int64(1)).radius == 1.5
    assert ArcPath(np.array([0, 0]), np.int32(3)).radius == 3.0


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: path_from_waypoints([[0, 0], [2e-9, 0]]), r"waypoints = .*spanning at least 0.001 m.*degenerate"),
        (lambda: path_from_waypoints([[0, 0], [1, 0], [0, 0], [1, 0]]), r"never turns back.*180 deg at waypoint 1"),
        (lambda: SplinePath([[0, 0], [1e-5, 0], [2e-5, 1e-6]]), r"at least 0.001 m long"),
        (lambda: ArcPath.circle(1e-5), r"at least 0.001 m long"),
        (lambda: ArcPath.circle("big"), r"radius = 'big': expected a finite radius > 0"),
        (lambda: ArcPath.circle(True), r"radius = True"),
        (lambda: ArcPath.circle(2.0, heading="north"), r"heading = 'north'"),
        (lambda: ArcPath.circle(1e9), r"radius.*<= 10000 \[m\]"),
        (lambda: ArcPath.circle(2.0, turns=1e9), r"turns = 1000000000.0: expected a finite number >= -100 and <= 100"),
        (lambda: SplinePath([[0, 0], [5000, 100], [9000, 0]], ds=1e-4), r"ds = 0.0001: expected a resampling step >= "),
        (lambda: LinePath((0, 0), (1e300, 0)), r"within \+-10000 m"),
        (lambda: LinePath("ab", (1, 0)), r"start = 'ab': expected a 2-vector"),
        (lambda: path_from_waypoints("abc"), r"waypoints = 'abc'"),
        (lambda: path_from_waypoints([[0, 0], [1, "x"]]), r"\(n, 2\) array"),
        (lambda: SplinePath([[0, 0], [1, 1], [2, 0]], ds=0), r"ds = 0"),
        (lambda: SplinePath([[1, 1]] * 4), r"two distinct points.*all 4 waypoints are the point \[1.0, 1.0\]"),
        (lambda: CompositePath(LinePath((0, 0), (1, 0))), r"a list of at least one path"),
    ],
)
def test_bad_paths_are_named(make, match):
    with pytest.raises(PathError, match=match):
        make()


def test_bad_queries_are_named():
    line = LinePath((0, 0), (1, 0))
    with pytest.raises(PathError, match=r"theta = 'a'"):
        line.position("a")
    with pytest.raises(PathError, match=r"n = 1\.5"):
        line.sample(1.5)
    with pytest.raises(PathError, match=r"theta_prev = 'x'"):
        line.closest_point([0, 0], theta_prev="x")
    with pytest.raises(PathError, match=r"window"):
        line.closest_point([0, 0], theta_prev=0.0, window=(1.0,))
    with pytest.raises(PathError, match=r"resolution = 0"):
        line.closest_point([0, 0], resolution=0)
    assert line.sample(np.int64(3)).shape == (3, 2)


def test_same_waypoint_in_a_csv_names_the_file_and_point(tmp_path):
    f = tmp_path / "same.csv"
    f.write_text("1,1\n1,1\n1,1\n1,1\n")
    with pytest.raises(PathError, match=r"same.csv.*two distinct points.*all 4 rows are the point \(1, 1\)"):
        load_path_csv(f)


def test_binary_path_file_is_refused_clearly(tmp_path):
    f = tmp_path / "image.csv"
    f.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    with pytest.raises(PathError, match=r"image.csv.*UTF-8 text.*the file is binary"):
        load_path_csv(f)
    with pytest.raises(PathError, match=r"no such file"):
        load_path_csv(tmp_path / "none.csv")


def test_check_loops_refuses_a_crossing_with_a_loop_shorter_than_the_search_window_only():
    """issue 31: the closest-point search looks 1 m back and 2 m ahead; a path crossing itself with a
    loop within that is refused (naming where), a longer loop and paper A's 1.25 turns are accepted."""
    import numpy as np

    from lipmpcc.exceptions import PathError
    from lipmpcc.paths import CLOSEST_POINT_WINDOW, ArcPath, check_loops, path_from_waypoints

    assert sum(CLOSEST_POINT_WINDOW) == 3.0
    small = path_from_waypoints([(0, 0), (2, 0), (2.5, 0.4), (2.2, 0.8), (1.8, 0.4), (2.2, -0.3), (2.5, -1.5)])
    with pytest.raises(PathError, match=r"crossing itself at arc lengths 1\.9\d and 4\.3\d m"):
        check_loops(small, "mine")
    check_loops(path_from_waypoints([(0, 0), (4, 0), (6, 1.5), (5, 3), (3.5, 2), (4, -1), (4.5, -3)]))  # a pretzel
    check_loops(ArcPath.circle(2.0, start=(0.0, 0.0), heading=0.0, turns=1.25))
    check_loops(path_from_waypoints(np.column_stack([np.linspace(0, 1000, 200), 3 * np.sin(np.linspace(0, 30, 200))])))


def test_extended_path_runs_straight_past_the_end_and_is_the_base_before_it():
    from lipmpcc.paths import ExtendedPath

    base = ArcPath.circle(2.0, turns=0.25)  # a quarter circle: the end tangent is not the x axis
    ext = ExtendedPath(base, 1.5)
    assert ext.length == pytest.approx(base.length + 1.5) and ext.end_length == base.length
    th = np.linspace(0.0, base.length, 7)
    assert np.allclose(ext.position(th), base.position(th)) and np.allclose(ext.slope(th), base.slope(th))
    t_end, p_end = base.tangent(base.length), base.position(base.length)
    for run in (0.3, 1.5):
        assert np.allclose(ext.position(base.length + run), p_end + run * t_end)
        assert ext.slope(base.length + run) == pytest.approx(base.slope(base.length))
        assert ext.curvature(base.length + run) == pytest.approx(0.0)
    s = ca.SX.sym("s")
    f = ca.Function("f", [s], list(ext.casadi_derivs(s)))
    for v in (0.5 * base.length, base.length + 0.7):
        p, d = (np.asarray(a).ravel() for a in f(v))
        assert np.allclose(p, ext.position(v), atol=1e-9)
        assert np.allclose(d / np.linalg.norm(d), ext.tangent(v), atol=1e-9)
    with pytest.raises(PathError, match="extra"):
        ExtendedPath(base, 0.0)


@pytest.mark.parametrize("name", list(_paths()) + ["extended"])
def test_frame_gives_the_numbers_of_position_and_slope_bit_for_bit(name):
    """The planners' unchecked ``_frame`` (issue 28) is position and slope in one evaluation, clipping included."""
    from lipmpcc.paths import ExtendedPath

    path = ExtendedPath(ArcPath.circle(2.0, turns=0.5), 1.0) if name == "extended" else _paths()[name]
    theta = np.concatenate([[-0.3, 0.0], np.linspace(0.1, path.length - 0.1, 13), [path.length, path.length + 0.7]])
    p, phi = path._frame(theta)
    assert np.array_equal(p, path.position(theta)) and np.array_equal(phi, path.slope(theta))
