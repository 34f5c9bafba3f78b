"""Q-networks and their learners built from a run's config, and a trained policy: a Q-network
with the features that turn observations into its inputs (``agents.training.policy_loading.load_policy``
loads one from a checkpoint)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch import nn

from agents.core.encoders import EgocentricQNetwork
from agents.core.learner import DQNLearner
from agents.core.lookahead import LookaheadQNetwork
from agents.core.obs_scaling import ObsScaler
from agents.core.networks import MLPQNetwork, PixelQNetwork, check_q_network, load_factory, q_values_of
from agents.core.recurrent import RecurrentLearner, RecurrentQNetwork
from agents.core.replay import Batch
from agents.core.sequence_replay import SequenceBatch


def build_q_network(config, input_specs, n_actions: int) -> nn.Module:
    """The run's Q-network, initialised from torch's generator seeded with ``config.seed``: the
    config's ``q_network`` factory, the conv net for pixel runs, the recurrent network (``recurrent``),
    or the MLP."""
    torch.manual_seed(config.seed)
    shapes = [tuple(shape) for shape, _ in input_specs]
    if config.dqn.recurrent:
        if len(shapes) != 1 or len(shapes[0]) != 1:
            raise ValueError(f"the recurrent Q-network reads one vector; this run's inputs have shapes {shapes}")
        d = config.dqn
        return RecurrentQNetwork(shapes[0][0], n_actions, d.hidden_sizes, d.recurrent_size, d.recurrent)
    dtypes = [torch.from_numpy(np.zeros(0, dtype=d)).dtype for _, d in input_specs]
    if config.dqn.q_network:
        module = load_factory(config.dqn.q_network)(shapes, n_actions)
        source = f"q_network {config.dqn.q_network!r}"
    elif config.dqn.lookahead:
        module = lookahead_network(config, shapes, n_actions)
        source = "the look-ahead Q-network"
    elif (config.dqn.laser_encoder, config.dqn.obstacle_encoder) != ("flat", "flat"):
        module = egocentric_network(config, shapes, n_actions)
        source = "the egocentric Q-network"
    elif config.camera.camera_frames and config.camera.camera_input == "pixels":
        module = PixelQNetwork(shapes[0], shapes[1][0], n_actions, shift=config.camera.pixel_shift)
        source = "the pixel Q-network"
    else:
        if len(shapes) != 1 or len(shapes[0]) != 1:
            raise ValueError(f"the MLP Q-network reads one vector; this run's inputs have shapes {shapes}")
        module = MLPQNetwork(shapes[0][0], n_actions, config.dqn.hidden_sizes)
        source = "the MLP Q-network"
    return check_q_network(module, shapes, dtypes, n_actions, source)


def egocentric_network(config, shapes, n_actions: int) -> EgocentricQNetwork:
    """The ``EgocentricQNetwork`` of a run on the egocentric state: its laser and obstacle counts are the
    task options ``laser_rays`` and ``obstacle_k`` (the task's defaults when not given)."""
    from dynnav_tasks.lasers import NUM_LASERS
    from dynnav_tasks.tasks.procedural import DEFAULT_OBSTACLE_K

    kwargs, d = config.env.task_kwargs, config.dqn
    return EgocentricQNetwork(shapes[0][0], n_actions, d.hidden_sizes, lasers=int(kwargs.get("laser_rays", NUM_LASERS)),
                              obstacle_k=int(kwargs.get("obstacle_k", DEFAULT_OBSTACLE_K)),
                              laser_encoder=d.laser_encoder, obstacle_encoder=d.obstacle_encoder)


def lookahead_network(config, shapes, n_actions: int) -> LookaheadQNetwork:
    """The ``LookaheadQNetwork`` of a run: the task's laser ring, pedestrian slots and drive from its task
    options (the task's defaults when not given); ValueError unless the state is ``lasers | target |
    odometry | humans`` and the drive the discrete one."""
    from dynnav_tasks.drive import DISCRETE_DRIVE
    from dynnav_tasks.egocentric import egocentric_space
    from dynnav_tasks.lasers import LaserConfig
    from dynnav_tasks.nav_env import ROBOT_RADIUS
    from dynnav_tasks.robot import DriveConfig
    from dynnav_tasks.tasks.crowd import DEFAULT_HUMAN_K
    from dynnav_tasks.tasks.procedural import DEFAULT_OBSTACLE_K

    kw, crowd = config.env.task_kwargs, config.task == "DynNav-Crowd-v1"
    human_k = int(kw.get("human_k", DEFAULT_HUMAN_K if crowd else 0))
    obstacle_k = 0 if crowd else int(kw.get("obstacle_k", DEFAULT_OBSTACLE_K))
    if (kw.get("odometry") is not True or kw.get("way") or obstacle_k or human_k < 1
            or kw.get("control_mode", DISCRETE_DRIVE) != DISCRETE_DRIVE):
        raise ValueError(f"lookahead reads the egocentric state lasers | target | odometry | pedestrians with the "
                         f"discrete drive: set the task options odometry=True and human_k >= 1, and no way, no "
                         f"obstacle slots (obstacle_k=0), no control_mode; this run has {dict(kw)}")
    lasers = LaserConfig.of(kw.get("laser_rays", LaserConfig.rays), kw.get("laser_fov_deg", LaserConfig.fov_deg),
                            kw.get("laser_range", LaserConfig.max_range))
    if not lasers.full_circle:
        raise ValueError(f"lookahead turns the laser ring with the robot: it needs the full ring (laser_fov_deg=360), "
                         f"not {lasers.fov_deg:g} degrees")
    drive = DriveConfig(**{name: kw[name] for name in ("forward_step", "turn_step", "turn_forward_step") if name in kw})
    moves = [(drive.forward_step, 0.0), (drive.turn_forward_step, drive.turn_step),
             (drive.turn_forward_step, -drive.turn_step)]
    if n_actions != len(moves):
        raise ValueError(f"lookahead scores the discrete drive's {len(moves)} actions; this run has {n_actions}")
    space = egocentric_space(lasers.rays, lasers.max_range, 0, human_k=human_k, odometry=True)
    if shapes != [space.shape]:
        raise ValueError(f"lookahead expects one state of {space.shape[0]} values (lasers, target, odometry, "
                         f"{human_k} pedestrians); this run's inputs have shapes {shapes}")
    scaler = ObsScaler(space, config.env.normalize_obs)
    return LookaheadQNetwork(moves, lasers.angles().tolist(), lasers.max_range, ROBOT_RADIUS, human_k,
                             config.dqn.hidden_sizes, scaler.offset.tolist(), scaler.scale.tolist())


def build_learner(config, q_network: nn.Module, input_specs) -> DQNLearner:
    """The run's (Double) DQN update of ``q_network``: a ``DQNLearner`` on minibatches of transitions,
    or with ``recurrent`` a ``RecurrentLearner`` on minibatches of sequences."""
    d = config.dqn
    settings = dict(gamma=d.gamma, double=d.algorithm == "ddqn", loss=d.loss, max_grad_norm=d.max_grad_norm,
                    learning_rate=config.schedule.learning_rate, device=config.run.device)
    if d.recurrent:
        return RecurrentLearner(q_network, SequenceBatch(d.batch_size, d.sequence_length, d.burn_in,
                                                         input_specs[0][0][0]), **settings)
    t = config.demos  # the large-margin loss on a teacher's labels (DQfD), when its demonstrations are kept
    margin = dict(margin_weight=t.margin_weight, margin=t.margin) if t.demonstrations else {}
    return DQNLearner(q_network, Batch(d.batch_size, input_specs), **settings, **margin)


@dataclass
class Policy:
    """A trained Q-network with the features that turn observations into its inputs."""

    config: object
    """the run's resolved config"""
    env: object
    features: object
    q_network: nn.Module
    path: Path
    """the checkpoint folder"""
    state: dict
    """the checkpoint's state without its replay memory"""
    hidden: object = None
    """a recurrent Q-network's state in the current episode (None: its start; see ``reset``)"""

    @property
    def device(self) -> torch.device:
        """Where the Q-network's parameters live."""
        return next(self.q_network.parameters()).device

    def reset(self) -> None:
        """An episode starts (call it after every ``env.reset``): a recurrent Q-network forgets the last one."""
        self.hidden = None

    def q_values(self, obs) -> np.ndarray:
        """Q-values (actions,) of an environment observation (for a recurrent Q-network, of the
        episode's next observation: its hidden state moves one step on)."""
        if isinstance(self.q_network, RecurrentQNetwork):
            q, self.hidden = self.q_network.step(self.features(obs), self.hidden, self.device)
            return q
        return q_values_of(self.q_network, self.features(obs), self.device)

    @property
    def views(self):
        """obs -> the auto-encoder's latent and reconstruction (camera latent runs), else None."""
        return getattr(self.features, "views", None)
