"""The training configuration: dataclasses grouped by job, parsed by tyro, loadable from YAML.

    python -m agents.dqn --config configs/study/5.2.yaml --seed 3 --learning-rate 0.001

``Config`` holds the task, the run's name, seed and episode count, the mode (``--eval``,
``--resume``) and one group per job: ``env`` (reward and task options), ``dqn`` (the algorithm
and network), ``schedule`` (epsilon and learning rate per episode), ``camera`` (camera runs),
``test`` (the test phase) and ``run`` (files, device, recordings). Flags keep their field names
(``--learning-rate``, not ``--dqn.learning-rate``); ``--help`` lists them by group. A YAML file
groups them the same way (``dqn: {learning_rate: 0.001}``) and may start from another file
(``base:``); reading and writing YAML is ``agents/training/config_io.py``. This module also
checks a Config (``validate``): every field with an impossible value is an error naming it.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Literal, Optional

from dynnav_tasks.task_options import TaskOption, parse_task_options


@dataclass
class EnvConfig:
    """Task options (dynnav tasks)."""

    reward_mode: Optional[str] = None
    """dynnav reward function (sparse, distance, distance_orientation, distance_orientation_always, potential,
    potential_as_written); None: the task's default"""
    reward_params: dict[str, float] = field(default_factory=dict)
    """dynnav overrides of dynnav_tasks.rewards.RewardParams, e.g. potential_gamma 0.95 (on the command line,
    the keys given replace those of the --config YAML and the others stay)"""
    task_kwargs: dict[str, TaskOption] = field(default_factory=dict)
    """dynnav task options, e.g. turn_forward_step 0.05 camera_size 32 (integers stay integers; on the command
    line, the keys given replace those of the --config YAML and the others stay)"""
    normalize_obs: bool = True
    """scale every bounded state component to [-1, 1] using the observation space's bounds"""
    state_frames: int = 1
    """state-vector runs: the Q-network reads the last N state vectors, oldest first, the first one
    repeated after a reset (beyond the study, which used 1: one state holds the obstacles'
    positions but not their speeds, two show how they move)"""


@dataclass
class DQNConfig:
    """The algorithm and the Q-network."""

    algorithm: Literal["dqn", "ddqn"] = "dqn"
    """dqn: target max_a Q_target(s', a) (Alg. 1); ddqn: Q_target(s', argmax_a Q(s', a)) (Appendix A)"""
    gamma: float = 0.97
    """discount factor"""
    hidden_sizes: tuple[int, ...] = (128, 128)
    """widths of the Q-network's ReLU hidden layers (the MLP on state vectors and latents)"""
    q_network: Optional[str] = None
    """your own Q-network: 'package.module:factory', factory(input_shapes, n_actions) -> torch.nn.Module
    (e.g. agents.core.networks:dueling_mlp); None: the MLP (or, with camera_input pixels, the conv net)"""
    batch_size: int = 128
    """minibatch size"""
    buffer_size: int = 100_000
    """replay memory capacity (transitions)"""
    learning_starts: int = 1000
    """environment steps collected before the first update"""
    train_frequency: int = 1
    """one update every this many environment steps"""
    loss: Literal["mse", "huber"] = "mse"
    """TD loss: mean squared error (the thesis) or Huber (smooth L1, delta 1)"""
    max_grad_norm: float = 0.0
    """clip the gradient's global norm to this; 0: no clipping"""
    target_update: Literal["hard", "soft"] = "hard"
    """hard: copy the network every target_update_interval steps; soft: theta- <- tau theta + (1 - tau) theta- every update"""
    target_update_interval: int = 500
    """environment steps between hard target copies (C in Alg. 1)"""
    tau: float = 0.005
    """soft target update rate"""
    laser_encoder: Literal["flat", "conv"] = "flat"
    """egocentric state (DynNav-Procedural-v1): conv reads the laser ring with a circular 1-D convolution
    (agents/core/encoders.py); flat: as one more part of the MLP's input"""
    obstacle_encoder: Literal["flat", "pooled"] = "flat"
    """egocentric state: pooled reads the tracked obstacles with one shared MLP and a max over them, whatever
    their order; flat: as they are"""
    lookahead: bool = False
    """look one step ahead (agents/core/lookahead.py, CrowdNav's value look-ahead): Q(s, a) is a value network's
    reading of the state action a leads to, the robot moved by the drive and each pedestrian at its last velocity;
    needs the discrete drive and the egocentric state with odometry=True and human_k >= 1 (no way, no obstacle slots)"""
    recurrent: Optional[Literal["gru", "lstm"]] = None
    """memory (docs/memory.md): gru or lstm puts that recurrent layer (recurrent_size) between an MLP encoder
    (hidden_sizes) and the Q head, its state carried through each episode, and trains on stored sequences of
    sequence_length steps after up to burn_in warm-up steps (batch_size counts sequences); None: no memory"""
    recurrent_size: int = 128
    """recurrent: width of the GRU's or LSTM's hidden state"""
    sequence_length: int = 20
    """recurrent: transitions per sampled sequence that carry the loss"""
    burn_in: int = 10
    """recurrent: steps before each sampled sequence (never before its episode's start) that only warm up the
    hidden state"""


@dataclass
class ScheduleConfig:
    """Exploration and learning rate, changed once per episode."""

    learning_rate: float = 0.003
    """Adam learning rate (at the first episode)"""
    learning_rate_end: float = 0.0003
    """learning rate reached after lr_decay_episodes (ignored by the constant schedule)"""
    lr_schedule: Literal["constant", "linear", "exponential"] = "constant"
    """how the learning rate moves from learning_rate to learning_rate_end"""
    lr_decay_episodes: int = 2000
    """episodes over which the learning rate decays"""
    random_episodes: int = 0
    """first episodes played at epsilon 1 (fully random), before the decay starts"""
    epsilon_start: float = 0.8
    """epsilon when the decay starts"""
    epsilon_end: float = 0.05
    """epsilon after the decay"""
    epsilon_decay_episodes: int = 1000
    """episodes over which epsilon decays (after random_episodes)"""
    epsilon_schedule: Literal["linear", "exponential"] = "linear"
    """how epsilon moves from epsilon_start to epsilon_end"""


@dataclass
class CameraConfig:
    """Camera runs (dynnav camera worlds): the study's auto-encoder (Sec. 4.3, Alg. 2) or pixels end to end."""

    camera_frames: int = 0
    """0: the Q-network reads the task's state vector; 1: the RGB camera frame; N >= 2: the stack of the last N gray frames"""
    camera_input: Literal["latent", "pixels"] = "latent"
    """latent: the study's auto-encoder compresses each frame, on Alg. 2's schedule; pixels: a conv
    Q-network reads the frames and its encoder learns from the TD loss (with random shifts)"""
    camera_state: tuple[str, ...] = ()
    """with a camera: parts of the state vector fed beside the frames (Table 5.4), e.g. lasers robot_xy
    obstacles (every obstacle's position); see the task's state_layout()"""
    pixel_shift: int = 2
    """camera_input pixels: random shift of up to this many pixels per frame in the update (DrQ); 0: none"""
    ae_latent: int = 0
    """auto-encoder latent size; 0: 10 for one frame, 15 for stacks (Table 5.3)"""
    ae_conv_channels: tuple[int, ...] = ()
    """filters of the two convolutions; empty: 32 64 for one frame, 64 128 for stacks"""
    ae_dense: int = 64
    """width of the auto-encoder's dense layer"""
    ae_learning_rate: float = 0.001
    """Adam learning rate of the auto-encoder"""
    ae_first_update: int = 400
    """episode of the first auto-encoder update; before it actions are random and the Q-network does not train"""
    ae_update_every: int = 400
    """episodes between auto-encoder updates"""
    ae_updates: int = 0
    """number of auto-encoder updates; 0: 3 for one frame, 4 for stacks"""
    ae_iterations: int = 0
    """iterations per update; 0: 20 for one frame, 40 for stacks"""
    ae_batches: int = 0
    """batches per iteration; 0: 50 for one frame, 25 for stacks"""
    ae_batch_size: int = 256
    """frames per auto-encoder batch"""
    ae_rare_colour_power: float = 0.0
    """beyond the study: weight each pixel's reconstruction error by (frequency of its colour in the
    observation memory)^-p, normalised to a mean weight of 1; 0: every pixel the same (Eq. 4.10)"""
    ae_pictures_every: int = 100
    """save observation / reconstruction pairs every this many episodes once the auto-encoder is trained"""


@dataclass
class DemoConfig:
    """Learning beside a teacher (agents.imitation): start from its student, keep its demonstrations (DQfD)."""

    init_from: Optional[str] = None
    """a run directory or checkpoint whose Q-network this run starts from (online and target), e.g. an
    agents.imitation run's cloned student; its network must be this run's"""
    demonstrations: Optional[str] = None
    """an agents.imitation run directory: its labelled episodes (demonstrations.npz) stay in the replay
    for the whole run and fill demo_share of every minibatch, with the large-margin loss on their
    labels (DQfD, Hester et al. 2018); they must come from this run's task, observation and reward"""
    demo_share: float = 0.25
    """share of each minibatch drawn from the demonstrations"""
    margin_weight: float = 1.0
    """weight of the large-margin loss on the demonstrations' rows (0: the TD loss only)"""
    margin: float = 0.8
    """how far Q(s, teacher's action) should lead every other action's Q-value"""
    pretrain_updates: int = 0
    """updates on the demonstrations alone before the first episode (DQfD's pre-training)"""


@dataclass
class TestConfig:
    """The test phase (after training, or of a checkpoint with --eval)."""

    eval_after_training: bool = True
    """run the test phase when training ends"""
    eval_episodes: int = 100
    """test episodes (greedy unless eval_epsilon > 0)"""
    eval_seed: int = 1_000_000
    """test episode i is reset with seed eval_seed + i (training episodes use other seeds)"""
    eval_epsilon: float = 0.0
    """probability of a random action in a test step (0: greedy, as the study tests)"""
    eval_out: Optional[str] = None
    """folder for eval.json, eval.md and the pictures of --eval (default: beside the checkpoint)"""
    eval_picture: bool = True
    """draw the test trajectories on the task's top-down picture (dynnav tasks)"""
    eval_task_kwargs: dict[str, TaskOption] = field(default_factory=dict)
    """task options changed for the test phase only, laid over the run's own (e.g. split test: a
    DynNav-Procedural-v1 navigator tested in held-out worlds). With --eval and no --eval-out, the
    results go to tests/<key=value,...>/ in the run directory"""
    also_test_on: tuple[str, ...] = ()
    """after the test phase, one more per entry, with the task options 'key=value,key=value' laid
    over the run's own (e.g. split=ood, or obstacle_count=4,obstacle_speed_scale=1.5), written to
    tests/<entry>/ in the run directory; each is a row of the run table (tested_on)"""


@dataclass
class RunConfig:
    """Files, device and recordings."""

    runs_dir: str = "runs"
    """directory the run directories are created in"""
    checkpoint_every: int = 100
    """write a checkpoint (and the learning-curve pictures) every this many episodes"""
    progress: bool = True
    """show a progress bar"""
    device: str = "cpu"
    """where the Q-network and its update run: cpu, cuda or cuda:N (an error if torch sees no GPU)"""
    rerun: Optional[str] = None
    """write a Rerun recording (.rrd) here: every rerun_every-th training episode step by step with
    its Q-values, the training curves, and (with --eval) every test episode"""
    rerun_every: int = 100
    """record every this many training episodes (the first included)"""
    tensorboard: bool = False
    """also write TensorBoard scalars (return, success, collision, loss, epsilon, learning rate, steps/s)
    into tensorboard/ in the run directory (needs pip install 'dynnav[tensorboard]')"""
    fast: bool = False
    """train on two processes: this one steps the environment, a second one makes the updates from a
    shared replay memory (same number of updates per step); faster, but not replayable bit for bit
    (docs/fast-training.md). State-vector and pixel runs (not camera_input latent)"""
    fast_sync_steps: int = 50
    """fast mode: the acting network copies the learner's latest weights every this many steps"""


@dataclass
class Config:
    """Train a DQN / Double DQN agent, or test a trained one (--eval)."""

    config: Optional[str] = None
    """YAML file of settings to start from (with --resume: the run's config.yaml); flags override it"""
    task: str = "DynNav-MovingTarget-v1"
    """gymnasium task id: a dynnav task (dynnav_tasks.ALL_TASK_IDS) or any env with Discrete actions and a Box state"""
    name: str = "dqn"
    """experiment name, part of the run directory runs/<task>__<name>__<seed>__<time> (default: the
    --config file's own name: field, else its file name without .yaml; never taken from a base:)"""
    description: str = ""
    """one line saying what the experiment is (a --config file's own description:, never taken from a base:)"""
    seed: int = 1
    """seeds the networks, exploration, replay sampling and every training episode"""
    episodes: int = 2000
    """training episodes"""
    eval: bool = False
    """test a checkpoint (--checkpoint) with its own settings instead of training"""
    checkpoint: Optional[str] = None
    """checkpoint (or run directory) to test with --eval, or pretrained:NAME (python -m agents.pretrained list)"""
    resume: Optional[str] = None
    """run directory of a stopped run to continue from its last checkpoint"""
    env: EnvConfig = field(default_factory=EnvConfig)
    """task options"""
    dqn: DQNConfig = field(default_factory=DQNConfig)
    """the algorithm and the Q-network"""
    schedule: ScheduleConfig = field(default_factory=ScheduleConfig)
    """exploration and learning rate per episode"""
    camera: CameraConfig = field(default_factory=CameraConfig)
    """camera runs"""
    demos: DemoConfig = field(default_factory=DemoConfig)
    """learning beside a teacher"""
    test: TestConfig = field(default_factory=TestConfig)
    """the test phase"""
    run: RunConfig = field(default_factory=RunConfig)
    """files, device and recordings"""

    def validate(self) -> "Config":
        """Raise ValueError naming the first field with an impossible value; return the config."""
        validate(self)
        return self


GROUPS = {"env": EnvConfig, "dqn": DQNConfig, "schedule": ScheduleConfig, "camera": CameraConfig,
          "demos": DemoConfig, "test": TestConfig, "run": RunConfig}
MODE_FIELDS = ("config", "eval", "checkpoint", "resume")
"""top-level fields that choose what a command does; not written to a run's config.yaml"""
GROUP_OF = {f.name: group for group, cls in GROUPS.items() for f in dataclasses.fields(cls)}
"""group of every grouped field, e.g. learning_rate -> schedule"""


def get(config: Config, name: str):
    """A field's value by its name (grouped or top level)."""
    group = GROUP_OF.get(name)
    return getattr(getattr(config, group), name) if group else getattr(config, name)


# ---------------------------------------------------------------------------------------- validation
POSITIVE = ["episodes", "checkpoint_every", "batch_size", "buffer_size", "train_frequency", "target_update_interval",
            "eval_episodes", "lr_decay_episodes", "rerun_every", "ae_dense", "ae_update_every", "ae_batch_size",
            "ae_pictures_every", "state_frames", "fast_sync_steps"]
NOT_NEGATIVE = ["learning_starts", "random_episodes", "epsilon_decay_episodes", "camera_frames", "ae_latent",
                "ae_first_update", "ae_updates", "ae_iterations", "ae_batches", "pixel_shift", "pretrain_updates"]


def validate(c: Config) -> None:
    """Raise ValueError naming the first field with an impossible value."""
    for name in POSITIVE:
        if get(c, name) < 1:
            raise ValueError(f"{name} must be at least 1, got {get(c, name)}")
    for name in NOT_NEGATIVE:
        if get(c, name) < 0:
            raise ValueError(f"{name} must not be negative, got {get(c, name)}")
    if "\n" in c.description or "\r" in c.description:
        raise ValueError(f"description must be one line, got {c.description!r}: say more in the docs, "
                         f"or in a comment of the config file")
    d, s, cam = c.dqn, c.schedule, c.camera
    checks = {
        "gamma": 0.0 <= d.gamma <= 1.0,
        "tau": 0.0 < d.tau <= 1.0,
        "learning_rate": s.learning_rate > 0,
        "learning_rate_end": s.learning_rate_end > 0,
        "epsilon_start": 0.0 <= s.epsilon_start <= 1.0,
        "epsilon_end": 0.0 <= s.epsilon_end <= 1.0,
        "eval_epsilon": 0.0 <= c.test.eval_epsilon <= 1.0,
        "max_grad_norm": d.max_grad_norm >= 0,
        "hidden_sizes": len(d.hidden_sizes) > 0 and all(h > 0 for h in d.hidden_sizes),
        "ae_learning_rate": cam.ae_learning_rate > 0,
        "ae_rare_colour_power": 0.0 <= cam.ae_rare_colour_power <= 2.0,
        "ae_conv_channels": len(cam.ae_conv_channels) in (0, 2) and all(v > 0 for v in cam.ae_conv_channels),
        "demo_share": 0.0 < c.demos.demo_share <= 1.0,
        "margin_weight": c.demos.margin_weight >= 0,
        "margin": c.demos.margin >= 0,
    }
    for name, ok in checks.items():
        if not ok:
            raise ValueError(f"{name} has an impossible value: {get(c, name)!r}")
    if d.batch_size > d.buffer_size:
        raise ValueError(f"batch_size ({d.batch_size}) is larger than buffer_size ({d.buffer_size}): the replay "
                         f"memory could never fill a minibatch and no update would run; lower --batch-size or raise "
                         f"--buffer-size")
    if cam.camera_state and not cam.camera_frames:
        raise ValueError("camera_state selects state parts to feed beside the camera: set camera_frames too "
                         "(without a camera the whole state vector is used)")
    if c.env.state_frames > 1 and cam.camera_frames:
        raise ValueError("state_frames stacks state vectors for runs without a camera; with camera_frames, "
                         "camera_frames N >= 2 already stacks frames")
    if cam.camera_input == "pixels" and not cam.camera_frames:
        raise ValueError("camera_input pixels reads camera frames: set camera_frames (1: RGB, N >= 2: N gray frames)")
    for entry in c.test.also_test_on:
        try:
            parse_task_options(entry)
        except ValueError as err:
            raise ValueError(f"also_test_on: {err}") from err
    if c.run.fast and not c.eval:
        check_fast(c)
    validate_memory(c)
    validate_demos(c)
    check_device(c.run.device)
    if c.run.tensorboard and not c.eval:
        from agents.training.tensorboard_log import check_available

        check_available()
    if c.eval and not c.checkpoint:
        raise ValueError("--eval needs --checkpoint <checkpoint or run directory>")


def check_fast(c: Config) -> None:
    """ValueError if the fast mode (run.fast) cannot train ``c``."""
    if c.camera.camera_frames and c.camera.camera_input != "pixels":
        raise ValueError("the fast mode (--fast) trains state-vector and pixel runs (camera_input pixels); the "
                         "auto-encoder of camera_input latent retrains between episodes in the single-process loop: "
                         "drop --fast, or set --camera-input pixels")
    if c.run.rerun is not None:
        raise ValueError("the fast mode (--fast) does not record training episodes: drop --rerun, or --fast "
                         "(a trained run can still be recorded with --eval --rerun)")
    if c.dqn.recurrent:
        raise ValueError(f"the fast mode (--fast) trains feed-forward Q-networks; recurrent {c.dqn.recurrent!r} "
                         "trains on sequences in the single-process loop: drop --fast")


def validate_memory(c: Config) -> None:
    """ValueError if the recurrent Q-network's settings (``dqn.recurrent`` ...) are impossible or clash."""
    d = c.dqn
    for name, low in (("recurrent_size", 1), ("sequence_length", 1), ("burn_in", 0)):
        if get(c, name) < low:
            raise ValueError(f"{name} must be at least {low}, got {get(c, name)}")
    if not d.recurrent:
        return
    if d.q_network:
        raise ValueError(f"recurrent {d.recurrent!r} builds its own Q-network; it cannot be combined with "
                         f"q_network {d.q_network!r} (set one of them)")
    if c.camera.camera_frames and c.camera.camera_input == "pixels":
        raise ValueError(f"recurrent {d.recurrent!r} reads vectors (the state, or the auto-encoder's latent "
                         f"beside state parts); with camera_input pixels use camera_input latent")


def validate_demos(c: Config) -> None:
    """ValueError if the teacher's settings (``demos``) or the egocentric encoders clash with the run's."""
    t = c.demos
    if t.pretrain_updates and not t.demonstrations:
        raise ValueError("pretrain_updates trains on demonstrations before the first episode: set demonstrations "
                         "(an agents.imitation run directory) too")
    d = c.dqn
    if (d.laser_encoder, d.obstacle_encoder) != ("flat", "flat") and (d.q_network or d.recurrent or c.camera.camera_frames
                                                                      or c.env.state_frames != 1):
        raise ValueError("laser_encoder and obstacle_encoder read one egocentric state vector: not with q_network, "
                         "recurrent, camera_frames or state_frames > 1")
    if d.lookahead and (d.q_network or d.recurrent or c.camera.camera_frames or c.env.state_frames != 1
                        or (d.laser_encoder, d.obstacle_encoder) != ("flat", "flat")):
        raise ValueError("lookahead builds its own Q-network on one egocentric state vector: not with q_network, "
                         "recurrent, laser_encoder, obstacle_encoder, camera_frames or state_frames > 1")
    if (t.init_from or t.demonstrations) and (c.dqn.recurrent or c.camera.camera_frames or c.env.state_frames != 1):
        raise ValueError("init_from and demonstrations start from a student that reads one state vector: not with "
                         "recurrent, camera_frames or state_frames > 1")


def check_device(device: str) -> None:
    """ValueError unless ``device`` is cpu, or a GPU torch can use."""
    import torch

    try:
        dev = torch.device(device)
    except RuntimeError as err:
        raise ValueError(f"device {device!r} is not a torch device (use cpu, cuda or cuda:N): {err}") from err
    if dev.type == "cuda":
        if not torch.cuda.is_available():
            raise ValueError(f"device {device!r} was asked for, but torch finds no GPU here "
                             f"(torch.cuda.is_available() is False); use --device cpu")
        if dev.index is not None and dev.index >= torch.cuda.device_count():
            raise ValueError(f"device {device!r}: torch sees {torch.cuda.device_count()} GPU(s)")
    elif dev.type != "cpu":
        raise ValueError(f"device {device!r}: use cpu, cuda or cuda:N")

