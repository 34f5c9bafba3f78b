"""Pedestrians in SAPIEN: bodies the lasers see, a touch that ends the episode as a human
collision (apart from other collisions), and a crowd that replays bit for bit from a seed."""


import gymnasium as gym
import numpy as np
import pytest
from mani_skill.utils.registration import register_env

import dynnav_tasks
from dynnav_tasks.crowd.crowd import Pedestrians
from dynnav_tasks.motion import Static
from dynnav_tasks.nav_env import NavEnv
from dynnav_tasks.world import Arena, Obstacles, StartArea, World

LEFT = 1
START = StartArea((-0.001, 0.001), (-0.001, 0.001), (0.0, 0.0))  # at the origin, facing +x


def _task(name: str, pedestrians: Pedestrians, obstacles=()):
    world = World(targets=(Static((4.0, 4.0)),), obstacles=obstacles, arena=Arena((-5.0, 5.0), (-5.0, 5.0)),
                  start=START, pedestrians=pedestrians)
    register_env(name, max_episode_steps=200)(type(name.replace("-", ""), (NavEnv,), {"world": world}))
    return dynnav_tasks.NumpyWrapper(gym.make(name))


@pytest.fixture(scope="module")
def one_pedestrian():
    env = _task("TestOnePedestrian-v1", Pedestrians(1, model="orca", scenario="corridor", corridor_width=9.0))
    yield env
    env.close()


def test_the_lasers_see_a_pedestrian_where_it_stands(one_pedestrian):
    """A pedestrian of radius 0.3 at (2, 0), straight ahead of the robot at the origin: ray 0
    (straight ahead) reads 2 - 0.3 = 1.7 m; ray 4 (90 degrees, +y) meets nothing but the wall."""
    env = one_pedestrian
    env.reset(seed=0)
    env.unwrapped.place_pedestrians([(2.0, 0.0)])
    lasers = env.unwrapped.snapshot.lasers
    assert lasers[0] == pytest.approx(1.7, abs=2e-3)
    assert lasers[4] == pytest.approx(5.0, abs=2e-3)  # the north wall's inner face at y = 5
    assert env.unwrapped.snapshot.d2 == pytest.approx(1.7, abs=2e-3)  # the nearest body's edge


def test_a_pedestrian_walking_into_the_robot_ends_the_episode_as_a_human_collision(one_pedestrian):
    """The pedestrian walks from (2, 0) to (-2, 0) through the robot, which turns in place and
    does not see it coming (the crowd does not see the robot either): the episode ends in a
    collision marked as a human one."""
    env = one_pedestrian
    env.reset(seed=0)
    env.unwrapped.place_pedestrians([(2.0, 0.0)], goals=[(-2.0, 0.0)])
    for _ in range(40):
        _, reward, terminated, truncated, info = env.step(LEFT)
        if terminated or truncated:
            break
    assert terminated and info["collision"] and info["human_collision"] and not info["success"]
    assert reward == pytest.approx(env.unwrapped.reward_params.collision_reward, abs=1.0)  # the collision's reward


def test_a_box_collision_is_not_a_human_collision():
    env = _task("TestBoxAndPedestrian-v1", Pedestrians(1, scenario="corridor", corridor_width=9.0),
                obstacles=(Obstacles((0.25, 0.25), Static((0.6, 0.0))),))
    try:
        env.reset(seed=0)
        env.unwrapped.place_pedestrians([(-3.0, 3.0)])
        terminated = False
        for _ in range(10):
            _, _, terminated, _, info = env.step(0)  # forward, into the box 0.6 m ahead
            if terminated:
                break
        assert terminated and info["collision"] and not info["human_collision"]
    finally:
        env.close()


def test_a_crowd_replays_bit_for_bit_from_its_seed():
    env = _task("TestCrowdReplay-v1", Pedestrians(5, model="social_force", scenario="circle_crossing",
                                                   circle_radius=3.5, see_robot=True))
    try:
        runs = []
        for _ in range(2):
            env.reset(seed=7)
            path = [env.unwrapped.snapshot.human_xy.copy()]
            for t in range(30):
                env.step(t % 3)
                path.append(env.unwrapped.snapshot.human_xy.copy())
            runs.append(np.array(path))
        np.testing.assert_array_equal(runs[0], runs[1])
        assert np.abs(runs[0][-1] - runs[0][0]).max() > 1.0  # they walked
    finally:
        env.close()


def test_a_crowd_episode_ends_with_its_social_metrics():
    """DynNav-Crowd-v1's last step carries the episode's social metrics; the minimum distance is
    the least edge-to-edge gap of the snapshots, worked out here from their positions."""
    from dynnav_tasks.crowd.metrics import DISCOMFORT
    from dynnav_tasks.nav_env import ROBOT_RADIUS

    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Crowd-v1", humans=5))
    try:
        env.reset(seed=3)
        gaps, done = [], False
        while not done:
            _, _, terminated, truncated, info = env.step(0)  # straight on, into the crowd
            s = env.unwrapped.snapshot
            gaps.append(float((np.hypot(*(s.human_xy - s.pose[:2]).T) - s.human_radius - ROBOT_RADIUS).min()))
            done = terminated or truncated
            assert done or "min_human_distance" not in info
        assert info["min_human_distance"] == pytest.approx(min(gaps))
        assert info["discomfort_frequency"] == pytest.approx(np.mean(np.array(gaps) < DISCOMFORT))
        assert info["path_length"] == pytest.approx(s.path_length)
    finally:
        env.close()


def test_the_orca_robot_passes_a_pedestrian_that_a_straight_drive_hits():
    """A pedestrian blind to the robot walks head-on from (3, 0.05) to (-3, 0.05); the target is at
    (4, 0). Driving straight at the pedestrians' speed collides with it; the robot driven by ORCA,
    taking the whole avoidance, goes round it and reaches the target."""
    model = "orca"
    from dynnav_tasks.baselines.crowd_robot import CrowdRobot

    world = World(targets=(Static((4.0, 0.0)),), arena=Arena((-5.0, 5.0), (-5.0, 5.0)), start=START,
                  pedestrians=Pedestrians(1, scenario="corridor", corridor_width=9.0))
    name = f"TestHeadOn{model.title().replace('_', '')}-v1"
    register_env(name, max_episode_steps=200)(type(name.replace("-", ""), (NavEnv,), {"world": world}))
    env = dynnav_tasks.NumpyWrapper(gym.make(name, control_mode="diff_drive_vel"))
    try:
        outcomes = {}
        for driver in ("straight", model):
            env.reset(seed=0)
            env.unwrapped.place_pedestrians([(3.0, 0.05)], goals=[(-3.0, 0.05)])
            robot = CrowdRobot(model)
            robot.start(env.unwrapped)
            done = False
            while not done:
                action = np.array([0.75, 0.0], np.float32) if driver == "straight" else robot.act(env.unwrapped)
                _, _, terminated, truncated, info = env.step(action)
                done = terminated or truncated
            outcomes[driver] = dynnav_tasks.outcome_of(info, terminated), info["human_collision"]
        assert outcomes == {"straight": ("collision", True), model: ("success", False)}
    finally:
        env.close()


def test_a_crowd_robot_turns_a_velocity_into_the_drives_command():
    """The model's velocity (m/s, world frame) from heading 0: straight ahead is driven as it is;
    10 degrees off, v = |u| cos 10 deg and w = 10 deg over one 0.2 s step; beyond a right angle, turn
    in place at the drive's top turn rate (5.236 rad/s)."""
    from types import SimpleNamespace

    from dynnav_tasks.baselines.crowd_robot import CrowdRobot

    robot = CrowdRobot("orca")
    robot.start(SimpleNamespace(controller_config=SimpleNamespace(max_linear_speed=1.2, max_angular_speed=5.236),
                                world=World(targets=(Static((1.0, 1.0)),)), control_freq=5))
    np.testing.assert_allclose(robot.command(0.6, 0.0, 0.0), [0.6, 0.0], atol=1e-7)
    angle = np.radians(10.0)
    np.testing.assert_allclose(robot.command(0.6 * np.cos(angle), 0.6 * np.sin(angle), 0.0),
                               [0.6 * np.cos(angle), angle / 0.2], rtol=1e-6)
    np.testing.assert_allclose(robot.command(-0.5, -0.1, 0.0), [0.0, -5.236], rtol=1e-6)


def test_a_crowd_baselines_results_file_holds_its_social_metrics(tmp_path):
    """``crowd_robot --out`` records each run under the controller and the task's options, with
    the social metrics of its episodes; a task option the task lacks is refused before anything
    is written."""
    import json

    from dynnav_tasks.baselines.crowd_robot import Args, main, run_crowd_robot

    out = tmp_path / "crowd.json"
    main(Args(model="social_force", episodes=2, options="humans=3", out=str(out)))
    entry = json.loads(out.read_text())["social_force_robot/DynNav-Crowd-v1 [humans=3]"]
    again = run_crowd_robot("DynNav-Crowd-v1", range(2), "social_force", task_kwargs=dict(humans=3))
    assert entry["success"] == again.rate() and entry["social"] == again.social()
    assert set(entry["social"]) >= {"discomfort_frequency", "human_collision_rate", "min_human_distance"}
    with pytest.raises(SystemExit, match="DynNav-Crowd-v1 has no option 'humanz'"):
        main(Args(episodes=1, options="humanz=3", out=str(tmp_path / "no.json")))
    assert not (tmp_path / "no.json").exists()


def test_the_pedestrian_forecast_is_where_a_blind_crowd_walks():
    """Pedestrians blind to the robot and stopping at their goals walk where the forecast said,
    whatever the robot does (here: turning in place)."""
    env = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Crowd-v1", humans=5, on_arrival="stop"))
    try:
        env.reset(seed=2)
        forecast = env.unwrapped.pedestrian_forecast(12)
        seen = [env.unwrapped.snapshot.human_xy.copy()]
        for _ in range(12):
            env.step(LEFT)
            seen.append(env.unwrapped.snapshot.human_xy.copy())
        np.testing.assert_allclose(np.array(seen), forecast, atol=1e-9)
    finally:
        env.close()


def test_the_full_state_planner_waits_for_a_pedestrian_that_a_straight_drive_hits():
    """The head-on pedestrian of the ORCA robot's test, with the discrete drive: driving straight
    collides; the planner, forecasting the pedestrian (with its model, or from its last step's velocity),
    reaches the target without touching it, and with a personal space of 0.2 m it passes no nearer
    than CrowdNav's discomfort distance."""
    from dynnav_tasks.baselines.episodes import ROBOT_RADIUS
    from dynnav_tasks.baselines.state_planner import PlannerController

    world = World(targets=(Static((4.0, 0.0)),), arena=Arena((-5.0, 5.0), (-5.0, 5.0)), start=START,
                  pedestrians=Pedestrians(1, scenario="corridor", corridor_width=9.0, on_arrival="stop"))
    register_env("TestPlannerHeadOn-v1", max_episode_steps=200)(type("TestPlannerHeadOn", (NavEnv,), {"world": world}))
    env = dynnav_tasks.NumpyWrapper(gym.make("TestPlannerHeadOn-v1"))
    try:
        outcomes, nearest = {}, {}
        for driver in ("straight", "planner", "planner_margin", "planner_cv"):
            env.reset(seed=0)
            env.unwrapped.place_pedestrians([(3.0, 0.05)], goals=[(-3.0, 0.05)])
            planner = PlannerController(human_margin=0.2 if driver == "planner_margin" else 0.0,
                                        human_forecast="constant_velocity" if driver == "planner_cv" else "model")
            planner.start(env.unwrapped)
            done, gaps = False, []
            while not done:
                action = 0 if driver == "straight" else planner.act(env.unwrapped)
                _, _, terminated, truncated, info = env.step(action)
                done = terminated or truncated
                s = env.unwrapped.snapshot  # the gap between the robot's circle and the pedestrian's
                gaps.append(np.hypot(*(s.human_xy[0] - s.pose[:2])) - ROBOT_RADIUS - world.pedestrians.radius)
            outcomes[driver] = dynnav_tasks.outcome_of(info, terminated), bool(info["human_collision"])
            nearest[driver] = min(gaps)
        # a pedestrian walking a straight line is forecast as well from its last step's velocity
        assert outcomes == {"straight": ("collision", True), "planner": ("success", False),
                            "planner_margin": ("success", False), "planner_cv": ("success", False)}
        assert nearest["planner"] < 0.2 <= nearest["planner_margin"]
    finally:
        env.close()
    with pytest.raises(ValueError, match=r"human_margin must be a distance in \[0, 1\] m; got -0.1"):
        PlannerController(human_margin=-0.1)
    with pytest.raises(ValueError, match="human_forecast must be one of model, constant_velocity; got 'psychic'"):
        PlannerController(human_forecast="psychic")
