"""Rerun recordings: read the file back and check what a viewer would show."""

import dataclasses

import numpy as np
import pytest
import rerun.chunk as rc

from agents.training.record import Args, main, record_episodes
from dynnav_tasks.viz.recording import Recorder


def read_back(path):
    """entity path -> list of record batches, and the row count per entity on 'step'."""
    store = rc.RrdReader(str(path)).store()
    batches = {}
    for chunk in store.stream().to_chunks():
        batches.setdefault(chunk.entity_path, []).append(chunk.to_record_batch())
    return batches


def column(batches, name):
    values = []
    for rb in batches:
        if name in rb.schema.names:
            values.extend(rb.column(rb.schema.names.index(name)).to_pylist())
    return values


def record(make_env, tmp_path, task, obs_mode, episodes=2):
    env = make_env(task, obs_mode=obs_mode)
    path = tmp_path / "run.rrd"
    with Recorder(path) as recorder:
        results = record_episodes(env, recorder, episodes=episodes, seed=3)
    return path, results


def test_state_task_recording(make_env, tmp_path):
    path, results = record(make_env, tmp_path, "DynNav-MovingObstacles-v1", "state")
    lengths = [n for _, n in results]
    data = read_back(path)
    for entity in ("/world", "/world/walls", "/world/robot", "/world/robot/body", "/world/robot/lasers",
                   "/world/obstacles", "/world/target", "/world/robot/camera", "/agent/action",
                   "/agent/reward", "/episode/outcome"):
        assert entity in data, entity
    assert column(data["/world/walls"], "step") == [0]  # one world: its walls logged once
    # one robot pose per reset and per step, on the step timeline
    steps = column(data["/world/robot"], "step")
    assert len(steps) == sum(n + 1 for n in lengths)
    assert steps == sorted(steps) and len(set(steps)) == len(steps)
    assert len(column(data["/agent/reward"], "step")) == sum(lengths)
    # 16 laser segments per logged step, each a 2-point strip from the laser ring
    strips = column(data["/world/robot/lasers"], "LineStrips3D:strips")
    assert len(strips) == sum(n + 1 for n in lengths)
    assert all(len(s) == 16 and all(len(seg) == 2 for seg in s) for s in strips)
    # two moving obstacles (5.3) in every obstacle frame
    assert all(len(c) == 2 for c in column(data["/world/obstacles"], "Boxes3D:centers"))
    outcomes = [row[0] for row in column(data["/episode/outcome"], "TextLog:text")]
    assert outcomes == [f"episode {i}: {o}" for i, (o, _) in enumerate(results)]
    assert "/world/robot/camera/image" not in data  # a state task renders no frames


def latest_at(batches, step):
    """The row a viewer shows at ``step`` on the step timeline: the last one logged at or before it
    (rows at one step in the order they were logged), as {column: value}."""
    rows = []
    for rb in batches:
        names = [n for n in rb.schema.names if n != "log_time"]  # wall-clock times, not needed here
        for values in zip(*(rb.column(n).to_pylist() for n in names)):
            row = dict(zip(names, values))
            if row["step"] <= step:
                rows.append(row)
    return max(rows, key=lambda row: (row["step"], row["rerun.controls.RowId"]))


def sorted_rows(points):
    return sorted(tuple(round(float(v), 3) for v in p) for p in points)


def test_generated_worlds_are_relogged_every_episode(make_env, tmp_path):
    env = make_env("DynNav-Procedural-v1", difficulty="medium")
    path, worlds, targets, starts = tmp_path / "procedural.rrd", [], [], []
    with Recorder(path) as recorder:
        for seed, options in ((0, None), (1, None), (2, "no blocks")):
            if options:  # the second world without its blocks: the recording must drop them
                world = worlds[1]
                options = {"world": dataclasses.replace(world, obstacles=tuple(g for g in world.obstacles if g.moving))}
            env.reset(seed=seed, options=options)
            recorder.start_episode(env)
            starts.append(recorder.step)
            worlds.append(env.unwrapped.world)
            targets.append(env.unwrapped.snapshot.target_xy)
            for _ in range(3):
                _, reward, terminated, truncated, info = env.step(0)
                recorder.log_step(env, 0, reward)
                if terminated or truncated:
                    break
    assert worlds[0].arena != worlds[1].arena and worlds[0].moving_obstacle_count != worlds[1].moving_obstacle_count
    data = read_back(path)
    for world, target, step in zip(worlds, targets, starts):
        walls = latest_at(data["/world/walls"], step)["Boxes3D:centers"]
        assert sorted_rows(w[:2] for w in walls) == sorted_rows(c for c, _ in world.arena.walls().values())
        blocks = [g.motion.at for g in world.obstacles if not g.moving]
        shown = latest_at(data["/world/blocks"], step)
        assert sorted_rows(c[:2] for c in shown.get("Boxes3D:centers") or []) == sorted_rows(blocks)
        assert ("Clear:is_recursive" in shown) == (not blocks)
        boxes = latest_at(data["/world/obstacles"], step)["Boxes3D:centers"]
        assert len(boxes) == world.moving_obstacle_count
        disc = latest_at(data["/world/target"], step)["Cylinders3D:centers"][0]
        assert np.allclose(disc[:2], target, atol=1e-5)
    assert column(data["/world/walls"], "step") == starts  # once per world


def test_camera_world_recording(make_env, tmp_path):
    path, results = record(make_env, tmp_path, "DynNav-VisualStaticTarget-v1", "rgb+state", episodes=2)
    data = read_back(path)
    formats = [row[0] for row in column(data["/world/robot/camera/image"], "Image:format")]
    assert len(formats) == sum(n + 1 for _, n in results)
    assert all(f["width"] == 32 and f["height"] == 32 for f in formats)
    buffers = [row[0] for row in column(data["/world/robot/camera/image"], "Image:buffer")]
    assert all(len(b) == 32 * 32 * 3 for b in buffers)
    assert len({bytes(b) for b in buffers}) > 1  # the frames change


def test_agent_outputs_are_recorded(make_env, tmp_path):
    env = make_env("DynNav-MovingTarget-v1")
    path = tmp_path / "agent.rrd"
    with Recorder(path) as recorder:
        env.reset(seed=0)
        recorder.start_episode(env)
        _, reward, *_ = env.step(0)
        recorder.log_step(env, action=0, reward=reward, q_values=[1.0, 2.0, 3.0], latent=np.arange(10),
                          reconstruction=np.zeros((32, 32, 3), np.uint8))
        recorder.log_training(0, ret=-3.5, loss=0.25, epsilon=0.8, success_rate=float("nan"))
    data = read_back(path)
    for entity in ("/agent/q_values", "/agent/latent", "/agent/reconstruction", "/training/ret",
                   "/training/loss", "/training/epsilon"):
        assert entity in data, entity
    assert "/training/success_rate" not in data  # not-a-number values are skipped


def test_missing_folder_is_a_clear_error_before_any_work(tmp_path, capsys):
    with pytest.raises(ValueError, match="does not exist"):
        Recorder(tmp_path / "missing" / "run.rrd")
    with pytest.raises(SystemExit, match="folder .* does not exist"):
        main(Args(task="DynNav-MovingTarget-v1", out=tmp_path / "missing" / "run.rrd"))


def test_unwritable_folder_is_a_clear_error():
    # /proc takes no new files, even for root (a chmod'ed folder would not stop root)
    with pytest.raises(ValueError, match="not writable"):
        Recorder("/proc/run.rrd")


def test_folder_instead_of_file(tmp_path):
    with pytest.raises(ValueError, match="is a folder"):
        Recorder(tmp_path)


def test_a_crowd_recording_shows_the_pedestrians_and_their_goals(make_env, tmp_path):
    """Every logged step of DynNav-Crowd-v1 shows its 5 pedestrians as cylinders where the
    snapshot has them, each with a line to the goal it heads for."""
    env = make_env("DynNav-Crowd-v1", obs_mode="state")
    path = tmp_path / "crowd.rrd"
    with Recorder(path) as recorder:
        results = record_episodes(env, recorder, episodes=1, seed=3)
    data = read_back(path)
    centers = column(data["/world/pedestrians"], "Cylinders3D:centers")
    goals = column(data["/world/pedestrian_goals"], "LineStrips3D:strips")
    assert len(centers) == len(goals) == results[0][1] + 1  # the reset and every step
    assert all(len(c) == 5 for c in centers) and all(len(g) == 5 for g in goals)
    last = env.unwrapped.snapshot.human_xy
    assert sorted_rows([c[:2] for c in centers[-1]]) == sorted_rows(last)
    assert sorted_rows([s[1][:2] for s in goals[-1]]) == sorted_rows(env.unwrapped.pedestrian_goals)
