"""Memory: the recurrent Q-network (``dqn.recurrent``), its sequences of stored episodes and its runs."""

import csv

import gymnasium as gym
import numpy as np
import pytest
import torch

from agents.core.frame_replay import FrameReplay
from agents.core.recurrent import RecurrentLearner, RecurrentQNetwork
from agents.core.sequence_replay import SequenceBatch, draw_windows, sample_sequences_into
from agents.dqn import main, train
from agents.training import checkpoint as ckpt
from agents.training.config_io import load_yaml, make
from agents.training.policy_loading import load_policy
from agents.training.test_phase import evaluate
from agents.training.threads import limit_threads

TIMING = {"steps_per_s", "wall_time_s"}
NO_FRAME = np.zeros(0, np.uint8)


class Draws:
    """A stand-in for numpy's generator that draws the given slots, to place windows by hand."""

    def __init__(self, slots):
        self.slots = np.array(slots)

    def integers(self, low, high, size):
        assert len(self.slots) == size and (self.slots < high).all()
        return self.slots.copy()


def store(memory: FrameReplay, lengths, first_value=0) -> None:
    """Episodes of the given lengths; an observation's state is its running number, a transition's
    reward the number of the observation it starts from."""
    v = first_value
    for length in lengths:
        memory.start(NO_FRAME, np.array([v], np.float32))
        for t in range(length):
            memory.add(t % 3, float(v), NO_FRAME, np.array([v + 1], np.float32), terminated=t == length - 1)
            v += 1
        v += 1


def test_windows_start_at_most_burn_in_back_within_the_episode_and_mask_its_end():
    memory = FrameReplay(40, (0,), state_dim=1, latent_dim=0)
    store(memory, [3, 4, 5])  # slots 0-3, 4-8, 9-14; 3, 8 and 14 are episode ends (no transition)
    # first steps with loss: 5 (1 step into episode 2), 11 (2 steps into episode 3), 0 (an episode's start)
    w = draw_windows(memory, 3, length=3, burn_in=2, rng=Draws([5, 11, 0]))
    assert w.burn.tolist() == [1, 2, 0]
    assert w.slots[:, 0].tolist() == [4, 9, 0]
    assert w.slots.shape == (3, 2 + 3 + 1)
    # window of 5 transitions; loss on steps burn .. burn + 2 while the episode lasts
    assert w.mask.astype(int).tolist() == [
        [0, 1, 1, 1, 0],   # slots 4..8: transitions 5, 6, 7 (slot 8 ends the episode)
        [0, 0, 1, 1, 1],   # slots 9..13: transitions 11, 12, 13
        [1, 1, 1, 0, 0],   # slots 0..4: transitions 0, 1, 2; slot 3 ends episode 1
    ]
    batch = SequenceBatch(3, 3, 2, 1)
    sample_sequences_into(memory, batch, Draws([5, 11, 0]))
    assert batch.obs[0, :, 0].tolist() == [4, 5, 6, 7, 8, 9]  # the observations of slots 4 to 9
    assert batch.rewards[0, 1:4].tolist() == [5, 6, 7]  # the transitions from slots 5, 6, 7 ...
    assert batch.not_done[0, 1:4].tolist() == [1, 1, 0]  # ... the last of them terminal
    assert batch.actions[1, 2:5].tolist() == [2, 0, 1]  # episode 3's steps 2, 3, 4
    np.testing.assert_array_equal(batch.mask, w.mask)


def test_windows_never_reach_back_past_the_oldest_slot_held():
    memory = FrameReplay(8, (0,), state_dim=1, latent_dim=0)
    store(memory, [4, 5])  # 5 + 6 slots in 8: episode 2's slots 5-7 and 0-2; the head is at slot 3
    assert (memory.pos, memory.size) == (3, 8)
    # slot 4 (episode 1's end, kept) starts no transition; slot 5 starts episode 2
    w = draw_windows(memory, 2, length=2, burn_in=3, rng=Draws([7, 3]))
    assert w.burn.tolist() == [2, 0]  # slot 7: back to 5, episode 2's start; slot 3: the oldest held
    assert w.slots[0].tolist() == [5, 6, 7, 0, 1, 2]
    # loss on steps 2-3 of the first window; the second ends with episode 1 at slot 4
    assert w.mask.astype(int).tolist() == [[0, 0, 1, 1, 0], [1, 0, 0, 0, 0]]


def cue_episodes(memory: FrameReplay, n: int, rng) -> None:
    """A memory task: a cue (+1 or -1) is seen at the first step only; after two blank steps the
    last step's action pays 1 if it names the cue (action 1 for +1, 0 for -1)."""
    for _ in range(n):
        cue = rng.choice([-1.0, 1.0])
        memory.start(NO_FRAME, np.array([cue, 0.0], np.float32))
        for t in range(3):
            action = int(rng.integers(2))
            last = t == 2
            nxt = np.array([0.0, 1.0 if t == 1 else 0.0], np.float32)
            reward = float(action == (cue > 0)) if last else 0.0
            memory.add(action, reward, NO_FRAME, nxt, terminated=last)


@pytest.mark.parametrize("cell", ["gru", "lstm"])
def test_the_hidden_state_remembers_a_cue_and_starts_at_zero_each_episode(cell):
    limit_threads(1)
    torch.manual_seed(0)
    net = RecurrentQNetwork(2, 2, (16,), hidden=16, cell=cell)
    learner = RecurrentLearner(net, SequenceBatch(32, 3, 2, 2), gamma=0.9, double=True, learning_rate=0.01)
    memory, rng = FrameReplay(2000, (0,), state_dim=2, latent_dim=0), np.random.default_rng(0)
    cue_episodes(memory, 400, rng)
    for _ in range(150):
        sample_sequences_into(memory, learner.batch, rng)
        learner.update()

    def last_q(cue):
        learner.reset()
        for x in ([cue, 0.0], [0.0, 0.0], [0.0, 1.0]):
            q = learner.q_values(np.array(x, np.float32))
        return q

    plus, minus = last_q(1.0), last_q(-1.0)
    # the last input is the same; only the cue two steps earlier tells the right action
    assert plus[1] > plus[0] + 0.5 and minus[0] > minus[1] + 0.5, (plus, minus)
    learner.reset()
    np.testing.assert_allclose(learner.q_values(np.array([1.0, 0.0], np.float32)),
                               net.step(np.array([1.0, 0.0], np.float32))[0], rtol=1e-6)


class CueEnv(gym.Env):
    """The memory task as an environment: a cue (+1 or -1) shown at the first of four steps; the
    last step's action pays 1 if it names the cue. Without memory, at best half the episodes pay."""

    observation_space = gym.spaces.Box(-1.0, 1.0, (2,), np.float32)
    action_space = gym.spaces.Discrete(2)

    def reset(self, seed=None, options=None):
        super().reset(seed=seed)
        self.cue, self.t = float(self.np_random.choice([-1.0, 1.0])), 0
        return np.array([self.cue, 0.0], np.float32), {}

    def step(self, action):
        self.t += 1
        if self.t < 4:
            return np.array([0.0, float(self.t == 3)], np.float32), 0.0, False, False, {}
        return np.zeros(2, np.float32), float(int(action) == (self.cue > 0)), True, False, {}


gym.register("MemoryCue-v0", entry_point=CueEnv)


def small(tmp_path, **overrides):
    values = dict(task="MemoryCue-v0", episodes=30, learning_starts=20, batch_size=8, hidden_sizes=(16,),
                  recurrent="gru", recurrent_size=16, sequence_length=4, burn_in=4, buffer_size=1000,
                  checkpoint_every=15, target_update_interval=10, epsilon_decay_episodes=20,
                  runs_dir=str(tmp_path / "runs"), progress=False, eval_after_training=False, seed=3)
    values.update(overrides)
    return make(**values).validate()


def rows(run_dir):
    with open(run_dir / "metrics.csv", newline="") as f:
        return [{k: v for k, v in r.items() if k not in TIMING} for r in csv.DictReader(f)]


def test_a_recurrent_run_resumes_exactly_and_its_policy_carries_its_state_through_an_episode(tmp_path):
    whole = rows(train(small(tmp_path, name="whole")))
    assert any(r["loss"] for r in whole), "the run made no update"
    stopped = train(small(tmp_path, name="stopped", episodes=15))
    main(["--resume", str(stopped), "--episodes", "30", "--no-progress", "--no-eval-after-training"])
    assert rows(stopped) == whole  # same seed: same losses, returns and epsilons as the run that never stopped
    assert ckpt.load(stopped)["episode"] == 30
    with pytest.raises(SystemExit, match="recurrent"):
        main(["--resume", str(stopped), "--recurrent", "lstm", "--no-progress"])

    policy = load_policy(stopped)
    obs, _ = policy.env.reset(seed=0)
    policy.reset()
    first = policy.q_values(obs)
    second = policy.q_values(obs)  # the same observation, one step later in the episode
    assert not np.allclose(first, second)
    policy.reset()
    np.testing.assert_allclose(policy.q_values(obs), first, rtol=1e-6)
    policy.env.close()
    summary = evaluate(stopped, episodes=4, picture=False, verbose=False)
    assert summary["episodes"] == 4


@pytest.mark.parametrize("recurrent", ["gru", None])
def test_only_memory_learns_a_task_that_needs_it(tmp_path, recurrent):
    """150 episodes of the cue task (600 steps, an update every other step): the GRU names the
    cue, the MLP guesses."""
    config = make(task="MemoryCue-v0", algorithm="ddqn", episodes=150, gamma=0.9, learning_rate=0.003,
                  epsilon_decay_episodes=75, batch_size=16, hidden_sizes=(32,), recurrent=recurrent,
                  recurrent_size=32, sequence_length=4, burn_in=4, learning_starts=100, train_frequency=2,
                  target_update_interval=100, checkpoint_every=150, runs_dir=str(tmp_path), progress=False, eval_after_training=False,
                  seed=1).validate()
    summary = evaluate(train(config), episodes=50, picture=False, verbose=False)
    if recurrent:
        assert summary["avg_return"] >= 0.95, summary
    else:
        assert summary["avg_return"] <= 0.75, summary


@pytest.mark.parametrize("values, message", [
    (dict(recurrent="gru", q_network="agents.core.networks:dueling_mlp"), "cannot be combined with q_network"),
    (dict(recurrent="gru", camera_frames=1, camera_input="pixels"), "camera_input latent"),
    (dict(sequence_length=0), "sequence_length must be at least 1"),
    (dict(burn_in=-1), "burn_in must be at least 0"),
    (dict(recurrent_size=0), "recurrent_size must be at least 1"),
])
def test_impossible_memory_settings_are_errors_naming_them(values, message):
    with pytest.raises(ValueError, match=message):
        make(**values).validate()


def test_an_unknown_recurrent_layer_in_a_config_file_is_an_error(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("dqn: {recurrent: rnn}\n")
    with pytest.raises(ValueError, match="recurrent"):
        load_yaml(path)


def test_a_camera_run_replays_its_sequences_through_the_current_encoder(tmp_path):
    """World 5.5a with the auto-encoder updated after episodes 1 and 2 (tiny updates): the
    Q-network trains after the first, and every stored frame's latent is the current encoder's."""
    import agents.training.loop as loop

    config = make(task="DynNav-VisualStaticTarget-v1", camera_frames=1, episodes=3, ae_first_update=1,
                  ae_update_every=1, ae_updates=2, ae_iterations=1, ae_batches=2, ae_batch_size=16,
                  ae_pictures_every=10, random_episodes=1, epsilon_decay_episodes=2, learning_starts=16,
                  batch_size=4, hidden_sizes=(16,), recurrent="gru", recurrent_size=16, sequence_length=4,
                  burn_in=2, buffer_size=2000, checkpoint_every=3, runs_dir=str(tmp_path), progress=False,
                  eval_after_training=False, seed=5).validate()
    seen = {}
    original = loop.update_state_representation

    def spy(srl, memory, rng, episodes_done, cfg, run_dir):
        original(srl, memory, rng, episodes_done, cfg, run_dir)
        seen.update(srl=srl, memory=memory)

    loop.update_state_representation = spy
    try:
        run = loop.train(config)
    finally:
        loop.update_state_representation = original
    losses = [r["loss"] for r in rows(run)]
    assert losses[0] == "" and all(losses[1:]), losses  # random until the first update, then training
    srl, memory = seen["srl"], seen["memory"]
    assert srl.updates_done == 2
    batch = SequenceBatch(8, 4, 2, srl.latent_dim)
    w = sample_sequences_into(memory, batch, np.random.default_rng(0))
    np.testing.assert_allclose(batch.obs[0], srl.encode(memory.frames[w.slots[0]]), rtol=1e-4, atol=1e-4)
    summary = evaluate(run, episodes=1, picture=False, verbose=False)  # the test phase reads latents too
    assert summary["episodes"] == 1


def test_the_memory_settings_change_a_runs_config_hash_only_with_memory():
    from agents.study.run_record import config_hash
    from agents.training.config_io import to_yaml_dict

    plain = to_yaml_dict(make(task="DynNav-MovingTarget-v1"))
    older = {**plain, "dqn": {k: v for k, v in plain["dqn"].items()
                              if k not in ("recurrent", "recurrent_size", "sequence_length", "burn_in")}}
    assert config_hash(older) == config_hash(plain)  # a run recorded before the settings existed
    gru = to_yaml_dict(make(task="DynNav-MovingTarget-v1", recurrent="gru"))
    longer = to_yaml_dict(make(task="DynNav-MovingTarget-v1", recurrent="gru", sequence_length=40))
    assert len({config_hash(plain), config_hash(gru), config_hash(longer)}) == 3
