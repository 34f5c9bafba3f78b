"""The full-state planner: its forecasts contain where obstacles really go, and it drives."""

import json

import numpy as np
import pytest

from dynnav_tasks.motion import BackAndForth, RandomInRect, Route
from dynnav_tasks.baselines.state_planner import ObstacleForecast, run_planner
from dynnav_tasks.world import Obstacles, World
from dynnav_tasks.motion import Static

HALF = (0.25, 0.25)


def _forecast_holds(motion, observed_steps, horizon=20, seed=3, remember=True):
    """Run the motion's mover; after ``observed_steps`` observations, every future position
    lies in the forecast's box for its step (the box minus the obstacle's half size)."""
    world = World(targets=(Static((0.0, 0.0)),), obstacles=(Obstacles(HALF, motion),))
    forecast = ObstacleForecast(world, remember=remember)
    rng = np.random.default_rng(seed)
    mover = motion.mover()
    xy = mover.reset(rng)
    for _ in range(observed_steps):
        boxes = forecast.boxes(xy, horizon)
        xy = mover.advance(rng)
    boxes = forecast.boxes(xy, horizon)
    future = [xy] + [mover.advance(rng) for _ in range(horizon)]
    sizes = []
    for k, p in enumerate(future):
        lo, hi = boxes[k, 0, 0] + HALF, boxes[k, 0, 1] - HALF
        assert np.all(p[0] >= lo - 1e-9) and np.all(p[0] <= hi + 1e-9), (k, p, lo, hi)
        sizes.append(hi - lo)
    return np.array(sizes)


def test_back_and_forth_is_forecast_exactly_once_its_way_is_seen():
    sizes = _forecast_holds(BackAndForth(center=(1, 1), direction=(1, 0), amplitude=1.5, speed=0.1), 1)
    # now: a point; step k: the span of the positions at k - 1 and k, one step long at most
    assert np.allclose(sizes[0], 0) and np.all(sizes[1:, 0] <= 0.1 + 1e-9) and np.allclose(sizes[:, 1], 0)
    assert np.isclose(sizes[1:, 0], 0.1).mean() > 0.8


def test_a_route_obstacle_is_forecast_after_its_speed_is_seen():
    route = Route(waypoints=((0, 0), (2, 0), (2, 2), (0, 2)), speed_range=(0.05, 0.5))
    assert _forecast_holds(route, 0).max() > 1.0  # before: every speed of the range
    sizes = _forecast_holds(route, 1)
    assert sizes.max() <= 0.5 + 1e-9  # after: one step of the true speed
    # a memoryless forecast (what one state vector tells) keeps every speed of the range
    assert _forecast_holds(route, 1, remember=False).max() > 1.0


def test_a_wandering_obstacle_stays_in_its_growing_box():
    for seed in range(5):
        sizes = _forecast_holds(RandomInRect(x_range=(0, 2), y_range=(0, 1)), 2, seed=seed)
        assert sizes[-1][0] == pytest.approx(2.0) and sizes[-1][1] == pytest.approx(1.0)  # its whole area


def test_the_planner_crosses_the_loop_of_world_5_3():
    result = run_planner("DynNav-MovingObstacles-v1", range(5))
    assert result.outcomes == ["success"] * 5, result.summary()


def test_out_file_collects_each_tasks_rates_and_refuses_junk(tmp_path, capsys):
    from types import SimpleNamespace

    from dynnav_tasks.baselines.cli import run_over_tasks

    def fake_run(task, seeds):
        outcomes = ["success"] * (len(seeds) - 1) + ["collision"]
        return SimpleNamespace(outcomes=outcomes, summary=lambda: f"{task}: done")

    out = tmp_path / "ceilings.json"
    run_over_tasks("A", ["A", "B"], "task id", 4, 7, fake_run, out=str(out))
    run_over_tasks("B", ["A", "B"], "task id", 2, 0, fake_run, out=str(out))
    data = json.loads(out.read_text())
    assert data["A"] == dict(success=0.75, collision=0.25, timeout=0.0, episodes=4, first_seed=7)
    assert data["B"]["success"] == 0.5 and data["B"]["episodes"] == 2
    assert [p.name for p in tmp_path.iterdir()] == ["ceilings.json"]  # no temporary files left
    out.write_text("not json")
    with pytest.raises(SystemExit, match="is not a JSON file"):
        run_over_tasks("A", ["A", "B"], "task id", 1, 0, fake_run, out=str(out))
    with pytest.raises(SystemExit, match="does not exist"):
        run_over_tasks("A", ["A", "B"], "task id", 1, 0, fake_run, out=str(tmp_path / "no" / "c.json"))


# The study worlds' ceilings (docs/results/ceilings.json) were measured with the straight-line
# search; these action lists were recorded from that version and must not change.
STUDY_ACTIONS = {
    ("DynNav-MovingTarget-v1", 0): [2, 2, 0, 2, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0,
                                    0, 0],
    ("DynNav-MotionAreas-v1", 2): [1, 1, 1, 1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 2, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2,
                                   0, 0, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0],
}


@pytest.mark.parametrize("task,seed", sorted(STUDY_ACTIONS))
def test_the_planners_actions_in_a_study_world_are_those_its_ceiling_was_measured_with(task, seed):
    from dynnav_tasks.baselines.episodes import run_episodes
    from dynnav_tasks.baselines.state_planner import PlannerController

    class Recorder(PlannerController):
        def __init__(self):
            super().__init__()
            self.actions = []

        def act(self, env):
            action = super().act(env)
            self.actions.append(int(action))
            return action

    recorder = Recorder()
    result = run_episodes(task, task, [seed], recorder)
    assert recorder.actions == STUDY_ACTIONS[(task, seed)]
    assert result.outcomes == ["success"] and not recorder.planner.uses_way


def test_auto_searches_along_the_straight_line_in_every_study_world_and_refuses_unknown_heuristics():
    from mani_skill.utils.registration import REGISTERED_ENVS

    from dynnav_tasks import TASK_IDS
    from dynnav_tasks.baselines.state_planner import StatePlanner

    for task in TASK_IDS:
        assert not StatePlanner(REGISTERED_ENVS[task].cls.world).uses_way, task
    world = REGISTERED_ENVS[TASK_IDS[0]].cls.world
    assert StatePlanner(world, heuristic="way").uses_way
    with pytest.raises(ValueError, match="heuristic must be one of"):
        StatePlanner(world, heuristic="grid")


def test_a_tracked_forecast_sees_the_nearest_boxes_at_constant_velocity():
    from dynnav_tasks.baselines.tracked_forecast import SPREAD, UNSEEN, TrackedForecast
    from dynnav_tasks.motion import BackAndForth
    from dynnav_tasks.world import Arena, Obstacles, World

    moving = tuple(Obstacles((0.25, 0.25), BackAndForth(center=(3.0, y), direction=(1.0, 0.0), amplitude=2.0,
                                                        speed=0.1)) for y in (0.0, 5.0))
    forecast = TrackedForecast(World(targets=(Static((5.0, 5.0)),), obstacles=moving, arena=Arena((-6, 6), (-6, 6))),
                               k=1)
    first = forecast.boxes(np.array([[2.0, 0.0], [5.0, 5.0]]), 3, robot=(0.0, 0.0))
    np.testing.assert_allclose(first[3, 0], [[2.0 - 0.25 - 3 * SPREAD, -0.25 - 3 * SPREAD],
                                             [2.0 + 0.25 + 3 * SPREAD, 0.25 + 3 * SPREAD]])  # no velocity yet
    assert (first[:, 1] == UNSEEN).all()  # the second box is not among the k = 1 nearest: unseen
    second = forecast.boxes(np.array([[2.1, 0.0], [5.0, 5.0]]), 3, robot=(0.0, 0.0))
    # by hand: 0.1 m per step along x; at step 2 the centre is at 2.3, the box swept from step 1 (2.2)
    lo, hi = second[2, 0]
    assert lo[0] == pytest.approx(2.2 - 0.25 - 1 * SPREAD) and hi[0] == pytest.approx(2.3 + 0.25 + 2 * SPREAD)
    assert lo[1] == pytest.approx(-0.25 - 2 * SPREAD) and hi[1] == pytest.approx(0.25 + 2 * SPREAD)  # y: it grows
