"""The pedestrians' motion models against forces and encounters worked out by hand."""

import math

import numpy as np
import pytest

from dynnav_tasks.crowd import social_force as sf
from dynnav_tasks.crowd.orca import orca_line, orca_velocities, solve

DT = 0.2


def test_the_social_force_of_two_pedestrians_is_the_papers_by_hand():
    """A at (0, 0) and B at (1, 0), both of radius 0.3, both walking +x at 0.5 m/s towards goals at
    x = 10 with a preferred speed of 1 m/s. Gap 1 - 0.6 = 0.4 m, so each pushes the other with
    (V0 / sigma) exp(-0.4 / sigma) = 7 exp(-4/3) = 1.84518 m/s^2; B is ahead of A (weight 1), A is
    behind B (weight c = 0.5). The goal's pull on each: (1 - 0.5) / tau = 1 m/s^2."""
    push = 2.1 / 0.3 * math.exp(-0.4 / 0.3)
    assert push == pytest.approx(1.8451799668, rel=1e-9)
    a = sf.accelerations(positions=np.array([[0.0, 0.0], [1.0, 0.0]]), velocities=np.array([[0.5, 0.0], [0.5, 0.0]]),
                         radii=np.array([0.3, 0.3]), goals=np.array([[10.0, 0.0], [10.0, 0.0]]),
                         preferred_speeds=np.array([1.0, 1.0]))
    np.testing.assert_allclose(a, [[1.0 - push, 0.0], [1.0 + 0.5 * push, 0.0]], rtol=1e-12, atol=1e-12)


def test_a_wall_and_a_robot_push_as_the_paper_says():
    """A pedestrian at rest at its goal (no pull), 1 m above a box whose top edge is y = 0 (gap 0.7 m:
    (U0 / R) exp(-0.7 / R) = 50 exp(-3.5) up), with a robot of radius 0.3 at 1.3 m to its right
    (gap 0.7 m: 7 exp(-0.7 / 0.3) to the left; with no goal every body counts fully)."""
    a = sf.accelerations(np.array([[0.5, 1.0]]), np.zeros((1, 2)), np.array([0.3]), np.array([[0.5, 1.0]]),
                         np.array([1.0]), bodies=(np.array([[1.8, 1.0]]), np.array([0.3])),
                         boxes=np.array([[0.0, -1.0, 1.0, 0.0]]))
    np.testing.assert_allclose(a, [[-7.0 * math.exp(-0.7 / 0.3), 50.0 * math.exp(-3.5)]], rtol=1e-12)


def test_a_push_cannot_make_a_pedestrian_faster_than_its_limit():
    v = sf.step_velocities(np.array([[1.0, 0.0], [0.2, 0.0]]), np.array([[10.0, 0.0], [1.0, 0.0]]),
                           np.array([1.0, 1.0]), DT)
    np.testing.assert_allclose(v, [[1.3, 0.0], [0.4, 0.0]])  # capped at 1.3 v0; the other free


def test_an_orca_half_plane_asks_each_agent_for_half_the_way_out():
    """An agent at the origin at 1.5 m/s towards a resting neighbour 2 m ahead, radii 0.5 each,
    horizon 1 s: the velocities that collide within 1 s are the cone cut off by the disc of centre
    (2, 0) and radius 1; the relative velocity (1.5, 0) lies in it, 0.5 m/s past its edge x = 1.
    Sharing the avoidance, the agent takes half: its velocity must keep x <= 1.25."""
    line = orca_line((0.0, 0.0), (1.5, 0.0), 0.5, (2.0, 0.0), (0.0, 0.0), 0.5, time_horizon=1.0, dt=DT)
    assert line.point == pytest.approx((1.25, 0.0)) and line.direction == pytest.approx((0.0, 1.0))
    assert solve([line], 3.0, (1.5, 0.0)) == pytest.approx((1.25, 0.0))  # the permitted velocity nearest its wish
    assert solve([line], 3.0, (1.0, 0.7)) == pytest.approx((1.0, 0.7))  # a permitted wish is kept
    whole = orca_line((0.0, 0.0), (1.5, 0.0), 0.5, (2.0, 0.0), (0.0, 0.0), 0.5, 1.0, DT, responsibility=1.0)
    assert whole.point == pytest.approx((1.0, 0.0))  # towards a neighbour that does not avoid: the whole way


@pytest.mark.parametrize("offset", [0.05, 0.2])
def test_two_orca_agents_on_a_head_on_course_pass_without_contact(offset):
    """Two agents of radius 0.3 walk towards each other's start, 6 m apart and ``offset`` m off
    the same line: they pass (each ends at its goal) and their centres never come closer than 0.6 m."""
    p = np.array([[-3.0, offset / 2], [3.0, -offset / 2]])
    goals, v, radii, speeds = p[::-1].copy(), np.zeros((2, 2)), np.full(2, 0.3), np.full(2, 1.0)
    closest = math.inf
    for _ in range(60):
        to_goal = goals - p
        distance = np.hypot(to_goal[:, 0], to_goal[:, 1])
        preferred = to_goal / np.maximum(distance, 1e-9)[:, None] * np.minimum(speeds, distance / DT)[:, None]
        v = orca_velocities(p, v, radii, preferred, speeds, DT)
        p = p + v * DT
        closest = min(closest, float(np.hypot(*(p[0] - p[1]))))
    assert closest >= 0.6 - 1e-6
    np.testing.assert_allclose(p, goals, atol=0.05)


def test_the_social_metrics_of_a_scripted_episode_are_those_worked_out_by_hand():
    """A robot of radius 0.3 starts at (0, 0) facing +y with the target at (2, 0) (a quarter turn
    needed), turns to +x, then drives 0.5, 0.5 and 1.0 m; one human of radius 0.3 stands at (1, 1).
    Edge gaps after each step: 1.414 - 0.6, 1.118 - 0.6, 1.0 - 0.6 = 0.4 (personal space), then
    1.414 - 0.6 (one step of four violates 0.45 m, none 0.2 m). Path 2 m, and the only turn was
    the needed one, so irregularity 0. Then the same robot facing the target turns 0.5 rad away and
    back while driving 1 m: 1 rad of turning that was not needed, per metre."""
    from dynnav_tasks.crowd.metrics import SocialMetrics

    m = SocialMetrics(robot_radius=0.3, dt=0.2)
    m.start(0.0, 0.0, math.pi / 2, (2.0, 0.0))
    human = ([[1.0, 1.0]], [0.3])
    for x, yaw in [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (2.0, 0.0)]:
        m.step(x, 0.0, yaw, *human)
    r = m.result(success=True, shortest=1.7)
    assert r["min_human_distance"] == pytest.approx(0.4)
    assert r["personal_space_compliance"] == pytest.approx(0.75) and r["discomfort_frequency"] == 0.0
    assert r["time_to_goal"] == pytest.approx(0.8) and r["path_length"] == pytest.approx(2.0)
    assert r["spl"] == pytest.approx(0.85) and r["path_irregularity"] == pytest.approx(0.0)
    # x at the five positions: 0, 0, 0.5, 1, 2; differences 0, 0.5, 0.5, 1; second 0.5, 0, 0.5;
    # third -0.5, 0.5: |d3| / dt^3 = 0.5 / 0.008 = 62.5 m/s^3 each
    assert r["jerk"] == pytest.approx(62.5)
    m.start(0.0, 0.0, 0.0, (2.0, 0.0))  # facing the target: every turn is extra
    for x, yaw in [(0.5, 0.5), (1.0, 0.0)]:
        m.step(x, 0.0, yaw)
    r = m.result(success=False, shortest=1.7)
    assert r["path_irregularity"] == pytest.approx(1.0 / 1.0) and r["spl"] == 0.0
    assert math.isnan(r["time_to_goal"]) and math.isnan(r["jerk"]) and r["min_human_distance"] == math.inf


def test_many_episodes_pool_their_steps_as_crowdnav_does():
    """Two episodes: 10 steps with discomfort 0.5, then 30 steps with 0.1, so 5 + 3 = 8 of 40
    steps: 0.2 (not the episodes' mean, 0.3). The second ended on a human; only the first
    reached the goal (its time alone is the time to goal); the minimum distance is the mean of
    the minima, and a jerk an episode lacks (too short) is left out."""
    from dynnav_tasks.crowd.metrics import AGGREGATE_METRICS, aggregate

    episodes = [dict(steps=10, human_collision=False, min_human_distance=0.1, personal_space_compliance=0.6,
                     discomfort_frequency=0.5, time_to_goal=2.0, path_length=4.0, path_irregularity=0.2, jerk=None),
                dict(steps=30, human_collision=True, min_human_distance=-0.05, personal_space_compliance=0.8,
                     discomfort_frequency=0.1, time_to_goal=None, path_length=2.0, path_irregularity=0.4, jerk=3.0)]
    a = aggregate(episodes)
    assert list(a) == list(AGGREGATE_METRICS)
    assert a["discomfort_frequency"] == pytest.approx(0.2)
    assert a["personal_space_compliance"] == pytest.approx((6 + 24) / 40)
    assert a["human_collision_rate"] == 0.5 and a["time_to_goal"] == 2.0 and a["jerk"] == 3.0
    assert a["min_human_distance"] == pytest.approx(0.025) and a["path_length"] == 3.0
    assert a["path_irregularity"] == pytest.approx(0.3)
    with pytest.raises(ValueError, match="no episodes"):
        aggregate([])


@pytest.mark.parametrize("scenario", ["circle_crossing", "square_crossing", "corridor"])
@pytest.mark.parametrize("model", ["orca", "social_force"])
def test_a_crowd_starts_spaced_walks_to_its_goals_and_takes_new_ones(scenario, model):
    """Ten pedestrians start 0.2 m apart or more (and clear of the robot's start and target),
    never overlap, and reach goals (each a new one after) within a minute of walking."""
    from dynnav_tasks.crowd.crowd import Crowd, Pedestrians

    crowd, rng = Crowd(Pedestrians(10, model=model, scenario=scenario)), np.random.default_rng(0)
    crowd.reset(rng, keep_clear=[(0.0, -4.0), (0.0, 4.0)])
    gaps = np.hypot(*(crowd.positions[:, None] - crowd.positions[None]).transpose(2, 0, 1)) + np.eye(10) * 9
    assert gaps.min() >= 0.8 - 1e-9
    assert np.hypot(*(crowd.positions - [0.0, -4.0]).T).min() >= 0.8 - 1e-9
    reached = 0
    for _ in range(300):  # 60 s
        goals = crowd.goals.copy()
        crowd.step(DT, rng)
        reached += int((crowd.goals != goals).any(axis=1).sum())
        gaps = np.hypot(*(crowd.positions[:, None] - crowd.positions[None]).transpose(2, 0, 1)) + np.eye(10) * 9
        assert gaps.min() >= 0.6 - 0.01  # bodies of 0.3 m never (more than a centimetre) inside each other
    assert reached >= 10


@pytest.mark.parametrize("model", ["orca", "social_force"])
def test_pedestrians_avoid_a_robot_they_see_and_walk_into_one_they_do_not(model):
    """One pedestrian walks from (-3, 0) to (3, 0) past a robot (radius 0.3) standing at (0, 0.05):
    seeing it, it keeps its body clear; blind to it, it walks through where the robot stands."""
    from dynnav_tasks.crowd.crowd import Crowd, Pedestrians

    closest = {}
    for visible in (True, False):
        crowd = Crowd(Pedestrians(1, model=model, scenario="corridor", square_width=6.0))
        crowd.reset(np.random.default_rng(0))
        crowd.positions[0], crowd.goals[0] = (-3.0, 0.0), (3.0, 0.0)
        robot = ((0.0, 0.05), (0.0, 0.0), 0.3)
        closest[visible] = math.inf
        for _ in range(60):
            crowd.step(DT, np.random.default_rng(1), robot=robot if visible else None)
            closest[visible] = min(closest[visible], float(np.hypot(*(crowd.positions[0] - robot[0]))))
    assert closest[True] >= 0.6 - 0.01 and closest[False] < 0.1


def test_a_crowd_that_cannot_fit_is_refused():
    from dynnav_tasks.crowd.crowd import Crowd, Pedestrians, PlacementError

    with pytest.raises(PlacementError, match="do not fit the circle_crossing scenario"):
        Crowd(Pedestrians(60, circle_radius=1.0)).reset(np.random.default_rng(0))
    with pytest.raises(ValueError, match="pedestrian model 'rvo' is not one of social_force, orca"):
        Pedestrians(5, model="rvo")


def test_free_space_pedestrians_start_clear_of_the_boxes_and_head_only_for_goals_in_sight():
    """A wall from (4, -5) to (4, 3) splits a 10 m room (a gap above it): every start leaves
    0.5 m (radius and spacing) to every box, and every goal, at the start and on arrival, is
    1 m away or more and seen past the wall (a straight walk that clears it by a radius)."""
    from dynnav_tasks.crowd.crowd import Crowd, Pedestrians

    walls = np.array([[3.9, -5.0, 4.1, 3.0], [-5.2, -5.0, -5.0, 5.0]])
    crowd = Crowd(Pedestrians(8, model="orca", scenario="free_space", area=((-5.0, 5.0), (-5.0, 5.0))))
    rng = np.random.default_rng(4)
    crowd.reset(rng, keep_clear=[(0.0, 0.0)], boxes=walls)

    def gap(p, b):
        return math.hypot(max(b[0] - p[0], 0.0, p[0] - b[2]), max(b[1] - p[1], 0.0, p[1] - b[3]))

    def seen(a, b):  # sampled along the segment: never within a radius of a wall
        return all(min(gap(a + t * (b - a), w) for w in walls) >= 0.3 - 1e-9 for t in np.linspace(0, 1, 400))

    assert all(gap(p, w) > 0.5 for p in crowd.positions for w in walls)
    assert all(np.hypot(*(g - p)) >= 1.0 and seen(p, g) for p, g in zip(crowd.positions, crowd.goals))
    for _ in range(300):  # walking: new goals stay in sight, and nobody goes through the wall
        before = crowd.goals.copy()
        crowd.step(0.2, rng, boxes=walls)
        for i in np.flatnonzero((crowd.goals != before).any(axis=1)):
            assert seen(crowd.positions[i], crowd.goals[i])
        assert all(gap(p, w) > 0.3 - 0.05 for p in crowd.positions for w in walls)


def test_pedestrians_told_to_stop_stay_at_their_goals():
    """``on_arrival="stop"`` (CrowdNav's humans): once across the circle each pedestrian stays at
    its goal; with "renew" the same crowd walks back."""
    from dynnav_tasks.crowd.crowd import Crowd, Pedestrians

    for on_arrival in ("stop", "renew"):
        crowd = Crowd(Pedestrians(3, model="orca", scenario="circle_crossing", on_arrival=on_arrival))
        rng = np.random.default_rng(1)
        crowd.reset(rng)
        goals = crowd.goals.copy()
        for _ in range(150):  # 30 s: 8 m across takes about 11 s at 0.75 m/s
            crowd.step(0.2, rng)
        if on_arrival == "stop":
            np.testing.assert_array_equal(crowd.goals, goals)
            assert (np.hypot(*(crowd.positions - goals).T) <= 0.3).all()
            assert (np.hypot(*crowd.velocities.T) < 1e-6).all()
        else:
            assert not np.array_equal(crowd.goals, goals)
    with pytest.raises(ValueError, match="on_arrival 'wander' is not one of renew, stop"):
        Pedestrians(1, on_arrival="wander")
