"""The pretrained navigators: every model under pretrained/ still drives as its card says, the
models fit their budget and the docs' table, and a run exported and loaded by name acts as the
run itself (``--eval``, recordings and ``agents.pretrained.load``)."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import torch

from agents.dqn import main as dqn_main
from agents.pretrained import available, card, load
from agents.pretrained.catalogue import CELLS
from agents.pretrained.cli import BUDGET_BYTES, list_models, total_size
from agents.pretrained.export import export
from agents.srl.state_representation import SRLSettings, StateRepresentation
from agents.study.table import read_table
from agents.training import pretrained_files as files
from agents.training.config_io import make
from agents.training.loop import train
from agents.training.policy_loading import load_policy
from agents.training.record import Args, main as record_main
from agents.training.test_phase import evaluate, run_episodes
from dynnav_tasks.task_options import parse_task_options

ROOT = Path(__file__).resolve().parents[1]
REPOSITORY_MODELS = available(ROOT / "pretrained")


def _card_tests() -> list[tuple[str, str]]:
    """(model, tested-on options) of every test on the models' cards: one per model, one per
    difficulty for a procedural model."""
    out = []
    for model in REPOSITORY_MODELS:
        facts = card.read(ROOT / "pretrained" / model)
        out += [(model, options) for options in facts.get("tests", {"": None})]
    return out


@pytest.mark.parametrize("name, options", _card_tests(), ids=lambda v: v or "")
def test_pretrained_model_keeps_its_success(name, options):
    """Replayed on its card's first test episodes, the model succeeds within 10 points of the card
    (a procedural model: in each difficulty's held-out worlds, within 10 points of that test)."""
    facts = card.read(ROOT / "pretrained" / name)
    test = facts["tests"][options] if options else facts["test"]
    episodes = min(card.CHECK_EPISODES, test["episodes"])
    with load(name, root=ROOT / "pretrained", **(parse_task_options(options) if options else {})) as navigator:
        assert (navigator.policy.config.name, navigator.policy.config.seed) == (facts["row"], facts["seed"])
        records = run_episodes(navigator.policy, episodes, test["seed"])
    success = np.mean([r["outcome"] == "success" for r in records])
    assert abs(success - test["success"]) <= 0.10, (
        f"pretrained:{name} {options} succeeds in {success:.0%} of {episodes} test episodes; its card says "
        f"{test['success']:.0%} (and {test['success_first_check']:.0%} on these {episodes})")


def test_the_models_fit_their_budget_and_the_docs_table():
    """All models together weigh at most 10 MB, each is a cell of the catalogue trained as its run,
    and docs/pretrained.md shows the table of their cards."""
    assert total_size(ROOT / "pretrained") <= BUDGET_BYTES
    for name in REPOSITORY_MODELS:
        facts = card.read(ROOT / "pretrained" / name)
        assert name in CELLS and (facts["row"], facts["seed"]) == (CELLS[name].row, CELLS[name].seed), name
    page = (ROOT / "docs" / "pretrained.md").read_text(encoding="utf-8")
    shown = re.search(r"<!-- models -->\n(.*?)\n<!-- end models -->", page, re.DOTALL)
    assert shown, "docs/pretrained.md lacks the <!-- models --> ... <!-- end models --> block"
    assert shown[1].strip() == card.models_table(ROOT / "pretrained").strip(), (
        "docs/pretrained.md's table differs from the cards: paste `python -m agents.pretrained list --markdown`")


def test_the_catalogue_names_runs_of_the_table():
    """Each cell's row has a config, and its seed is in the run table with the success the catalogue says."""
    rows = {(r["experiment"], r["seed"], r["tested_on"]): r for r in read_table()}
    for cell, source in CELLS.items():
        assert source.config.is_file(), f"{cell}: {source.config} does not exist"
        run = rows.get((source.row, source.seed, source.tested_on))
        assert run is not None, f"{cell}: the run table has no run of {source.row} seed {source.seed}"
        assert run["success_rate"] == pytest.approx(source.success), cell


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    """A run of a few episodes (the round trip needs weights, not skill)."""
    folder = tmp_path_factory.mktemp("tiny")
    config = make(task="DynNav-MovingTarget-v1", reward_mode="distance", episodes=3, learning_starts=64,
                  batch_size=32, hidden_sizes=(32, 32), buffer_size=5000, checkpoint_every=3, name="tiny-run",
                  epsilon_decay_episodes=2, runs_dir=str(folder / "runs"), progress=False,
                  eval_after_training=False, seed=3).validate()
    return train(config)


def test_export_and_load_round_trip(tiny_run, tmp_path, monkeypatch):
    """The exported model is the run's policy: same Q-values, same test results by name
    (``--eval``, ``agents.pretrained.load``), recordable, listed; its folder holds safetensors,
    the resolved config and the card."""
    models = tmp_path / "models"
    facts = export(tiny_run, "tiny", episodes=3, root=models, verbose=False)
    assert sorted(p.name for p in (models / "tiny").iterdir()) == ["card.md", "config.yaml", "model.safetensors"]
    assert card.read(models / "tiny") == facts
    assert (facts["row"], facts["seed"], facts["trained_episodes"]) == ("tiny-run", 3, 3)
    original = evaluate(tiny_run, episodes=3, picture=False, verbose=False)
    assert facts["test"]["success"] == original["success_rate"]
    assert facts["test"]["collision"] == original["collision_rate"]

    source = load_policy(tiny_run)
    with load("tiny", root=models) as navigator:
        obs, _ = navigator.env.reset(seed=7)
        expected = source.q_values(obs)
        np.testing.assert_array_equal(navigator.q_values(obs), expected)
        assert navigator.act(obs) == int(np.argmax(expected))
        assert navigator.card["cell"] == "tiny"
    source.env.close()

    monkeypatch.setenv(files.ROOT_VARIABLE, str(models))
    monkeypatch.chdir(tmp_path)
    dqn_main(["--eval", "--checkpoint", "pretrained:tiny", "--eval-episodes", "3", "--no-eval-picture"])
    result = json.loads((tmp_path / "runs" / "pretrained-tiny" / "eval.json").read_text())
    assert result["summary"]["success_rate"] == original["success_rate"]
    assert [e["steps"] for e in result["episodes"]] == [e["steps"] for e in json.loads(
        (tiny_run / "eval.json").read_text())["episodes"]]
    record_main(Args(checkpoint="pretrained:tiny", episodes=1, out=tmp_path / "tiny.rrd"))
    assert (tmp_path / "tiny.rrd").stat().st_size > 0
    assert any(line.startswith("pretrained:tiny ") for line in list_models(models))


def test_a_model_with_memory_remembers_within_an_episode_and_forgets_at_reset(tmp_path):
    """An exported recurrent run keeps its GRU: the navigator's Q-values for one observation change
    as it remembers, ``reset`` starts it again from the first step's values, and they are the run's."""
    config = make(task="DynNav-MovingTarget-v1", episodes=3, recurrent="gru", recurrent_size=16, hidden_sizes=(32,),
                  sequence_length=8, burn_in=4, batch_size=8, learning_starts=50, name="tiny-gru",
                  runs_dir=str(tmp_path / "runs"), progress=False, eval_after_training=False, seed=2).validate()
    run = train(config)
    models = tmp_path / "models"
    export(run, "tiny-gru", episodes=2, root=models, verbose=False)
    source = load_policy(run)
    with load("tiny-gru", root=models) as navigator:
        obs, _ = navigator.env.reset(seed=5)
        source.reset()
        navigator.reset()
        first = navigator.q_values(obs)
        np.testing.assert_array_equal(first, source.q_values(obs))
        assert not np.allclose(navigator.q_values(obs), first)  # the same observation, one step later
        navigator.reset()
        np.testing.assert_array_equal(navigator.q_values(obs), first)
    source.env.close()


def test_the_encoder_alone_encodes_as_the_trained_auto_encoder(tmp_path):
    """A camera model keeps the encoder (at half precision) and the latent standardisation: its
    latents are the trained ones to float16's precision; it cannot reconstruct, and a model of
    another size is refused."""
    settings = SRLSettings.from_config(make(task="DynNav-VisualStaticTarget-v1", camera_frames=1))
    trained = StateRepresentation(settings, seed=1)
    trained.mean[:], trained.std[:] = np.linspace(-1, 1, trained.latent_dim), np.linspace(0.5, 2, trained.latent_dim)
    trained.updates_done = 1
    files.write_model(tmp_path, {"bias": torch.zeros(3)}, {}, 1, autoencoder=trained.encoder_weights())
    weights, _ = files.read_tensors(tmp_path / files.AUTOENCODER)
    assert {v.dtype for k, v in weights.items() if k.startswith("encoder.")} == {files.ENCODER_DTYPE}
    assert not any(k.startswith("decoder.") for k in weights)
    loaded = StateRepresentation(settings, seed=2)
    loaded.load_encoder_weights(weights)
    frames = np.random.default_rng(0).integers(0, 256, (8, 32, 32, 3), dtype=np.uint8)
    np.testing.assert_allclose(loaded.encode(frames), trained.encode(frames), atol=0.05)
    assert loaded.trained and not loaded.can_reconstruct
    with pytest.raises(ValueError, match="without its decoder"):
        loaded.reconstruct(frames)
    stacked = SRLSettings.from_config(make(task="DynNav-VisualMovingTargets-v1", camera_frames=4))
    with pytest.raises(ValueError, match="do not fit"):
        StateRepresentation(stacked, seed=1).load_encoder_weights(weights)


def test_unknown_names_are_clear_errors(tiny_run, tmp_path, monkeypatch):
    """An unknown model lists the models there are; a bad name or a run that is not the cell's is refused."""
    models = tmp_path / "models"
    export(tiny_run, "tiny", episodes=1, root=models, verbose=False)
    with pytest.raises(ValueError, match=r"no pretrained model 'nope'.*the models there: tiny"):
        load("nope", root=models)
    monkeypatch.setenv(files.ROOT_VARIABLE, str(models))
    with pytest.raises(SystemExit, match=r"no pretrained model '5\.3'.*tiny"):
        dqn_main(["--eval", "--checkpoint", "pretrained:5.3"])
    with pytest.raises(ValueError, match="cannot name a pretrained model"):
        load("../tiny", root=models)
    with pytest.raises(ValueError, match=r"cell '5\.3' is '5\.3-g0\.1-two-states-ddqn-lr-decay-12000ep' seed 4"):
        export(tiny_run, "5.3", episodes=1, root=models, verbose=False)
    assert available(models) == ["tiny"]


def test_a_procedural_model_is_tested_per_difficulty_and_plays_a_world_of_ones_own(tmp_path):
    """A navigator of every difficulty: its card tests it in each difficulty's held-out worlds, and
    loaded by name it plays any procedural world, one a user made included."""
    from agents.imitation.config import ImitationConfig
    from agents.imitation.dagger import train as imitate
    from dynnav_tasks.motion import Static
    from dynnav_tasks.world import Arena, Obstacles, StartArea, World

    student = tmp_path / "student.yaml"
    student.write_text(f"base: {ROOT / 'configs/procedural/generalist.yaml'}\n"
                       "dqn: {hidden_sizes: [32]}\ntest: {eval_after_training: false}\n")
    run = imitate(ImitationConfig(student=str(student), teacher_episodes=2, rounds=0, epochs=2, workers=0,
                                  runs_dir=str(tmp_path / "runs"), progress=False, dataset=False))
    facts = export(run, "procedural-tiny", episodes=2, root=tmp_path / "models", verbose=False)
    assert list(facts["tests"]) == [f"difficulty={d},split=test" for d in ("easy", "medium", "hard")]
    assert facts["test"]["success"] == pytest.approx(np.mean([t["success"] for t in facts["tests"].values()]))
    assert "difficulty=hard,split=test" in (tmp_path / "models" / "procedural-tiny" / "card.md").read_text()
    mine = World(targets=(Static((5.0, 2.0)),), obstacles=(Obstacles((0.25, 0.25), Static((3.0, 2.0))),),
                 arena=Arena((0.0, 7.0), (0.0, 4.0)), start=StartArea((0.9, 1.1), (1.9, 2.1)))
    with load("procedural-tiny", root=tmp_path / "models") as navigator:
        obs, _ = navigator.env.reset(seed=0, options={"world": mine})
        assert navigator.env.unwrapped.world is mine and obs.shape == (42,)
        navigator.reset()
        obs, *_ = navigator.env.step(navigator.act(obs))
