"""Writing the test phase's results: eval.json, the eval.md table and trajectories.png (every
test path on the task's top-down picture, as in the thesis's Fig. 6.2)."""

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
    width = max(len(r[0]) for r in rows)
    lines = [f"| {'metric':<{width}} | value |", f"|{'-' * (width + 2)}|-------|"]
    lines += [f"| {name:<{width}} | {value} |" for name, value in rows]
    return "\n".join(lines) + "\n"


def draw_trajectories(env, records: list[dict], path: Path) -> None:
    """Every test trajectory on the task's top-down render, coloured by outcome."""
    from PIL import ImageDraw

    from dynnav_tasks.viz.pictures import annotated_top_down

    env.reset(seed=records[0]["seed"])
    img = annotated_top_down(env)
    draw = ImageDraw.Draw(img)
    px = env.unwrapped.top_down_pixel
    for r in records:
        pts = [px(x, y) for x, y in r["trajectory"]]
        color = OUTCOME_COLORS.get(r["outcome"], (128, 128, 128))
        if len(pts) > 1:
            draw.line(pts, fill=color, width=2)
        (c, w), (tc, tw) = pts[0], px(*r["target_start"])
        draw.ellipse([c - 3, w - 3, c + 3, w + 3], fill=(255, 255, 255))
        draw.ellipse([tc - 3, tw - 3, tc + 3, tw + 3], outline=(120, 0, 0))
    y = 6
    for name, color in OUTCOME_COLORS.items():
        n = sum(r["outcome"] == name for r in records)
        draw.rectangle([6, y + 2, 16, y + 10], fill=color)
        draw.text((22, y), f"{name} ({n})", fill=(255, 255, 255))
        y += 14
    save_figure(img, path)


def write_results(out_dir: Path, result: dict, heading: str) -> str:
    """eval.json (``result``) and eval.md (``heading`` and the table); returns the table."""
    table = markdown_table(result["task"], result["summary"])
    atomic_write_bytes(out_dir / "eval.json", json.dumps(result, indent=1).encode())
    atomic_write_bytes(out_dir / "eval.md", f"{heading}\n\n{table}".encode())
    return table
