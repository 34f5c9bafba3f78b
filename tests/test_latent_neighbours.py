"""agents.analysis.latent_neighbours: how an episode's last latent sits among the other episodes' latents."""

import json

import numpy as np
import pytest

from agents.analysis.latent_neighbours import load_run, main, neighbour_shares


def write_run(path, latents, episodes):
    path.mkdir(parents=True)
    np.savez_compressed(path / "latents.npz", latents=np.asarray(latents, dtype=np.float32),
                        targets=np.zeros(len(latents), dtype=np.int64), rewards=np.zeros(len(latents)))
    (path / "eval.json").write_text(json.dumps({"episodes": episodes}))
    return path


# four episodes of three steps, latents on a line: the two successes end near each other (10.0 and
# 10.1), far from every other step; the collision ends at 0.55, between ordinary steps (0.5 and 0.6);
# the timeout ends at 3.0
LATENTS = [[0.0], [0.5], [10.0],
           [0.1], [0.6], [10.1],
           [0.2], [0.4], [0.55],
           [0.3], [2.0], [3.0]]
EPISODES = [dict(steps=3, outcome="success"), dict(steps=3, outcome="success"),
            dict(steps=3, outcome="collision"), dict(steps=3, outcome="timeout")]


def test_last_steps_are_compared_with_other_episodes_steps_only(tmp_path):
    run = write_run(tmp_path / "run", LATENTS, EPISODES)
    latents, episode_of_step, outcomes = load_run(run)
    assert episode_of_step.tolist() == [0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3]
    shares = neighbour_shares(latents, episode_of_step, outcomes, k=1)
    # each success's nearest other-episode step is the other success's last step
    assert shares["success"] == dict(episodes=2, base=2 / 12, neighbours=1.0)
    # the collision's nearest other-episode steps are 0.5 and 0.6 (0.4 is its own episode's): none ends one
    assert shares["collision"] == dict(episodes=1, base=1 / 12, neighbours=0.0)
    # with k = 2 a success's neighbours are the other success (10.1 or 10.0) and 3.0, the timeout's end
    assert neighbour_shares(latents, episode_of_step, outcomes, k=2)["success"]["neighbours"] == 0.5


def test_the_command_prints_a_row_per_run_and_ending(tmp_path, capsys):
    run = write_run(tmp_path / "camera_5_5a" / "seed3" / "run", LATENTS, EPISODES)
    main([str(run), "--k", "1"])
    out = capsys.readouterr().out
    assert "| camera_5_5a/seed3 | success | 2 | 16.7% | 100.0% |" in out
    assert "| camera_5_5a/seed3 | collision | 1 | 8.3% | 0.0% |" in out


def test_files_of_different_test_phases_are_refused(tmp_path):
    run = write_run(tmp_path / "run", LATENTS[:-1], EPISODES)
    with pytest.raises(SystemExit, match="holds 11 steps but eval.json's episodes 12"):
        main([str(run)])
    with pytest.raises(SystemExit, match="latents.npz not found"):
        main([str(tmp_path / "nothing")])
