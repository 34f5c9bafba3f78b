"""The report's rows of scripted controllers beyond the planner: DWA in the study's worlds, and
the crowd table, navigators among pedestrians beside the classical robots and CrowdNav's numbers.

``docs/results/baselines.json`` holds what the controllers' ``--out`` writes (``python -m
dynnav_tasks.baselines.dwa ...`` and ``python -m dynnav_tasks.baselines.crowd_robot ...``), one
entry per controller, task and options: ``controller/task [options]``.

``dwa_section``: DWA (the laser scan alone, continuous drive) in each of the study's worlds it
was run in, beside the full-state planner's ceiling.

``crowd_section``: one row per experiment of the run table on ``DynNav-Crowd-v1`` (its own test, e.g.
``configs/crowd/circle-crossing.yaml``): the mean over seeds of the test's success, collision and
timeout rates and of its social metrics (``dynnav_tasks.crowd.metrics.aggregate``). Beside them,
the scripted robots' entries on that task and the success rates CrowdNav published for the same
geometry (``CROWDNAV``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

CROWD_TASK = "DynNav-Crowd-v1"
CROWDNAV = [("ORCA", 0.43), ("CADRL", 0.78), ("LSTM-RL", 0.95), ("SARL", 0.99)]
"""CrowdNav's success rates with 5 humans crossing a circle of radius 4 m, the robot invisible to
them (Chen et al. 2019, "Crowd-Robot Interaction", Table I; a holonomic robot at 1 m/s among
humans at 1 m/s, 500 test episodes)"""
CONTROLLERS = {"state_planner": "full-state planner (discrete drive, forecasts the pedestrians)",
               "state_planner_cv": "planner (discrete drive) forecasting the pedestrians at constant velocity "
                                   "(what the DQN reads)",
               "orca_robot": "ORCA robot", "social_force_robot": "social-force robot", "dwa": "DWA (laser scan)"}
"""the scripted controllers' names in the table"""
METRICS = [("success", "success"), ("collision", "collision"), ("timeout", "timeout"),
           ("human_collision_rate", "human collision"), ("discomfort_frequency", "discomfort"),
           ("personal_space_compliance", "personal space"), ("min_human_distance", "min. distance (m)"),
           ("time_to_goal", "time to goal (s)")]
"""the table's columns: key of a results entry (or of its ``social``) and header"""


def load_baselines(path: str | Path | None) -> dict[str, dict]:
    """The scripted robots' entries of a results file (empty if there is none)."""
    if path is None or not Path(path).is_file():
        return {}
    try:
        data = json.loads(Path(path).read_text())
        return {key: dict(v) for key, v in data.items() if isinstance(v, dict) and "success" in v}
    except (ValueError, AttributeError, TypeError) as err:
        raise ValueError(f"crowd baselines file {str(path)!r} is not what the baselines' --out writes: {err}")


def dwa_section(baselines: dict[str, dict], ceilings: dict[str, float]) -> list[str]:
    """The DWA section's Markdown lines: one row per study world (none without a DWA entry there)."""
    rows = sorted(k for k in baselines if k.startswith("dwa/") and not k.startswith(f"dwa/{CROWD_TASK}"))
    if not rows:
        return []
    lines = ["", "## The classical local planner", "",
             "DWA (`dynnav_tasks.baselines.dwa`: the dynamic window on the laser scan alone, on the continuous drive, "
             "docs/baselines.md) in the study's worlds, beside the planner that sees the full state; the procedural "
             "worlds' DWA row is in the generalist table above.", "",
             "| world | episodes | success | collision | timeout | SPL | planner ceiling |", "|---|---|---|---|---|---|---|"]
    for key in rows:
        e, task = baselines[key], key.split("/", 1)[1]
        ceiling = ceilings.get(task)
        lines.append(f"| {task} | {e.get('episodes', '-')} | {e['success']:.0%} | {e.get('collision', 0):.0%} | "
                     f"{e.get('timeout', 0):.0%} | {e.get('spl') or 0:.2f} | "
                     + ("-" if ceiling is None else f"{ceiling:.0%}") + " |")
    return lines


def _cell(key: str, value) -> str:
    if value is None:
        return "-"
    if key in ("min_human_distance", "time_to_goal"):
        return f"{value:.2f}" if key == "min_human_distance" else f"{value:.1f}"
    if key in ("discomfort_frequency", "personal_space_compliance"):
        return f"{value:.3f}"
    return f"{value:.1%}"


def _mean(values) -> float | None:
    values = [v for v in values if v is not None]
    return float(np.mean(values)) if values else None


def _learner(experiment: str) -> str:
    """How a crowd experiment learned, from its name: the imitation run's record ends in -dagger, the
    reinforcement learning on top of it in -finetune, the look-ahead Q-network's in -lookahead
    (configs/crowd/, configs/imitation/)."""
    if experiment.endswith("-lookahead"):
        return "Double DQN, one-step look-ahead"
    if experiment.endswith("-dagger"):
        return "behaviour cloning + DAgger"
    if experiment.endswith("-finetune"):
        return "Double DQN from the student, DQfD"
    return "DQN"


def _controller_name(controller: str) -> str:
    """The table's name of a scripted controller's entry (``state_planner_cv_margin0.2``: the planner
    forecasting the pedestrians at constant velocity and keeping 0.2 m of personal space)."""
    base, _, margin = controller.partition("_margin")
    name = CONTROLLERS.get(base, base.replace("_", " "))
    return f"{name}, {margin} m personal space" if margin else name


def crowd_section(rows: list[dict], baselines: dict[str, dict]) -> list[str]:
    """The crowd section's Markdown lines (none without a crowd run or a crowd baseline)."""
    runs: dict[str, list[dict]] = {}
    for r in rows:
        if r["task"] == CROWD_TASK and not r["tested_on"]:
            runs.setdefault(r["experiment"], []).append(r)
    robots = {k: v for k, v in baselines.items() if f"/{CROWD_TASK}" in k}
    if not runs and not robots:
        return []
    settings = {key.split("/", 1)[1].removeprefix(CROWD_TASK).strip() for key in robots}
    lines = ["", "## Crowds", "",
             f"Navigators among pedestrians on `{CROWD_TASK}` (docs/crowds.md): the learned ones (mean over seeds "
             "of each seed's greedy test) and the scripted robots (`dynnav_tasks.baselines.crowd_robot`, "
             "`dynnav_tasks.baselines.dwa`, on the continuous drive, from `docs/results/baselines.json`), "
             "with the social metrics of `dynnav_tasks.crowd.metrics`: discomfort is the share of steps with a "
             "pedestrian within 0.2 m of the robot's edge, personal space the share with none within 0.45 m. "
             "The scripted rows' settings: " + ", ".join(f"`{s}`" for s in sorted(settings) if s) + ".", "",
             "| navigator | seeds x episodes | " + " | ".join(h for _, h in METRICS) + " |",
             "|---|---|" + "---|" * len(METRICS)]
    for name in sorted(runs):
        group = runs[name]
        values = {"success": _mean(r["success_rate"] for r in group),
                  "collision": _mean(r["collision_rate"] for r in group),
                  "timeout": _mean(r["timeout_rate"] for r in group)}
        values.update({k: _mean(r[k] for r in group) for k, _ in METRICS[3:]})
        size = f"{len(group)} x {group[0]['test_episodes']}"
        lines.append(f"| `{name}` ({_learner(name)}) | {size} | " + " | ".join(_cell(k, values[k]) for k, _ in METRICS) + " |")
    for key in sorted(robots, key=lambda k: (-robots[k]["success"], k)):
        entry = robots[key]
        social = entry.get("social") or {}
        values = {k: entry.get(k, social.get(k)) for k, _ in METRICS}
        controller, task = key.split("/", 1)
        name = _controller_name(controller)
        if len(settings) > 1:
            name += f" {task.removeprefix(CROWD_TASK).strip()}"
        lines.append(f"| {name} | 1 x {entry.get('episodes', '-')} | "
                     + " | ".join(_cell(k, values[k]) for k, _ in METRICS) + " |")
    lines += ["", "CrowdNav's published success in the same geometry (5 humans crossing a circle of radius 4 m, the "
              "robot invisible to them; Chen et al. 2019, Table I, a holonomic robot): "
              + ", ".join(f"{name} {rate:.0%}" for name, rate in CROWDNAV) + "."]
    return lines
