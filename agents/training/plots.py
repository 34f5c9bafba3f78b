"""Learning-curve pictures from a run's metrics CSV: reward and Q-loss per episode with their
moving average, as in the thesis's training figures."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from agents.files import save_figure


def moving_average(values: np.ndarray, window: int) -> np.ndarray:
    """Mean of the last ``window`` finite values at each index (fewer at the start)."""
    values = np.asarray(values, dtype=float)
    ok = np.isfinite(values)
    sums = np.cumsum(np.where(ok, values, 0.0))
    counts = np.cumsum(ok)
    lag_sums = np.concatenate([np.zeros(window), sums[:-window]]) if len(values) > window else np.zeros(len(values))
    lag_counts = np.concatenate([np.zeros(window), counts[:-window]]) if len(values) > window else np.zeros(len(values))
    n = counts - lag_counts
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 0, (sums - lag_sums) / np.maximum(n, 1), np.nan)


def read_metrics(path: str | Path) -> dict[str, np.ndarray]:
    """metrics.csv as one float array per column (empty cells are NaN)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return {}
    return {k: np.array([float(r[k]) if r[k] != "" else np.nan for r in rows]) for k in rows[0]}


def _curve(ax, episodes, values, window, label, color):
    ax.plot(episodes, values, color=color, alpha=0.25, linewidth=0.8, label=label)
    ax.plot(episodes, moving_average(values, window), color=color, linewidth=2,
            label=f"moving average ({window} episodes)")
    ax.set_xlabel("episode")
    ax.grid(alpha=0.3)
    ax.legend(loc="best")


def plot_learning_curves(metrics_csv: str | Path, out_dir: str | Path, title: str = "", window: int = 100) -> list[Path]:
    """Write reward.png and loss.png next to the CSV (or into ``out_dir``); return their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = read_metrics(metrics_csv)
    if not m:
        return []
    out_dir = Path(out_dir)
    written = []
    for key, ylabel, name, color in (("return", "accumulated reward", "reward.png", "tab:blue"),
                                     ("loss", "Q-loss (mean per episode)", "loss.png", "tab:red")):
        fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
        _curve(ax, m["episode"] + 1, m[key], window, key, color)
        ax.set_ylabel(ylabel)
        if key == "loss" and np.nanmax(np.where(np.isfinite(m[key]), m[key], np.nan), initial=0) > 0:
            ax.set_yscale("log")
        ax.set_title(f"{title}: {ylabel}" if title else ylabel)
        fig.tight_layout()
        path = out_dir / name
        save_figure(fig, path)
        plt.close(fig)
        written.append(path)
    return written
