"""The score card: a suite's scores as JSON and Markdown, beside the references.

Each cell's row shows, where dynnav measured them, the full-state planner's success (the ceiling:
``docs/results/ceilings.json`` for the study's worlds, ``procedural_ceilings.json`` for the
procedural cells) and the go-to-target floor's (``procedural_ceilings.json``); the card names the
dynnav version and the exact command that made it. Both files are written whole, to a temporary
file renamed into place.
"""

from __future__ import annotations

import json
from importlib import metadata
from pathlib import Path
from typing import Optional

from agents.benchmark.suites import Cell
from agents.files import atomic_write_bytes

RESULTS = Path(__file__).resolve().parents[2] / "docs" / "results"
SOCIAL = (("human_collision_rate", "human collision", "{:.0%}"), ("discomfort_frequency", "discomfort", "{:.3f}"),
          ("min_human_distance", "min. distance (m)", "{:.2f}"))


def version() -> str:
    """dynnav's installed version."""
    try:
        return metadata.version("dynnav")
    except metadata.PackageNotFoundError:
        return "unknown"


def _json(name: str) -> dict:
    path = RESULTS / name
    return json.loads(path.read_text()) if path.is_file() else {}


SCRIPTED = ("dwa", "orca_robot", "social_force_robot")
"""the classical controllers whose success a card shows beside the planner's and the floor's"""


def references(cell: Cell) -> dict:
    """The success in ``cell`` of the planner, the floor and the classical controllers, where
    measured (else None), each on its own drive: a cell's ``control_mode`` is the navigator's."""
    if cell.task == "DynNav-Procedural-v1" and {"difficulty", "split"} <= set(cell.options):
        cells = _json("procedural_ceilings.json")
        key = f"{cell.options['difficulty']}/{cell.options['split']}"
        get = lambda who: (cells.get(f"{who}/{key}") or {}).get("success")  # noqa: E731
        return dict(planner=get("state_planner"), go_to_target=get("go_to_target"), **{w: get(w) for w in SCRIPTED})
    name = cell.task_name  # each reference on its own drive
    scripted = _json("baselines.json")
    get = lambda who: (scripted.get(f"{who}/{name}") or {}).get("success")  # noqa: E731
    ceiling = _json("ceilings.json").get(name)
    planner = ceiling.get("success") if ceiling else get("state_planner")
    return dict(planner=planner, go_to_target=None, **{w: get(w) for w in SCRIPTED})


def make_card(policy: str, algo: Optional[str], suite: str, cells: list[Cell], scores: list[dict],
              command: str, name: Optional[str] = None) -> dict:
    """The score card as a JSON-ready dict; ``name``: the navigator's name on the leaderboard (default: the
    policy spec)."""
    return dict(dynnav_version=version(), command=command, name=name or policy, policy=policy, algo=algo, suite=suite,
                cells=[dict(task=c.task, options=c.options, name=c.name, first_seed=c.first_seed, **s,
                            references=references(c)) for c, s in zip(cells, scores)])


def _pct(v) -> str:
    return "-" if v is None else f"{v:.0%}"


def markdown(card: dict) -> str:
    """The card as a Markdown table, with its command and version."""
    social = any("social" in c for c in card["cells"])
    head = ["task", "episodes", "success (95% CI)", "collision", "timeout", "SPL", "planner", "go to target"]
    head += [h for _, h, _ in SOCIAL] if social else []
    lines = [f"# {card.get('name') or card['policy']} on {card['suite']}", "",
             f"`{card['command']}` (dynnav {card['dynnav_version']})", "",
             "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for c in card["cells"]:
        lo, hi = c["success_ci95"]
        row = [c["name"], str(c["episodes"]), f"{c['success']:.0%} ({lo:.0%}-{hi:.0%})", _pct(c["collision"]),
               _pct(c["timeout"]), f"{c['spl']:.2f}", _pct(c["references"]["planner"]),
               _pct(c["references"]["go_to_target"])]
        if social:
            s = c.get("social") or {}
            row += ["-" if s.get(k) is None else fmt.format(s[k]) for k, _, fmt in SOCIAL]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def write_card(card: dict, out: Path) -> tuple[Path, Path]:
    """``out`` (.json) and the Markdown beside it (.md)."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    md = out.with_suffix(".md")
    atomic_write_bytes(out, (json.dumps(card, indent=1) + "\n").encode())
    atomic_write_bytes(md, markdown(card).encode())
    return out, md
