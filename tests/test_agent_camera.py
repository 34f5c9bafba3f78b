"""Camera runs: the auto-encoder on the thesis's Algorithm 2 schedule, end to end on world 5.5a/5.5c.

Small settings: the auto-encoder updates after episodes 2 and 4, with 2 iterations of 2
batches; the runs share this process's camera renderer with the other camera tests."""

import csv
import shutil

import numpy as np
import pytest
import torch

import agents.training.loop as dqn
from agents.training import checkpoint as ckpt
from agents.training.config import Config
from agents.training.config_io import make, replace
from agents.training.envs import frame_key
from agents.training.test_phase import evaluate
from agents.training.policy_loading import load_policy
from agents.srl.state_representation import SRLSettings

CASES = {
    "rgb": dict(task="DynNav-VisualStaticTarget-v1", camera_frames=1),
    "stack+lasers": dict(task="DynNav-VisualMovingTargets-v1", camera_frames=2, camera_state=("lasers",)),
}


def small(tmp_path, **overrides) -> Config:
    values = dict(episodes=6, ae_first_update=2, ae_update_every=2, ae_updates=2, ae_iterations=2, ae_batches=2,
                  ae_batch_size=16, ae_pictures_every=2, learning_starts=32, batch_size=16, hidden_sizes=(16,),
                  buffer_size=2000, checkpoint_every=1, random_episodes=2, epsilon_decay_episodes=2,
                  runs_dir=str(tmp_path / "runs"), progress=False, eval_after_training=False, seed=5)
    values.update(overrides)
    return make(**values).validate()


def encoder_fingerprint(srl) -> float:
    return float(sum(p.detach().double().sum() for p in srl.model.encoder.parameters()))


@pytest.fixture(scope="module", params=list(CASES))
def camera_run(request, tmp_path_factory):
    """A small camera training run, with the encoder's weights noted after every episode."""
    config = small(tmp_path_factory.mktemp(request.param), **CASES[request.param])
    after_episode = {}
    original = dqn.update_state_representation

    def spy(srl, memory, rng, episodes_done, cfg, run_dir):
        original(srl, memory, rng, episodes_done, cfg, run_dir)
        after_episode[episodes_done] = (encoder_fingerprint(srl), srl.updates_done)
        spy.srl, spy.memory = srl, memory

    dqn.update_state_representation = spy
    try:
        run_dir = dqn.train(config)
    finally:
        dqn.update_state_representation = original
    return config, run_dir, after_episode, spy.srl, spy.memory


def metric_rows(run_dir):
    with open(run_dir / "metrics.csv", newline="") as f:
        return list(csv.DictReader(f))


def test_phases_switch_at_the_configured_episodes(camera_run):
    config, run_dir, after_episode, srl, _ = camera_run
    rows = metric_rows(run_dir)
    assert len(rows) == 6
    for r in rows[:2]:  # before the first update: random actions, no Q-network training
        assert float(r["epsilon"]) == 1.0 and r["loss"] == ""
    for r in rows[2:]:
        assert float(r["epsilon"]) < 1.0 and r["loss"] != ""
    with open(run_dir / "srl_loss.csv", newline="") as f:
        updates = list(csv.DictReader(f))
    assert [(int(u["update"]), int(u["episode"])) for u in updates] == [(1, 2), (1, 2), (2, 4), (2, 4)]
    assert [after_episode[e][1] for e in range(1, 7)] == [0, 1, 1, 2, 2, 2]
    for name in ("srl_loss.png", "reconstructions/episode_00002.png", "reconstructions/episode_00006.png"):
        assert (run_dir / name).is_file(), name


def test_encoder_is_frozen_between_updates(camera_run):
    _, _, after_episode, _, _ = camera_run
    w = {e: after_episode[e][0] for e in range(1, 7)}
    assert w[2] != w[1] and w[4] != w[3]  # the updates change it
    assert w[3] == w[2] and w[5] == w[4] == w[6]  # the Q-network's training does not


def test_replayed_latents_come_from_the_current_encoder(camera_run):
    _, _, _, srl, memory = camera_run
    n = memory.size
    # frames encoded one at a time while acting and in batches after an update differ in float
    # rounding only (about 1e-4 after standardising); a stale encoder's latents differ by O(1)
    np.testing.assert_allclose(memory.latents[:n], srl.encode(memory.frames[:n]), rtol=0, atol=3e-3)


def test_checkpoint_restores_the_auto_encoder_with_the_q_network(camera_run):
    config, run_dir, _, srl, memory = camera_run
    state = ckpt.load(run_dir)
    assert state["episode"] == 6 and state["srl"]["updates_done"] == 2
    policy = load_policy(run_dir)
    env, features = policy.env, policy.features
    for mine, saved in zip(features.srl.model.state_dict().values(), srl.model.state_dict().values()):
        torch.testing.assert_close(mine, saved, rtol=0, atol=0)
    obs, _ = env.reset(seed=0)
    x = features(obs)
    settings = SRLSettings.from_config(config)
    assert x.shape == (settings.spec.latent + (16 if config.camera.camera_state else 0),)
    frame = obs[frame_key(config.camera.camera_frames)]
    np.testing.assert_allclose(x[: settings.spec.latent], srl.encode(frame), rtol=1e-5, atol=1e-5)
    assert policy.q_values(obs).shape == (3,)
    env.close()


def test_resume_continues_with_the_restored_auto_encoder(camera_run, tmp_path):
    config, run_dir, _, _, _ = camera_run
    copy = tmp_path / "run"
    shutil.copytree(run_dir, copy)
    resumed = dqn.train(replace(config, episodes=7, resume=str(copy)))
    state = ckpt.load(resumed)
    assert state["episode"] == 7 and state["srl"]["updates_done"] == 2
    assert len(metric_rows(resumed)) == 7


def test_test_phase_writes_latent_maps(camera_run):
    _, run_dir, _, _, _ = camera_run
    summary = evaluate(run_dir, episodes=2, verbose=False)
    assert summary["episodes"] == 2
    for name in ("latent_pca.png", "latent_tsne.png", "latents.npz", "trajectories.png"):
        assert (run_dir / name).is_file(), name
    data = np.load(run_dir / "latents.npz")
    assert len(data["latents"]) == len(data["rewards"]) == len(data["targets"]) > 0


def test_recording_of_a_camera_checkpoint_shows_latent_and_reconstruction(camera_run, tmp_path):
    from agents.training.record import Args, main

    from test_recording import read_back

    config, run_dir, _, srl, _ = camera_run
    out = tmp_path / "camera.rrd"
    main(Args(checkpoint=run_dir, episodes=1, out=out))
    data = read_back(out)
    for entity in ("/agent/q_values", "/agent/latent", "/agent/reconstruction", "/world/robot/camera/image"):
        assert entity in data, entity
    latent_rows = sum(rb.num_rows for rb in data["/agent/latent"])
    image_rows = sum(rb.num_rows for rb in data["/agent/reconstruction"])
    assert latent_rows == image_rows > 0


def test_camera_settings_errors_name_the_field(tmp_path):
    with pytest.raises(ValueError, match="camera_state selects state parts"):
        small(tmp_path, task="DynNav-VisualStaticTarget-v1", camera_state=("lasers",))
    with pytest.raises(ValueError, match="camera_frames must not be negative"):
        small(tmp_path, task="DynNav-VisualStaticTarget-v1", camera_frames=-1)
    with pytest.raises(ValueError, match=r"unknown state part 'laser'; valid parts: lasers, robot_xy, target_xy"):
        dqn.train(small(tmp_path, task="DynNav-VisualStaticTarget-v1", camera_frames=1, camera_state=("laser",)))
    assert not (tmp_path / "runs").exists()  # no run directory for a run that never started
    with pytest.raises(ValueError, match="apply to dynnav tasks only"):
        dqn.train(small(tmp_path, task="CartPole-v1", camera_frames=1))


def test_pixel_agent_trains_its_encoder_from_the_td_loss(tmp_path):
    """camera_input pixels: a conv Q-network on the frames (+ state parts) learns from the first
    episodes, with no auto-encoder; its checkpoint tests and resumes like any other."""
    from agents.core.networks import PixelQNetwork

    config = small(tmp_path, task="DynNav-VisualMovingTargets-v1", camera_frames=2, camera_input="pixels",
                   camera_state=("lasers",), episodes=3, random_episodes=0, learning_starts=16, buffer_size=500,
                   checkpoint_every=3)
    run_dir = dqn.train(config)
    rows = metric_rows(run_dir)
    assert all(r["loss"] != "" for r in rows[1:]) and float(rows[0]["epsilon"]) < 1.0
    assert not (run_dir / "srl_loss.csv").exists()
    state = ckpt.load(run_dir)
    assert state["input_shapes"] == [[32, 32, 2], [16]] and state["srl"] is None
    torch.manual_seed(config.seed)  # the initial weights, as the run built them
    before = PixelQNetwork((32, 32, 2), 16, 3, shift=config.camera.pixel_shift).state_dict()
    policy = load_policy(run_dir)
    assert isinstance(policy.q_network, PixelQNetwork)
    trained = policy.q_network.state_dict()
    assert any(not torch.equal(trained[k], before[k]) for k in before if k.startswith("encoder"))
    policy.env.close()
    assert evaluate(run_dir, episodes=1, picture=False, verbose=False)["episodes"] == 1
    resumed = dqn.train(replace(config, episodes=4, resume=str(run_dir)))
    assert ckpt.load(resumed)["episode"] == 4
