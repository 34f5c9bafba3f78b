"""Writing the test phase's results: eval.json, the eval.md table and trajectories.png.

trajectories.png shows every test path on the task's top-down picture, as in the thesis's
Fig. 6.2, when all test episodes play in one world (the study's tasks). A task whose world
changes from episode to episode (``DynNav-Procedural-v1``) gets a grid instead: the first
``GRID_EPISODES`` test episodes, each path on its own episode's world, under a legend that
counts the outcomes of all of them. Each episode's world is found by replaying its reset
(``env.reset(seed=...)``, then ``env.unwrapped.world``)."""

from __future__ import annotations

import json
from pathlib import Path

from agents.files import atomic_write_bytes, save_figure

OUTCOME_COLORS = {"success": (30, 90, 255), "collision": (230, 30, 30), "timeout": (255, 170, 0)}


def markdown_table(task: str, summary: dict) -> str:
    """The test phase's summary as a Markdown table (eval.md and the terminal)."""
    lo, hi = summary["success_ci95"]
    avg = summary["avg_steps_success"]
    rows = [
        ("task", task),
        (f"test episodes (epsilon {summary.get('epsilon', 0.0):g})", summary["episodes"]),
        ("success rate", f"{summary['success_rate']:.0%} (95% CI {lo:.0%}-{hi:.0%})"),
        ("collision rate", f"{summary['collision_rate']:.0%}"),
        ("timeout rate", f"{summary['timeout_rate']:.0%}"),
        ("ended otherwise (terminated)", f"{summary['terminated_rate']:.0%}"),
        ("average steps (successful episodes)", "-" if avg is None else f"{avg:.1f}"),
        ("average return", f"{summary['avg_return']:.2f}"),
    ]
    if not summary["terminated_rate"]:
        rows = [r for r in rows if not r[0].startswith("ended otherwise")]
    if "spl" in summary:
        rows.append(("SPL", f"{summary['spl']:.3f}"))
    rows += social_rows(summary.get("social"))
    width = max(len(r[0]) for r in rows)
    lines = [f"| {'metric':<{width}} | value |", f"|{'-' * (width + 2)}|-------|"]
    lines += [f"| {name:<{width}} | {value} |" for name, value in rows]
    return "\n".join(lines) + "\n"


SOCIAL_LABELS = {
    "human_collision_rate": ("human collision rate", "{:.0%}"),
    "min_human_distance": ("minimum distance to a human (m, mean)", "{:.2f}"),
    "personal_space_compliance": ("personal-space compliance (no human within 0.45 m)", "{:.3f}"),
    "discomfort_frequency": ("discomfort frequency (a human within 0.2 m)", "{:.3f}"),
    "time_to_goal": ("time to goal (s, successful episodes)", "{:.1f}"),
    "path_irregularity": ("path irregularity (rad/m)", "{:.3f}"),
    "jerk": ("jerk (m/s^3)", "{:.1f}"),
}
"""the social metrics' rows of the table: label and format (``dynnav_tasks.crowd.metrics`` defines them)"""


def social_rows(social: dict | None) -> list[tuple[str, str]]:
    """The table rows of a summary's social metrics (none without pedestrians; "-" for a metric
    no episode had, e.g. the time to goal without a success)."""
    if not social:
        return []
    return [(label, "-" if social.get(key) is None else fmt.format(social[key]))
            for key, (label, fmt) in SOCIAL_LABELS.items()]


GRID_EPISODES = 12
"""test episodes pictured (the first ones) when each plays in its own world"""
GRID_COLUMNS = 4
TILE_SIZE = 256
"""pixels a side of one episode's picture in the grid"""
HEADER_HEIGHT = 34
LABEL_BACKGROUND = (40, 40, 40)


def episode_worlds(env, records: list[dict]) -> list:
    """The ``World`` of each test episode in ``records``, replayed by resetting ``env`` with the
    episode's seed (the env is left after the last episode's reset)."""
    worlds = []
    for r in records:
        env.reset(seed=r["seed"])
        worlds.append(env.unwrapped.world)
    return worlds


def one_world(worlds: list) -> bool:
    """Whether every world in ``worlds`` is the same (worlds are frozen dataclasses)."""
    return all(w is worlds[0] or w == worlds[0] for w in worlds)


def draw_trajectories(env, records: list[dict], path: Path) -> None:
    """trajectories.png (see the module docstring): every test trajectory coloured by outcome,
    on the one world's top-down picture or, when the world changes per episode, on a grid of
    the first ``GRID_EPISODES`` episodes' pictures."""
    if not records:
        raise ValueError("no test episodes to draw: run one or more (--eval-episodes 1 or more)")
    if one_world(episode_worlds(env, records)):
        img = _one_world_picture(env, records)
    else:
        img = _episode_grid(env, records)
    save_figure(img, path)


def _one_world_picture(env, records: list[dict]):
    from PIL import ImageDraw

    from dynnav_tasks.viz.pictures import annotated_top_down

    env.reset(seed=records[0]["seed"])
    img = annotated_top_down(env)
    draw = ImageDraw.Draw(img)
    for r in records:
        _draw_path(draw, env.unwrapped.top_down_pixel, r, width=2)
    _legend(draw, records, 6, 6)
    return img


def _episode_grid(env, records: list[dict]):
    from PIL import Image, ImageDraw

    from dynnav_tasks.viz.pictures import annotated_top_down

    shown = records[:GRID_EPISODES]
    rows = -(-len(shown) // GRID_COLUMNS)
    columns = min(len(shown), GRID_COLUMNS)
    grid = Image.new("RGB", (columns * TILE_SIZE, HEADER_HEIGHT + rows * TILE_SIZE), LABEL_BACKGROUND)
    draw = ImageDraw.Draw(grid)
    _legend(draw, records, 6, 4, columns=3)
    draw.text((6, 20), f"first {len(shown)} of {len(records)} test episodes, each in its own world",
              fill=(255, 255, 255))
    for i, r in enumerate(shown):
        env.reset(seed=r["seed"])
        tile = annotated_top_down(env)
        _draw_path(ImageDraw.Draw(tile), env.unwrapped.top_down_pixel, r, width=4)
        tile = tile.resize((TILE_SIZE, TILE_SIZE), Image.BOX)
        label = ImageDraw.Draw(tile)
        text = f"seed {r['seed']}: {r['outcome']}"
        label.rectangle([0, 0, 8 + 6 * len(text), 14], fill=LABEL_BACKGROUND)
        label.text((4, 2), text, fill=OUTCOME_COLORS.get(r["outcome"], (255, 255, 255)))
        grid.paste(tile, ((i % GRID_COLUMNS) * TILE_SIZE, HEADER_HEIGHT + (i // GRID_COLUMNS) * TILE_SIZE))
    return grid


def _draw_path(draw, px, record: dict, width: int) -> None:
    """One episode's path (coloured by outcome), its start (white) and the target's start (dark red)."""
    pts = [px(x, y) for x, y in record["trajectory"]]
    color = OUTCOME_COLORS.get(record["outcome"], (128, 128, 128))
    if len(pts) > 1:
        draw.line(pts, fill=color, width=width)
    (c, w), (tc, tw), r = pts[0], px(*record["target_start"]), width + 1
    draw.ellipse([c - r, w - r, c + r, w + r], fill=(255, 255, 255))
    draw.ellipse([tc - r, tw - r, tc + r, tw + r], outline=(120, 0, 0), width=max(1, width // 2))


def _legend(draw, records: list[dict], x: int, y: int, columns: int = 1) -> None:
    """Each outcome's colour and count over ``records``, in ``columns`` columns from (x, y)."""
    for i, (name, color) in enumerate(OUTCOME_COLORS.items()):
        n = sum(r["outcome"] == name for r in records)
        cx, cy = x + (i % columns) * 120, y + (i // columns) * 14
        draw.rectangle([cx, cy + 2, cx + 10, cy + 10], fill=color)
        draw.text((cx + 16, cy), f"{name} ({n})", fill=(255, 255, 255))


def write_results(out_dir: Path, result: dict, heading: str) -> str:
    """eval.json (``result``) and eval.md (``heading`` and the table); returns the table."""
    table = markdown_table(result["task"], result["summary"])
    atomic_write_bytes(out_dir / "eval.json", json.dumps(result, indent=1).encode())
    atomic_write_bytes(out_dir / "eval.md", f"{heading}\n\n{table}".encode())
    return table
