"""Config files as differences: ``base:`` chains, their errors, and the files in configs/."""

import dataclasses
from pathlib import Path

import pytest
import yaml

from agents.training.config_io import config_from_dict, load_yaml, parse_args, resolve_yaml, to_yaml_dict

CONFIGS = Path(__file__).resolve().parents[1] / "configs"
STUDY = sorted((CONFIGS / "study").glob("*.yaml"))


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def settings(path: Path) -> dict:
    """Every resolved setting of a config file but the two a file never inherits."""
    values = to_yaml_dict(load_yaml(path))
    values.pop("name"), values.pop("description")
    return values


def test_a_chain_of_bases_merges_groups_and_env_mappings_key_by_key(tmp_path):
    write(tmp_path / "root.yaml", "name: root\ndescription: the root\nepisodes: 10\ntask: CartPole-v1\n"
                                  "dqn: {batch_size: 32, gamma: 0.9, hidden_sizes: [64, 64]}\n"
                                  "env:\n  reward_params: {distance_gamma: 0.1}\n"
                                  "  task_kwargs: {turn_forward_step: 0.05}\n")
    write(tmp_path / "sub" / "mid.yaml", "base: ../root.yaml\ndqn: {batch_size: 64}\n"
                                         "env:\n  reward_params: {collision_reward: -100.0}\n")
    child = write(tmp_path / "sub" / "leaf.yaml", "base: mid.yaml\nlearning_rate: 0.01\nhidden_sizes: [16]\n"
                                                  "reward_params: {distance_gamma: 0.3}\n")
    c = load_yaml(child)
    assert (c.episodes, c.task) == (10, "CartPole-v1")  # top-level fields from the root
    assert (c.dqn.batch_size, c.dqn.gamma) == (64, 0.9)  # a group merged key by key
    assert c.dqn.hidden_sizes == (16,)  # a list replaced whole (the flat layout works in a child too)
    assert c.schedule.learning_rate == 0.01
    assert c.env.reward_params == {"distance_gamma": 0.3, "collision_reward": -100.0}
    assert c.env.task_kwargs == {"turn_forward_step": 0.05}
    assert (c.name, c.description) == ("leaf", "")  # never inherited: the stem, and no description
    assert "base" not in resolve_yaml(child)


def test_name_is_the_files_own_or_its_stem(tmp_path):
    write(tmp_path / "base.yaml", "name: base_name\ndescription: a base\n")
    assert load_yaml(write(tmp_path / "5.3-g0.1.yaml", "base: base.yaml\nepisodes: 3\n")).name == "5.3-g0.1"
    own = load_yaml(write(tmp_path / "own.yaml", "base: base.yaml\nname: mine\ndescription: one line\n"))
    assert (own.name, own.description) == ("mine", "one line")
    assert load_yaml(write(tmp_path / "flat.yaml", "episodes: 3\n")).name == "flat"
    assert parse_args(["--config", str(tmp_path / "own.yaml"), "--name", "flag"]).name == "flag"


def test_a_cycle_of_bases_is_an_error_naming_the_files(tmp_path):
    a = write(tmp_path / "a.yaml", "base: b.yaml\nepisodes: 3\n")
    write(tmp_path / "b.yaml", "base: a.yaml\nepisodes: 4\n")
    with pytest.raises(ValueError, match=r"cycle of bases: .*a\.yaml -> .*b\.yaml -> .*a\.yaml"):
        load_yaml(a)
    itself = write(tmp_path / "self.yaml", "base: self.yaml\n")
    with pytest.raises(ValueError, match=r"cycle of bases: .*self\.yaml -> .*self\.yaml"):
        parse_args(["--config", str(itself)])


def test_a_missing_or_unusable_base_is_an_error_naming_both_files(tmp_path):
    child = write(tmp_path / "child.yaml", "base: nowhere.yaml\n")
    with pytest.raises(ValueError, match=r"nowhere\.yaml' \(the base of '.*child\.yaml'\) does not exist; "
                                         r"base: is a path relative to the folder"):
        load_yaml(child)
    write(tmp_path / "list.yaml", "- 1\n- 2\n")
    with pytest.raises(ValueError, match=r"list\.yaml' \(the base of '.*child\.yaml'\): expected a mapping"):
        load_yaml(write(tmp_path / "child.yaml", "base: list.yaml\n"))
    with pytest.raises(ValueError, match=r"child\.yaml': base must be the path of a YAML file"):
        load_yaml(write(tmp_path / "child.yaml", "base: [a.yaml]\n"))
    with pytest.raises(ValueError, match="works in a YAML file read by path"):
        config_from_dict({"base": "a.yaml", "episodes": 3})


def test_an_unknown_key_is_an_error_naming_the_file_that_has_it(tmp_path):
    write(tmp_path / "base.yaml", "episodes: 3\n")
    child = write(tmp_path / "child.yaml", "base: base.yaml\ndqn: {lerning_rate: 0.01}\n")
    with pytest.raises(ValueError, match=r"child\.yaml: unknown field 'dqn\.lerning_rate'"):
        load_yaml(child)
    write(tmp_path / "base.yaml", "episods: 3\n")
    with pytest.raises(ValueError, match=r"base\.yaml: unknown field 'episods'.*'episodes'"):
        load_yaml(write(tmp_path / "child.yaml", "base: base.yaml\n"))
    with pytest.raises(ValueError, match=r"child\.yaml: field 'episodes' expects int"):
        load_yaml(write(tmp_path / "child.yaml", "base: base.yaml\nepisodes: many\n"))


def test_a_description_is_one_line():
    with pytest.raises(ValueError, match="description must be one line"):
        parse_args(["--description", "two\nlines"])


def test_a_run_writes_its_fully_resolved_config(tmp_path):
    from agents.training.loop import train

    write(tmp_path / "base.yaml", "description: tiny CartPole runs\ntask: CartPole-v1\nepisodes: 2\n"
                                  "dqn: {learning_starts: 16, batch_size: 8, hidden_sizes: [8]}\n"
                                  "run: {progress: false}\ntest: {eval_after_training: false}\n")
    child = write(tmp_path / "tiny-lr.yaml", "base: base.yaml\ndescription: tiny, learning rate 0.01\n"
                                             "schedule: {learning_rate: 0.01}\n")
    config = parse_args(["--config", str(child), "--runs-dir", str(tmp_path / "runs")])
    run = train(config)
    saved = yaml.safe_load((run / "config.yaml").read_text())
    assert "base" not in saved
    assert (saved["name"], saved["description"]) == ("tiny-lr", "tiny, learning rate 0.01")
    assert saved["task"] == "CartPole-v1"
    assert (saved["schedule"]["learning_rate"], saved["dqn"]["batch_size"], saved["schedule"]["epsilon_start"]) == (
        0.01, 8, 0.8)  # the file's value, the base's, and a default
    assert load_yaml(run / "config.yaml") == dataclasses.replace(config, config=None)  # reads back the same


IMITATION = sorted((CONFIGS / "imitation").glob("*.yaml"))
"""agents.imitation's settings (each names a training config as its student)"""
ABLATIONS = sorted((CONFIGS / "imitation" / "ablations").glob("*.yaml"))
"""agents.imitation.ablation's settings"""


@pytest.mark.parametrize("path", sorted(set(CONFIGS.rglob("*.yaml")) - set((CONFIGS / "imitation").rglob("*.yaml"))),
                         ids=lambda p: str(p.relative_to(CONFIGS)))
def test_every_config_file_loads_and_validates(path):
    config = load_yaml(path).validate()
    assert config.description and "\n" not in config.description


@pytest.mark.parametrize("path", IMITATION, ids=lambda p: p.name)
def test_every_imitation_config_loads_and_names_a_valid_student(path):
    from agents.imitation.config import ImitationConfig, load_yaml as load_imitation

    assert yaml.safe_load(path.read_text())["description"]
    cfg = ImitationConfig(**load_imitation(path)).validate()
    load_yaml(cfg.student).validate()


def test_every_study_experiment_has_a_one_line_description_and_differs_from_its_base():
    assert len(STUDY) >= 23
    for path in STUDY:
        own = yaml.safe_load(path.read_text(encoding="utf-8"))
        assert isinstance(own.get("description"), str) and own["description"].strip(), path
        assert "\n" not in own["description"], path
        assert "name" not in own, f"{path}: the experiment's name is its file name"
        assert "base" in own, path
        assert settings(path) != settings(path.parent / own["base"]), f"{path} repeats its base"
    assert len({p.stem for p in STUDY}) == len(STUDY)


def test_the_study_configs_hold_the_study_settings():
    c52, c53 = load_yaml(CONFIGS / "study" / "5.2.yaml"), load_yaml(CONFIGS / "study" / "5.3.yaml")
    assert (c52.name, c52.task, c52.episodes, c52.schedule.learning_rate, c52.schedule.epsilon_decay_episodes) == (
        "5.2", "DynNav-MovingTarget-v1", 2000, 0.003, 1000)
    assert (c53.name, c53.task, c53.episodes, c53.schedule.learning_rate, c53.schedule.epsilon_decay_episodes) == (
        "5.3", "DynNav-MovingObstacles-v1", 4000, 0.001, 2000)
    for c in (c52, c53):
        assert (c.env.reward_mode, c.dqn.algorithm, c.dqn.gamma, c.dqn.batch_size, c.dqn.hidden_sizes,
                c.schedule.epsilon_start, c.schedule.epsilon_end) == (
            "distance", "dqn", 0.97, 128, (128, 128), 0.8, 0.05)
    variant = load_yaml(CONFIGS / "study" / "5.5a-camera-g0.1-turn-forward-collision-100.yaml")
    assert variant.env.reward_params == {"distance_gamma": 0.1, "collision_reward": -100.0}
    assert (variant.env.task_kwargs, variant.camera.camera_frames, variant.schedule.random_episodes) == (
        {"turn_forward_step": 0.05}, 1, 400)


@pytest.mark.parametrize("path", ABLATIONS, ids=lambda p: p.name)
def test_every_ablation_variant_makes_a_valid_student(path):
    from agents.imitation.ablation import read_config, variant_config

    settings = read_config(path)
    base = load_yaml(CONFIGS / "procedural" / "generalist.yaml")
    for name, changes in settings["variants"].items():
        config = variant_config(base, settings["experiment"], name, changes, seed=1)
        assert config.name == f"{settings['experiment']}-{name}"
