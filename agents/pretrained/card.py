"""A pretrained model's card: ``card.md`` in its folder, a YAML block of facts between ``---``
lines (what ``list``, the tests and the docs read) followed by the same facts for a reader.

The facts: the cell, the row and seed it was trained as, the task, the training episodes, the
test of the exported model (episodes, first seed, success, collision and timeout rates, and the
success of its first ``CHECK_EPISODES`` episodes, the ones the test suite replays), the run
table's success of the original run, and the commands that reproduce it.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from agents.files import atomic_write_bytes, megabytes
from agents.pretrained.catalogue import CELLS
from agents.training import pretrained_files as files

CHECK_EPISODES = 20
"""test episodes the test suite replays per model (the first ones of the card's test)"""


def render(facts: dict) -> str:
    """The text of a card with ``facts``."""
    t = facts["test"]
    front = yaml.safe_dump(facts, sort_keys=False, width=1000).strip()
    reproduce_in_one_go = (f", or train and export in one go with `python -m agents.pretrained train {facts['cell']}`"
                           if facts.get("table_success") is not None else "")
    rate = lambda x: "-" if x is None else f"{x:.0%}"  # noqa: E731
    checked = min(CHECK_EPISODES, t["episodes"])
    return f"""---
{front}
---

# Pretrained navigator `{facts['cell']}`

The Q-network{" and the auto-encoder's encoder" if facts.get('autoencoder') else ''} of `{facts['row']}` \
seed {facts['seed']}, on `{facts['task']}`, after \
{facts['trained_episodes']} training episodes. Its resolved config is `config.yaml` beside this card.

| test of this model | |
|---|---|
| episodes (seeds {t['seed']} on) | {t['episodes']} |
| success | {rate(t['success'])} |
| collision | {rate(t['collision'])} |
| timeout | {rate(t['timeout'])} |
| success of the first {checked} (replayed by tests/test_pretrained.py) | {rate(t['success_first_check'])} |
| the run table's success of the original run | {rate(facts['table_success'])} |

{_per_test(facts)}Use it: `python -m agents.dqn --eval --checkpoint pretrained:{facts['cell']}`, or in Python
`agents.pretrained.load("{facts['cell']}")` (docs/pretrained.md).

Reproduce it: `{facts['reproduce']}`{reproduce_in_one_go}.
"""


def _per_test(facts: dict) -> str:
    """A procedural model's test per difficulty (its ``tests``), as a table; nothing for another model."""
    tests = facts.get("tests")
    if not tests:
        return ""
    lines = ["The test above is the mean of its tests in each difficulty's held-out test worlds:", "",
             "| tested on | episodes | success | collision | timeout | success of the first "
             f"{CHECK_EPISODES} (replayed by tests/test_pretrained.py) |", "|---|---|---|---|---|---|"]
    for options, t in tests.items():
        lines.append(f"| `{options}` | {t['episodes']} | {t['success']:.0%} | {t['collision']:.0%} | "
                     f"{t['timeout']:.0%} | {t['success_first_check']:.0%} |")
    return "\n".join(lines) + "\n\n"


def write(folder: str | Path, facts: dict) -> None:
    """Write ``facts`` as the card of the model in ``folder``, atomically."""
    atomic_write_bytes(Path(folder) / files.CARD, render(facts).encode())


def read(folder: str | Path) -> dict:
    """The facts of the card in ``folder``; ValueError naming the file if it is missing or malformed."""
    path = Path(folder) / files.CARD
    try:
        text = path.read_text(encoding="utf-8")
        _, front, _ = text.split("---\n", 2)
        facts = yaml.safe_load(front)
    except (OSError, ValueError, yaml.YAMLError) as err:
        raise ValueError(f"{path} is missing or is not a model card (a YAML block between '---' lines): {err}") from err
    if not isinstance(facts, dict) or not isinstance(facts.get("test"), dict) or "success" not in facts["test"]:
        raise ValueError(f"{path}: its YAML block lacks test: success: (write it again with "
                         f"`python -m agents.pretrained export`)")
    return facts


def folder_size(folder: str | Path) -> int:
    """Bytes of the files in ``folder`` (a model's)."""
    return sum(p.stat().st_size for p in Path(folder).iterdir() if p.is_file())


def models_table(root: str | Path | None = None) -> str:
    """The Markdown table of the models in ``root`` (default: the repository's): cell, row, seed,
    test success, size; what docs/pretrained.md shows."""
    root = Path(root) if root is not None else files.models_root()
    lines = ["| model | row (configs/) | seed | test success | episodes | size |", "|---|---|---|---|---|---|"]
    for name in files.available(root):
        facts = read(root / name)
        t = facts["test"]
        row = f"{CELLS[name].folder}/{facts['row']}" if name in CELLS else facts["row"]
        lines.append(f"| `pretrained:{name}` | `{row}` | {facts['seed']} | {t['success']:.0%} | "
                     f"{t['episodes']} | {megabytes(folder_size(root / name))} |")
    return "\n".join(lines)
