"""The one-step look-ahead: the odometry in the egocentric state, the afterstates the look-ahead
Q-network scores (checked against geometry worked by hand), its indifference to the pedestrians'
order, and a run config it cannot read refused before anything is written."""

import math

import gymnasium as gym
import numpy as np
import pytest
import torch

import dynnav_tasks
from agents.core.lookahead import LookaheadQNetwork
from agents.core.policy import build_q_network
from agents.training.config import validate
from agents.training.config_io import make
from dynnav_tasks.egocentric import FAR, egocentric_layout
from dynnav_tasks.motion import Static
from dynnav_tasks.nav_env import ROBOT_RADIUS
from dynnav_tasks.world import Arena, StartArea, World

FORWARD, LEFT, RIGHT = 0, 1, 2
TURN = math.pi / 8
MOVES = [(0.15, 0.0), (0.0, TURN), (0.0, -TURN)]  # the discrete drive's defaults
ANGLES = (2 * math.pi * np.arange(16) / 16).tolist()


def raw_network(human_k=2) -> LookaheadQNetwork:
    """A look-ahead network that reads raw (unscaled) states."""
    width = 16 + 6 + 5 * human_k
    torch.manual_seed(0)
    return LookaheadQNetwork(MOVES, ANGLES, 5.0, ROBOT_RADIUS, human_k, (32,), [0.0] * width, [1.0] * width).eval()


def state(humans) -> torch.Tensor:
    """Lasers 1.0, 1.1, ..., 2.5; the target 2 m straight ahead; the robot advanced 0.15 m last step."""
    lasers = [1.0 + 0.1 * i for i in range(16)]
    slots = [v for h in humans for v in h]
    return torch.tensor([lasers + [2.0, 0.0, 1.0] + [0.15, 0.0, 0.0] + slots], dtype=torch.float32)


PEDESTRIAN = (1.0, 0.5, -0.1, 0.0, 0.3)  # 1 m ahead, 0.5 m left, closing at 0.1 m a step: its own step is 0.05 m ahead
EMPTY = (FAR, 0.0, 0.0, 0.0, 0.0)


def test_the_afterstates_move_the_robot_by_each_action_and_the_pedestrians_at_constant_velocity():
    robot, lasers, people, present = raw_network().afterstates(state([PEDESTRIAN, EMPTY]))
    assert present.tolist() == [[True, False]]
    c, s = math.cos(TURN), math.sin(TURN)
    # forward: 0.15 m ahead; the target 1.85 m ahead, the pedestrian (1.0 + 0.05 - 0.15, 0.5), moving 0.05 m ahead
    assert robot[0, FORWARD].tolist() == pytest.approx([1.85, 0.0, 1.0, 0.15, 0.0, 0.0], abs=1e-5)
    assert people[0, FORWARD, 0].tolist() == pytest.approx([0.9, 0.5, 0.05, 0.0, 0.3], abs=1e-5)
    # turning left in place: everything turns by -pi/8 in the robot's frame
    assert robot[0, LEFT].tolist() == pytest.approx([2.0, -s, c, 0.0, 0.0, TURN], abs=1e-5)
    x, y = 1.05, 0.5
    assert people[0, LEFT, 0, :4].tolist() == pytest.approx([c * x + s * y, -s * x + c * y, c * 0.05, -s * 0.05],
                                                            abs=1e-5)
    assert robot[0, RIGHT].tolist() == pytest.approx([2.0, s, c, 0.0, 0.0, -TURN], abs=1e-5)
    # the ring: ahead, the wall 1.0 m away comes 0.15 m nearer; to the left (ray 4, 1.4 m) a bit farther
    assert lasers[0, FORWARD, 0].item() == pytest.approx(0.85, abs=1e-5)
    assert lasers[0, FORWARD, 4].item() == pytest.approx(math.hypot(1.4, 0.15), abs=1e-5)
    # a left turn of one ray's spacing: what ray 1 read is now straight ahead; a right turn: what ray 15 read
    assert lasers[0, LEFT].tolist() == pytest.approx([1.0 + 0.1 * ((i + 1) % 16) for i in range(16)], abs=1e-5)
    assert lasers[0, RIGHT].tolist() == pytest.approx([1.0 + 0.1 * ((i - 1) % 16) for i in range(16)], abs=1e-5)


def test_an_arc_moves_the_robot_along_its_chord():
    net = LookaheadQNetwork([(0.1, TURN)], ANGLES, 5.0, ROBOT_RADIUS, 1, (8,), [0.0] * 27, [1.0] * 27)
    robot, *_ = net.afterstates(state([EMPTY]))
    # an arc of 0.1 m turning pi/8: a chord of 2 (0.1 / (pi/8)) sin(pi/16) at pi/16 to the heading
    chord = 2 * 0.1 / TURN * math.sin(TURN / 2)
    tx, ty = 2.0 - chord * math.cos(TURN / 2), -chord * math.sin(TURN / 2)
    assert robot[0, 0, 0].item() == pytest.approx(math.hypot(tx, ty), abs=1e-5)
    assert robot[0, 0, 3:5].tolist() == pytest.approx([chord * math.cos(TURN / 2), -chord * math.sin(TURN / 2)], abs=1e-5)


def test_the_value_ignores_the_pedestrians_order_and_the_empty_slots():
    net = raw_network(human_k=3)
    other = (-1.5, 0.2, 0.1, 0.05, 0.3)
    q = net(state([PEDESTRIAN, other, EMPTY]))
    assert q.shape == (1, 3)
    torch.testing.assert_close(net(state([other, PEDESTRIAN, EMPTY])), q)
    torch.testing.assert_close(net(state([PEDESTRIAN, other, (12.0, -3.0, 0.2, 0.1, 0.0)])), q)
    assert not torch.allclose(net(state([PEDESTRIAN, (-1.0, 0.2, 0.1, 0.05, 0.3), EMPTY])), q)


def lookahead_config(**task_kwargs):
    kwargs = {**dict(scenario="circle_crossing", humans=5, human_k=5, odometry=True), **task_kwargs}
    return make(task="DynNav-Crowd-v1", task_kwargs={k: v for k, v in kwargs.items() if v is not None},
                lookahead=True, hidden_sizes=[32])


def test_the_run_builds_it_from_the_tasks_options_and_refuses_a_state_it_cannot_read():
    width = 16 + 3 + 3 + 25
    net = build_q_network(lookahead_config(), [((width,), np.float32)], 3)
    assert isinstance(net, LookaheadQNetwork)
    # the scaling the DQN feeds it is undone: a scaled zero is the middle of each bound
    assert net.afterstates(torch.zeros(1, width))[0].shape == (1, 3, 6)
    with pytest.raises(ValueError, match="odometry=True"):
        build_q_network(lookahead_config(odometry=None), [((width - 3,), np.float32)], 3)
    with pytest.raises(ValueError, match="full ring"):
        build_q_network(lookahead_config(laser_fov_deg=180.0), [((width,), np.float32)], 3)
    with pytest.raises(ValueError, match="not with q_network"):
        validate(make(task="DynNav-Crowd-v1", lookahead=True, recurrent="gru"))


@pytest.fixture(scope="module")
def env():
    world = World(targets=(Static((4.0, 4.0)),), arena=Arena((-5.0, 5.0), (-5.0, 5.0)),
                  start=StartArea((-0.001, 0.001), (-0.001, 0.001), (0.0, 0.0)))
    e = dynnav_tasks.NumpyWrapper(gym.make("DynNav-Procedural-v1", obstacle_k=0, odometry=True))
    e.reset(seed=0, options={"world": world})
    yield e
    e.close()


def test_the_odometry_reads_the_robots_own_last_move(env):
    layout = egocentric_layout(16, 0, odometry=True)
    assert [name for name, _ in layout] == ["lasers", "target", "odometry"]
    assert env.observation_space.shape == (22,)
    env.unwrapped.place_robot(0.0, 0.0, math.pi / 2)
    odometry = slice(19, 22)
    obs, *_ = env.step(FORWARD)
    assert obs[odometry].tolist() == pytest.approx([0.15, 0.0, 0.0], abs=2e-3)
    obs, *_ = env.step(LEFT)
    assert obs[odometry].tolist() == pytest.approx([0.0, 0.0, TURN], abs=2e-3)
    obs, *_ = env.step(RIGHT)
    assert obs[odometry].tolist() == pytest.approx([0.0, 0.0, -TURN], abs=2e-3)
    assert env.observation_space.contains(obs)
    env.unwrapped.place_robot(1.0, 0.0, 0.0)
    assert env.unwrapped.task_state_vector()[odometry].tolist() == [0.0, 0.0, 0.0]
