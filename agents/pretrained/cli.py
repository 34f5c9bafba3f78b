"""``python -m agents.pretrained``: list the pretrained models, export a run as one, or train
and export a cell of the study.

    python -m agents.pretrained list [--markdown]
    python -m agents.pretrained export runs/pretrained/<run> --cell 5.3
    nice -n 19 python -m agents.pretrained train 5.3 [5.2 ...] | --missing
"""

from __future__ import annotations

import argparse
import sys

from agents.files import DiskFullError, megabytes
from agents.pretrained import card
from agents.pretrained.catalogue import CELLS, cheapest_first, source_of
from agents.training import pretrained_files as files

BUDGET_BYTES = 10_000_000
"""what all the models together may weigh (they live in the repository)"""


def total_size(root=None) -> int:
    """Bytes of every model in ``root`` (default: the repository's pretrained/)."""
    root = files.models_root() if root is None else root
    return sum(card.folder_size(root / name) for name in files.available(root))


def list_models(root=None) -> list[str]:
    """Lines of ``list``: per model its row, seed, test success and size; then the total against the
    budget and the cells still without a model."""
    root = files.models_root() if root is None else root
    names = files.available(root)
    lines = [f"{'model':<34} {'success':>7}  {'size':>7}  row (seed)"]
    for name in names:
        facts = card.read(root / name)
        lines.append(f"{'pretrained:' + name:<34} {facts['test']['success']:>7.0%}  "
                     f"{megabytes(card.folder_size(root / name)):>7}  {facts['row']} ({facts['seed']})")
    total = total_size(root)
    lines.append(f"{len(names)} model(s) in {root}: {total / 1e6:.2f} MB of the {BUDGET_BYTES / 1e6:.0f} MB budget"
                 + (" (over budget)" if total > BUDGET_BYTES else ""))
    missing = [c for c in cheapest_first() if c not in names]
    if missing:
        lines.append(f"cells without a model (cheapest first; `python -m agents.pretrained train --missing`): "
                     f"{', '.join(missing)}")
    return lines


def main(argv: list[str] | None = None) -> None:
    """The command line."""
    parser = argparse.ArgumentParser(prog="python -m agents.pretrained", description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    ls = sub.add_parser("list", help="the models with their test success and size")
    ls.add_argument("--markdown", action="store_true", help="the table of docs/pretrained.md instead")
    exp = sub.add_parser("export", help="export a finished run directory as a model (tests it, writes its card)")
    exp.add_argument("run_dir", metavar="RUN_DIR")
    exp.add_argument("--cell", required=True, help=f"the model's name; the study's cells: {', '.join(CELLS)}")
    exp.add_argument("--episodes", type=int, default=100, help="test episodes measured for the card (default 100)")
    tr = sub.add_parser("train", help="train a cell's run (its best row and seed), then export it")
    tr.add_argument("cells", nargs="*", metavar="CELL")
    tr.add_argument("--missing", action="store_true", help="every cell without a model, cheapest first")
    tr.add_argument("--runs-dir", default="runs/pretrained", help="where the runs go (default runs/pretrained)")
    tr.add_argument("--episodes", type=int, default=100, help="test episodes measured for the card (default 100)")
    tr.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    try:
        if args.command == "list":
            print(card.models_table() if args.markdown else "\n".join(list_models()))
        elif args.command == "export":
            from agents.pretrained.export import export

            export(args.run_dir, args.cell, episodes=args.episodes)
        else:
            from agents.pretrained.train import train_and_export

            present = set(files.available())
            cells = [c for c in cheapest_first() if c not in present] if args.missing else args.cells
            for cell in cells:
                source_of(cell)  # every name checked before any training
            if not cells:
                raise ValueError("name the cells to train (e.g. 5.3) or give --missing")
            for cell in cells:
                train_and_export(cell, args.runs_dir, args.episodes, progress=not args.no_progress)
    except (ValueError, DiskFullError) as err:
        raise SystemExit(f"error: {err}")


if __name__ == "__main__":
    main(sys.argv[1:])
