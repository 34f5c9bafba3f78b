"""The report's learning-curve figures, drawn from the run table's down-sampled training curves.

Each figure compares experiments of one of the study's figures (agents/study/numbers.py FIGURES):
per experiment, the mean over its seeds of each block's mean (BLOCK = 50 training episodes, see
agents/study/run_record.py), smoothed by a trailing mean over SMOOTH_EPISODES // BLOCK blocks, so a
point is the mean over seeds of the last 100 episodes' mean, plotted at the block's last episode.
Figures are written without a timestamp or version tag: the same table draws the same PNG bytes
with the same matplotlib.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from agents.files import save_figure
from agents.study.run_record import parse_curve
from agents.training.plots import moving_average

SMOOTH_EPISODES = 100
"""training episodes each plotted point averages"""
PANELS = (("loss", "Q-loss (mean per episode)"), ("return", "accumulated reward"))
"""the study's figures' panels: (curve, axis label)"""
SUCCESS_PANELS = (("success", "success (share of episodes)"), ("return", "accumulated reward"))
"""panels of figures whose members learn from different losses (a fit's and a Q-loss)"""


def block_size(rows: list[dict]) -> int:
    """The runs' common curve block (ValueError if the runs were stored with different blocks)."""
    blocks = {r["curve_block"] for r in rows}
    if len(blocks) != 1:
        raise ValueError(f"the runs were stored with different curve blocks {sorted(blocks)}; add them again "
                         "with one version of agents.study.table")
    return blocks.pop()


def mean_curve(rows: list[dict], key: str) -> np.ndarray:
    """Per block, the mean over the runs of ``curve_<key>`` (runs of different lengths: over those
    that got there; nan where none has a value)."""
    curves = [parse_curve(r[f"curve_{key}"]) for r in rows]
    curves = [c for c in curves if len(c)]
    if not curves:
        return np.array([])
    stack = np.full((len(curves), max(len(c) for c in curves)), np.nan)
    for i, c in enumerate(curves):
        stack[i, :len(c)] = c
    counts = np.sum(np.isfinite(stack), axis=0)
    sums = np.nansum(stack, axis=0)
    return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)


def caption(block: int) -> str:
    """What a figure's curves are, in words."""
    n = max(1, SMOOTH_EPISODES // block)
    return (f"mean over seeds of {block}-episode block means, trailing mean over {n} blocks "
            f"({n * block} episodes)")


def draw_figure(path: Path, title: str, members: list[tuple[str, list[dict]]], panels=PANELS) -> None:
    """Write one comparison figure: the ``panels``' curves (Q-loss and return) of each (label, runs) member."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    block = block_size([r for _, rows in members for r in rows])
    fig, axes = plt.subplots(1, 2, figsize=(8, 5), dpi=100)
    for (key, ylabel), ax in zip(panels, axes):
        for label, rows in members:
            curve = mean_curve(rows, key)
            if len(curve):
                x = np.minimum(np.arange(1, len(curve) + 1) * block, max(r["episodes_done"] for r in rows))
                ax.plot(x, moving_average(curve, max(1, SMOOTH_EPISODES // block)), linewidth=1.5,
                        label=f"{label} ({len(rows)} seed{'s' * (len(rows) != 1)})")
        ax.set_xlabel("episode")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        if key == "loss":
            ax.set_yscale("log")
    axes[1].legend(loc="lower right", fontsize=7)
    fig.suptitle(f"{title}\n{caption(block)}", fontsize=10)
    fig.tight_layout()
    try:
        save_figure(fig, path, metadata={"Software": None})
    finally:
        plt.close(fig)


def write_figures(groups: dict[str, list[dict]], figures: list[tuple[str, str, list[tuple[str, str]]]],
                  folder: Path, panels=PANELS) -> list[tuple[Path, str]]:
    """Draw each figure of which at least two experiments have runs, with ``panels``; return (path, title) of each."""
    written = []
    for stem, title, members in figures:
        present = [(label, groups[e]) for e, label in members if groups.get(e)]
        if len(present) >= 2:  # a comparison needs two curves
            folder.mkdir(parents=True, exist_ok=True)
            path = folder / f"{stem}.png"
            draw_figure(path, title, present, panels)
            written.append((path, title))
    return written
