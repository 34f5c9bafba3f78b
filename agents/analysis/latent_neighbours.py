"""Does the auto-encoder's latent tell an episode's last step apart? Nearest neighbours in the
test phase's latents, by how the episode ended.

    python -m agents.analysis.latent_neighbours RUN_DIR [RUN_DIR ...] [--k 10]

A camera run's test phase writes ``latents.npz`` (the latent from which each step's action was
chosen, in order) beside ``eval.json`` (its episodes in the same order, with their lengths and
outcomes). For every episode's last step, the one whose action reached the target or hit an
obstacle, this finds its ``k`` nearest latents (Euclidean) among the other episodes' steps and
counts how many of them are also last steps with the same outcome. Beside that share it prints
the share of all steps such last steps make up, the share a latent that tells them nothing
would give. A share far above it means the latent marks that moment (the target filling the
view); a share near it means the Q-network, which reads the latent, sees that step much as it
sees steps from which other episodes drove on.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

ENDINGS = ("success", "collision")


def load_run(run_dir: str | Path) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """(latents (n, d), each step's episode index (n,), each episode's outcome)."""
    run_dir = Path(run_dir)
    for name in ("latents.npz", "eval.json"):
        if not (run_dir / name).is_file():
            raise FileNotFoundError(f"{run_dir / name} not found: give camera runs whose test phase has run "
                                    "(python -m agents.dqn --eval --checkpoint RUN writes both files)")
    latents = np.load(run_dir / "latents.npz")["latents"].astype(np.float64)
    episodes = json.loads((run_dir / "eval.json").read_text())["episodes"]
    lengths = [int(e["steps"]) for e in episodes]
    if sum(lengths) != len(latents):
        raise ValueError(f"{run_dir}: latents.npz holds {len(latents)} steps but eval.json's episodes "
                         f"{sum(lengths)}: the two files come from different test phases; run the test again")
    episode_of_step = np.repeat(np.arange(len(lengths)), lengths)
    return latents, episode_of_step, [e["outcome"] for e in episodes]


def neighbour_shares(latents: np.ndarray, episode_of_step: np.ndarray, outcomes: list[str],
                     k: int = 10) -> dict[str, dict]:
    """Per ending: how many episodes end so, the share of all steps their last steps are, and the
    mean share of a last step's ``k`` nearest other-episode latents that are last steps of the same ending."""
    last = np.flatnonzero(np.r_[episode_of_step[1:] != episode_of_step[:-1], True])
    ending = np.full(len(latents), "", dtype=object)
    ending[last] = [outcomes[episode_of_step[i]] for i in last]
    result = {}
    for name in ENDINGS:
        queries = last[ending[last] == name]
        shares = []
        for i in queries:
            others = np.flatnonzero(episode_of_step != episode_of_step[i])
            if len(others) < k:
                raise ValueError(f"only {len(others)} steps in other episodes: give a run of more episodes or a smaller --k")
            dist = ((latents[others] - latents[i]) ** 2).sum(axis=1)
            nearest = others[np.argsort(dist, kind="stable")[:k]]
            shares.append(float(np.mean(ending[nearest] == name)))
        result[name] = dict(episodes=len(queries), base=len(queries) / len(latents),
                            neighbours=float(np.mean(shares)) if shares else float("nan"))
    return result


def label(run_dir: str | Path) -> str:
    """A sweep's run folder (``<experiment>/seed<N>/<run>``) as ``<experiment>/seed<N>``, any other as its name."""
    path = Path(run_dir).resolve()
    return f"{path.parent.parent.name}/{path.parent.name}" if path.parent.name.startswith("seed") else path.name


def render(rows: list[tuple[str, dict]], k: int) -> str:
    lines = [f"| run | ending | episodes | share of all steps | share of the {k} nearest |", "|---|---|---|---|---|"]
    for run, shares in rows:
        for name, s in shares.items():
            lines.append(f"| {run} | {name} | {s['episodes']} | {s['base']:.1%} | {s['neighbours']:.1%} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="camera run directories (holding latents.npz and eval.json)")
    parser.add_argument("--k", type=int, default=10, help="neighbours per last step (default 10)")
    args = parser.parse_args(argv)
    if args.k < 1:
        parser.error("--k must be at least 1")
    try:
        runs = [(label(d), load_run(d)) for d in args.runs]  # every run read before any is measured
        rows = [(name, neighbour_shares(*run, k=args.k)) for name, run in runs]
    except (FileNotFoundError, ValueError) as e:
        raise SystemExit(f"agents.analysis.latent_neighbours: {e}") from None
    print(render(rows, args.k))


if __name__ == "__main__":
    main()
