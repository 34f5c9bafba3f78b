"""docs/leaderboard.md from the committed score cards (``results/scorecards/*.json``).

    python -m agents.benchmark.leaderboard [--cards results/scorecards] [--out docs/leaderboard.md]

One table per suite (or single task): a row per score card (named by its ``--name``, else its
policy spec), a column per cell, each the card's success rate; above them the references the cards carry (the full-state planner, the
go-to-target floor). Cards are small JSON files that ``dynnav-benchmark --out`` writes; run
folders are never read. The same cards give the same page byte for byte.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from agents.benchmark.suites import DRIVE, Cell
from agents.files import atomic_write_bytes

ROOT = Path(__file__).resolve().parents[2]
CARDS = ROOT / "results" / "scorecards"
PAGE = ROOT / "docs" / "leaderboard.md"
REFERENCES = (("planner", "full-state planner (the ceiling)"), ("go_to_target", "go to target (the floor)"),
              ("dwa", "DWA on the laser scan (continuous drive)"), ("orca_robot", "ORCA robot (continuous drive)"),
              ("social_force_robot", "social-force robot (continuous drive)"))


def read_cards(folder: Path) -> list[dict]:
    """Every score card in ``folder``, by file name; ValueError naming a file that is not one."""
    cards = []
    for path in sorted(Path(folder).glob("*.json")):
        try:
            card = json.loads(path.read_text())
            card["cells"][0]["success"]
        except (ValueError, KeyError, IndexError, TypeError) as err:
            raise ValueError(f"{path} is not a score card of dynnav-benchmark ({err})") from err
        card["file"] = path.stem
        cards.append(card)
    return cards


def _pct(v) -> str:
    return "-" if v is None else f"{v:.0%}"


def _label(name: str) -> str:
    name = name.removeprefix("DynNav-Procedural-v1 ").removeprefix("DynNav-")
    return name[1:-1] if name.startswith("[") else name


def _column(cell: dict) -> str:
    """A card cell's column (``Cell.task_name``: navigators on either drive share it)."""
    return Cell(cell["task"], cell.get("options", {})).task_name


def _drive(card: dict) -> str:
    """`` (continuous drive)`` for a card played on the velocity drive, else nothing."""
    modes = {c.get("options", {}).get(DRIVE) for c in card["cells"]}
    return " (continuous drive)" if "diff_drive_vel" in modes else ""


def render(cards: list[dict]) -> str:
    """The page's Markdown."""
    lines = ["# Leaderboard", "",
             "Success rates of navigators scored by `dynnav-benchmark` (docs/benchmark.md) on fixed suites: the "
             "same tasks, seeds and episode counts for every row. Each row is a score card in `results/scorecards/` "
             "(its JSON and Markdown hold every rate's 95% interval, SPL, the social metrics and the exact command); "
             "`python -m agents.benchmark.leaderboard` makes this page from them. The rows above the cards' are the "
             "references the cards carry, measured by each controller's own command on its own episodes "
             "(`docs/results/`); a `controller:NAME` row is a scripted controller scored by the benchmark on the "
             "suite's seeds.", ""]
    suites: dict[str, list[dict]] = {}
    for card in cards:
        suites.setdefault(card["suite"], []).append(card)
    if not suites:
        lines.append("No score cards yet.")
    for suite in sorted(suites):
        group = suites[suite]
        names = [_column(c) for c in group[0]["cells"]]
        episodes = group[0]["cells"][0]["episodes"]
        lines += [f"## {suite}", "", f"{len(names)} cell(s), {episodes} episodes each (success rate).", "",
                  "| navigator | " + " | ".join(_label(n) for n in names) + " |", "|---|" + "---|" * len(names)]
        for key, label in REFERENCES:
            values = [next((c["references"].get(key) for card in group for c in card["cells"]
                            if _column(c) == n and c["references"].get(key) is not None), None) for n in names]
            if any(v is not None for v in values):
                lines.append(f"| {label} | " + " | ".join(_pct(v) for v in values) + " |")
        for card in sorted(group, key=lambda c: -sum(x["success"] for x in c["cells"])):
            rates = {_column(c): c["success"] for c in card["cells"]}
            algo = f" ({card['algo']})" if card.get("algo") else ""
            who = card["name"] if card.get("name", card["policy"]) != card["policy"] else f"`{card['policy']}`"
            lines.append(f"| {who}{algo}{_drive(card)} | " + " | ".join(_pct(rates.get(n)) for n in names) + " |")
        lines.append("")
    return "\n".join(lines).rstrip("\n") + "\n"


def main(argv: list[str] | None = None) -> None:
    """Write the page."""
    parser = argparse.ArgumentParser(prog="python -m agents.benchmark.leaderboard", description=main.__doc__)
    parser.add_argument("--cards", default=str(CARDS), help="folder of score cards (default results/scorecards)")
    parser.add_argument("--out", default=str(PAGE), help="the page (default docs/leaderboard.md)")
    args = parser.parse_args(argv)
    try:
        text = render(read_cards(Path(args.cards)))
    except ValueError as err:
        raise SystemExit(f"error: {err}")
    atomic_write_bytes(Path(args.out), text.encode())
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
